"""Evaluation: the models and the claims held against the simulations. Fits to the simulated steady
state and predictions (model_vs_simulation), the held-out benchmarks of the fabric models and the
stress relations and every model on every protocol (model_benchmark, stress_benchmark,
protocol_benchmark), the stress relation against the simulated stress (stress_model), the paper's
claims decided per seed and its steady-state claims (claims, verdicts), the comparison of datasets
and the map over state points (dataset_comparison, state_map).

Imports io, analysis, simulation, models and study; reporting (figures and pages) reads what it
computes.
"""

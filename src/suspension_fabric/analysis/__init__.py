"""Analysis: frames and tensor storage, near-contact detection and fabric tensors, the stress per
frame, per-run and seed-aggregated tables (along protocols too), steady states, and the statistics
over seeds.

Imports only [`suspension_fabric.io`][suspension_fabric.io].
"""

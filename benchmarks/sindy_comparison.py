"""The project's sparse regression against PySINDy's on the same problem: the reference's weak-form
design (model_discovery.weak_form_system, every seed and angle, terms of order <= 2) with the steady
state held (model_discovery.steady_constraint).

- sequential thresholding: the project's stlsq against pysindy.STLSQ (normalize_columns, no ridge) at
  the same thresholds, mapped to PySINDy's absolute threshold on unit-rms columns; are the supports
  the same?
- constrained fit: the project's bordered least squares on each support against
  pysindy.ConstrainedSR3 (l0, equality constraints) over a grid of its weight: per support size,
  the weak-form residual |A c - y| / |y| and the constraint's violation |C c - d|.

A study that decided something once: run once, conclusion in docs/fabric_models.md.
    PYTHONPATH=<site with pysindy 2.1 and cvxpy> .venv/bin/python benchmarks/sindy_comparison.py results/reference
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.evaluation.model_discovery import (
    THRESHOLDS,
    _training_system,
    candidate_supports,
    constrained_least_squares,
    run_curves,
    stlsq,
)
from suspension_fabric.models.sparse_fabric import LIBRARY


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", type=Path, help="a finished study's results folder (results/reference)")
    args = parser.parse_args()
    import pysindy
    from pysindy.optimizers import STLSQ, ConstrainedSR3

    tables = args.results / "tables"
    startup = run_curves(pd.read_csv(tables / "startup_runs.csv"))
    rotation = run_curves(pd.read_csv(tables / "rotation_runs.csv"))
    seeds = {seed for seed, _ in startup}
    thetas = np.array(sorted({theta for _, theta in rotation}))
    names = list(LIBRARY)
    A, y, (C, d, _) = _training_system(startup, rotation, seeds, thetas, names, (2.0, 5.0), {})
    scale = np.sqrt(np.mean(A**2, axis=0))
    unit = A / scale
    print(f"pysindy {pysindy.__version__}; design {A.shape[0]} rows x {A.shape[1]} terms, {len(seeds)} seeds")

    full = np.abs(np.linalg.lstsq(unit, y, rcond=None)[0])
    same, rows = 0, []
    for threshold in THRESHOLDS:
        ours = stlsq(A, y, threshold)
        theirs = STLSQ(threshold=threshold * full.max(), alpha=0.0, max_iter=50, normalize_columns=False)
        theirs.fit(unit, y)
        found = np.abs(theirs.coef_.ravel()) > 0
        same += np.array_equal(ours, found)
        rows.append((threshold, int(ours.sum()), int(found.sum()), np.array_equal(ours, found)))
    print(f"STLSQ: same support at {same} of {len(THRESHOLDS)} thresholds")
    print(pd.DataFrame(rows, columns=["threshold", "project_terms", "pysindy_terms", "same"]).to_string(index=False))

    def quality(coefficients):
        return np.linalg.norm(A @ coefficients - y) / np.linalg.norm(y), np.linalg.norm(C @ coefficients - d)

    project = {}
    start = time.perf_counter()
    for support in candidate_supports(A, y):
        project[int(support.sum())] = quality(constrained_least_squares(A, y, support, (C, d)))
    project_time = time.perf_counter() - start
    sr3, start = {}, time.perf_counter()
    for weight in np.geomspace(1e-6, 1e-1, 16):
        optimizer = ConstrainedSR3(
            reg_weight_lam=weight,
            regularizer="l0",
            constraint_lhs=C / scale,
            constraint_rhs=d,
            equality_constraints=True,
            max_iter=200,
            unbias=False,
        )
        optimizer.fit(unit, y)
        coefficients = optimizer.coef_.ravel() / scale
        size = int(np.count_nonzero(coefficients))
        if size and size not in sr3:
            sr3[size] = quality(coefficients)
    sr3_time = time.perf_counter() - start
    table = pd.DataFrame(
        [
            {
                "terms": k,
                "project_residual": project.get(k, (np.nan, np.nan))[0],
                "project_violation": project.get(k, (np.nan, np.nan))[1],
                "sr3_residual": sr3.get(k, (np.nan, np.nan))[0],
                "sr3_violation": sr3.get(k, (np.nan, np.nan))[1],
            }
            for k in sorted(set(project) | set(sr3), reverse=True)
        ]
    )
    print(f"constrained fits: project {project_time:.2f} s for {len(project)} supports, "
          f"ConstrainedSR3 {sr3_time:.2f} s for 16 weights")  # fmt: skip
    print(table.to_string(index=False, float_format=lambda x: f"{x:.3g}"))


if __name__ == "__main__":
    main()

"""The global fit's finite-difference step for models integrated numerically: with the default step
(~1e-8 relative) the ODE solver's noise (rtol 1e-10) enters the Jacobian at ~1%, and the fitted
parameter moves with round-off; with model_benchmark.NUMERICAL_DIFF_STEP it does not. For each
model that is not affine, the global fit on the reference study's tables with the default step and
with the project's, each twice: once as shipped and once with the right-hand side's round-off
changed (the hybrid closure formed and contracted by einsum instead of in closed form; the sparse
model's right-hand side scaled by 1 + 1e-14, a few units in its last place).

    .venv/bin/python benchmarks/global_fit_step.py results/reference
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import model_benchmark
from suspension_fabric.models import closures, fabric_models
from suspension_fabric.models.fits_file import read_fits


def perturbed(model):
    """The model with the same right-hand side up to round-off."""
    if model.key == "gw_hybrid":

        def rhs(fabric, flow, params, phi):
            formed = np.einsum(
                "...kl,...ijkl->...ij", 2.0 * flow.e_hat + params["beta"] * flow.e_ext, closures.hybrid_closure(fabric)
            )
            exact = model.rhs(fabric, flow, params, phi)
            return exact - formed + formed  # round-off of the formed contraction added to the closed form

    else:

        def rhs(fabric, flow, params, phi):
            return model.rhs(fabric, flow, params, phi) * (1.0 + 1e-14)  # a few units in the last place

    return dataclasses.replace(model, rhs=rhs)


def main(results: Path) -> None:
    fits = read_fits(results / "fits.json")
    curves = model_benchmark.seed_curves(
        tables.read_fabric_table(results / "tables/startup_runs.csv"),
        tables.read_fabric_table(results / "tables/rotation_runs.csv"),
        2.0,
        fits["steady_window"],
    )
    models = fabric_models.resolve_models(["gw_hybrid", "data/models/sparse_reference.json"])
    shipped = model_benchmark.NUMERICAL_DIFF_STEP
    print("model | step | parameters as shipped | with round-off changed | relative change | seconds")
    for key, model in models.items():
        start = fits["models"][key]["parameters"]
        for step in (None, shipped):
            model_benchmark.NUMERICAL_DIFF_STEP = step
            values, seconds = [], 0.0
            for variant in (model, perturbed(model)):
                begin = time.perf_counter()
                values.append(model_benchmark.fit_global(variant, curves, fits["phi"], 5.0, start)["parameters"])
                seconds += time.perf_counter() - begin
            name = model.names[0]
            change = abs(values[1][name] / values[0][name] - 1.0)
            print(
                f"{key} | {step or 'default'} | {values[0][name]:.6g} | {values[1][name]:.6g} | {change:.1e} | "
                f"{seconds / 2:.1f}"
            )
    model_benchmark.NUMERICAL_DIFF_STEP = shipped


if __name__ == "__main__":
    main(Path(sys.argv[1]))

"""Model side of the study on synthetic 'simulations' drawn from a known model.

Per-run tables are generated from the modified model with known (beta, A) plus
independent noise per seed, then pushed through the real aggregation, steady-state,
fit, prediction, error and figure code. The fits must recover the parameters and the
error table must rank the generating model first.
"""

import json

import numpy as np
import pandas as pd
import pytest

from suspension_fabric import figures, model, study, tables
from suspension_fabric.fabric import COMPONENTS

BETA, A, PHI = 9.4, 42.4, 0.45
STARTUP = np.linspace(0.0, 20.0, 201)  # long enough that the window below is steady (slowest rate 0.64)
ROTATION = np.linspace(0.0, 3.0, 31)
THETAS = [0.0, 45.0, 90.0, 135.0, 180.0]
NOISE = 0.002


def run_table(seed, theta, strains, tensors):
    frame = pd.DataFrame({"seed": seed, "theta": theta, "N": 500, "phi": PHI,
                          "step": np.round(strains * 1e5).astype(int), "strain": strains})
    for name, (i, j) in COMPONENTS.items():
        frame[name] = tensors[:, i, j]
    frame["Z"] = 2 * np.trace(tensors, axis1=-2, axis2=-1)
    return frame


@pytest.fixture(scope="module")
def synthetic():
    rng = np.random.default_rng(7)
    fabric0 = 0.03 * np.eye(3)
    startup, rotation = [], []
    for seed in range(4):
        noisy = model.startup_shear(STARTUP, BETA, A, PHI, fabric0) + NOISE * rng.normal(size=(len(STARTUP), 3, 3))
        startup.append(run_table(seed, 0.0, STARTUP, 0.5 * (noisy + np.swapaxes(noisy, -1, -2))))
        rotated = model.shear_rotation(np.radians(THETAS), ROTATION, BETA, A, PHI, STARTUP[-1], fabric0)
        for theta, tensors in zip(THETAS, rotated):
            noisy = tensors + NOISE * rng.normal(size=tensors.shape)
            rotation.append(run_table(seed, theta, ROTATION, 0.5 * (noisy + np.swapaxes(noisy, -1, -2))))
    startup, rotation = pd.concat(startup), pd.concat(rotation)
    steady = tables.steady_state(startup, 10.0, 20.0)
    fits = study.fit_steady_state(steady, PHI)
    startup_agg, rotation_agg = tables.aggregate_seeds(startup), tables.aggregate_seeds(rotation)
    predictions = study.predict(fits, study.initial_fabric(startup_agg), STARTUP, STARTUP[-1], THETAS, ROTATION,
                                extra_thetas_deg=np.arange(0, 181, 15))
    return fits, startup_agg, rotation_agg, predictions


def test_fits_recover_generating_parameters(synthetic):
    """Modified fit returns (beta, A) within 4 propagated standard errors; G-W fits <nn>_12 exactly."""
    fits = synthetic[0]
    mod = fits["modified"]
    assert abs(mod["beta"] - BETA) < 4 * mod["beta_err"] + 1e-3
    assert abs(mod["A"] - A) < 4 * mod["A_err"] + 1e-2
    gw_n12 = fits["model_steady_state"]["gw"]["n12"]
    assert gw_n12 == pytest.approx(fits["targets"]["n12"]["mean"], rel=1e-8)


def test_error_table_ranks_generating_model_first(synthetic):
    """rms (model - sim)/|n12_ss|: modified is at noise level and G-W worse, per theta, for 12 and 23."""
    fits, _, rotation_agg, predictions = synthetic
    errors = study.model_errors(rotation_agg, predictions, fits["targets"]["n12"]["mean"], "rotation")
    pivot = errors[errors["component"].isin(["n12", "n23"])].pivot_table(
        index="theta", columns="model", values="rms_error", aggfunc="mean")
    assert (pivot["modified"] < 0.1).all()
    assert pivot.loc[[45.0, 90.0, 135.0], "gw"].gt(2 * pivot.loc[[45.0, 90.0, 135.0], "modified"]).all()


def test_error_table_rejects_mismatched_grids(synthetic):
    fits, _, rotation_agg, predictions = synthetic
    shifted = predictions.assign(strain=predictions["strain"] + 0.01)
    with pytest.raises(ValueError, match="strain grid"):
        study.model_errors(rotation_agg, shifted, fits["targets"]["n12"]["mean"], "rotation")


def test_fits_json_round_trip(synthetic, tmp_path):
    fits = synthetic[0]
    path = study.write_fits(fits, tmp_path / "fits.json")
    assert study.read_fits(path)["modified"]["A"] == pytest.approx(fits["modified"]["A"])
    json.loads(path.read_text())  # strict JSON
    (tmp_path / "bad.json").write_text("{}")
    with pytest.raises(ValueError, match="missing key 'phi'"):
        study.read_fits(tmp_path / "bad.json")


def test_mirror_uses_parity():
    """theta -> -theta copies: 12 even, 23 odd; 180 copied to -180; 0 not duplicated."""
    table = pd.DataFrame({"theta": [0.0, 90.0, 180.0], "strain": 0.0, "n12": [1.0, 2.0, 3.0], "n23": [0.0, 5.0, 0.0]})
    mirrored, done = figures.mirror_negative_angles(table, ["n12", "n23"])
    assert done and sorted(mirrored["theta"]) == [-180.0, -90.0, 0.0, 90.0, 180.0]
    row = mirrored[mirrored["theta"] == -90.0].iloc[0]
    assert row["n12"] == 2.0 and row["n23"] == -5.0


def test_figures_are_written(synthetic, tmp_path):
    fits, startup_agg, rotation_agg, predictions = synthetic
    paths = figures.save_figure(figures.figure_startup(startup_agg, predictions, fits), tmp_path / "fig1")
    paths += figures.save_figure(figures.figure_rotation(rotation_agg, predictions, fits), tmp_path / "fig2")
    for path in paths:
        assert path.stat().st_size > 10_000

"""Models versus simulation (suspension_fabric.evaluation.model_vs_simulation) on synthetic 'simulations'
drawn from a known model.

Per-run tables are generated from the modified model with known (beta, A) plus
independent noise per seed, then pushed through the real aggregation, steady-state,
fit, prediction, error and figure code. The fits must recover the parameters and the
error table must rank the generating model first.
"""

import json

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis import tables
from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.evaluation import model_vs_simulation
from suspension_fabric.models import gillissen_wilson as model
from suspension_fabric.models.fabric_models import GW, MODIFIED
from suspension_fabric.models.fits_file import read_fits, write_fits
from suspension_fabric.reporting import figures

PAPER_MODELS = {"gw": GW, "modified": MODIFIED}

BETA, A, PHI = 9.4, 42.4, 0.45
STARTUP = np.linspace(0.0, 20.0, 201)  # long enough that the window below is steady (slowest rate 0.64)
ROTATION = np.linspace(0.0, 3.0, 31)
THETAS = [0.0, 45.0, 90.0, 135.0, 180.0]
NOISE = 0.002


def run_table(seed, theta, strains, tensors):
    frame = pd.DataFrame(
        {
            "seed": seed,
            "theta": theta,
            "N": 500,
            "phi": PHI,
            "step": np.round(strains * 1e5).astype(int),
            "strain": strains,
        }
    )
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
    fits = model_vs_simulation.fit_steady_state(steady, PHI, startup, 10.0, 20.0, PAPER_MODELS)
    startup_agg, rotation_agg = tables.aggregate_seeds(startup), tables.aggregate_seeds(rotation)
    predictions = model_vs_simulation.predict(
        fits,
        PAPER_MODELS,
        model_vs_simulation.initial_fabric(startup_agg),
        STARTUP,
        STARTUP[-1],
        THETAS,
        ROTATION,
        extra_thetas_deg=np.arange(0, 181, 15),
    )
    return fits, startup_agg, rotation_agg, predictions


def test_fits_recover_generating_parameters(synthetic):
    """Modified fit returns (beta, A) within 4 jackknife standard errors (over the 4 seeds); G-W fits
    <nn>_12 exactly."""
    fits = synthetic[0]
    mod = fits["models"]["modified"]
    assert abs(mod["parameters"]["beta"] - BETA) < 4 * mod["errors"]["beta"] + 1e-3
    assert abs(mod["parameters"]["A"] - A) < 4 * mod["errors"]["A"] + 1e-2
    gw_n12 = fits["models"]["gw"]["steady_state"]["n12"]
    assert gw_n12 == pytest.approx(fits["targets"]["n12"]["mean"], rel=1e-8)


def test_error_table_ranks_generating_model_first(synthetic):
    """rms (model - sim)/|n12_ss|: modified is at noise level and G-W worse, per theta, for 12 and 23."""
    fits, _, rotation_agg, predictions = synthetic
    errors = model_vs_simulation.model_errors(rotation_agg, predictions, fits["targets"]["n12"]["mean"], "rotation")
    pivot = errors[errors["component"].isin(["n12", "n23"])].pivot_table(
        index="theta", columns="model", values="rms_error", aggfunc="mean"
    )
    assert (pivot["modified"] < 0.1).all()
    assert pivot.loc[[45.0, 90.0, 135.0], "gw"].gt(2 * pivot.loc[[45.0, 90.0, 135.0], "modified"]).all()


def test_error_table_rejects_mismatched_grids(synthetic):
    fits, _, rotation_agg, predictions = synthetic
    shifted = predictions.assign(strain=predictions["strain"] + 0.01)
    with pytest.raises(ValueError, match="strain grid"):
        model_vs_simulation.model_errors(rotation_agg, shifted, fits["targets"]["n12"]["mean"], "rotation")


def aggregate(thetas, strains_of):
    """A minimal seed aggregate: rows (theta, strain) with strains_of(theta), shuffled."""
    frame = pd.concat([pd.DataFrame({"theta": float(theta), "strain": strains_of(theta)}) for theta in thetas])
    return frame.sample(frac=1.0, random_state=1)


def test_prediction_grids_are_the_simulated_strains_and_angles_plus_a_polar_grid():
    startup = aggregate([0.0], lambda theta: [0.0, 0.5, 0.25, 1.0])
    rotation = aggregate([90.0, 0.0, 30.0], lambda theta: [0.0, 0.1, 0.2])
    grids = model_vs_simulation.prediction_grids(startup, rotation, 45.0)
    np.testing.assert_array_equal(grids.startup_strains, [0.0, 0.25, 0.5, 1.0])
    np.testing.assert_array_equal(grids.thetas_deg, [0.0, 30.0, 90.0])
    np.testing.assert_array_equal(grids.rotation_strains, [0.0, 0.1, 0.2])
    np.testing.assert_array_equal(grids.polar_thetas_deg, [0.0, 45.0, 90.0, 135.0, 180.0])
    # a negative simulated angle: the polar grid covers [-180, 180]
    negative = aggregate([-30.0, 60.0], lambda theta: [0.0, 0.1, 0.2])
    np.testing.assert_array_equal(
        model_vs_simulation.prediction_grids(startup, negative, 60.0).polar_thetas_deg,
        [-180.0, -120.0, -60.0, 0.0, 60.0, 120.0, 180.0],
    )
    with pytest.raises(ValueError, match="polar_step_deg must be positive"):
        model_vs_simulation.prediction_grids(startup, rotation, 0.0)


@pytest.mark.parametrize("strains_at_90", [[0.0, 0.1, 0.25], [0.0, 0.1]], ids=["shifted", "shorter"])
def test_prediction_grids_reject_angles_on_different_strains(strains_at_90):
    """Every angle is compared with the predictions at one shared strain grid (model_errors)."""
    startup = aggregate([0.0], lambda theta: [0.0, 1.0])
    rotation = aggregate([0.0, 90.0], lambda theta: strains_at_90 if theta == 90.0 else [0.0, 0.1, 0.2])
    with pytest.raises(ValueError, match=r"theta=90.0 .* differ from those at theta=0.0"):
        model_vs_simulation.prediction_grids(startup, rotation, 15.0)


def test_predictions_on_simulation_grids_match_predict_at_the_simulated_points(synthetic):
    """The workflow's predictions (rule predict) are predict() at the simulated strains and angles
    plus the polar grid, from the simulated initial fabric."""
    fits, startup_agg, rotation_agg, predictions = synthetic
    on_grids = model_vs_simulation.predict_on_simulation_grids(
        fits, PAPER_MODELS, startup_agg, rotation_agg, STARTUP[-1], 15.0
    )
    pd.testing.assert_frame_equal(on_grids, predictions)


def test_error_tables_cover_both_protocols_and_summarise_them(synthetic):
    fits, startup_agg, rotation_agg, predictions = synthetic
    errors, summary = model_vs_simulation.error_tables(fits, predictions, startup_agg, rotation_agg)
    n12_ss = fits["targets"]["n12"]["mean"]
    expected = pd.concat(
        [
            model_vs_simulation.model_errors(startup_agg, predictions, n12_ss, "startup"),
            model_vs_simulation.model_errors(rotation_agg, predictions, n12_ss, "rotation"),
        ],
        ignore_index=True,
    )
    pd.testing.assert_frame_equal(errors, expected)
    pd.testing.assert_frame_equal(summary, model_vs_simulation.summarise_errors(expected))
    assert "gw_over_modified" not in summary  # a ratio only when asked for
    _, ratio = model_vs_simulation.error_tables(fits, predictions, startup_agg, rotation_agg, ratio=("gw", "modified"))
    np.testing.assert_allclose(ratio["gw_over_modified"], ratio["rms_gw"] / ratio["rms_modified"])
    assert set(summary["protocol"]) == {"startup", "rotation"}


def test_fits_json_round_trip(synthetic, tmp_path):
    fits = synthetic[0]
    path = write_fits(fits, tmp_path / "fits.json")
    assert read_fits(path)["models"]["modified"]["parameters"]["A"] == pytest.approx(
        fits["models"]["modified"]["parameters"]["A"]
    )
    json.loads(path.read_text())  # strict JSON
    (tmp_path / "bad.json").write_text('{"format": 2}')
    with pytest.raises(ValueError, match="missing key 'phi'"):
        read_fits(tmp_path / "bad.json")
    (tmp_path / "future.json").write_text('{"format": 3}')
    with pytest.raises(ValueError, match="fits format 3 is not one this package reads"):
        read_fits(tmp_path / "future.json")


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

"""The model benchmark (suspension_fabric.evaluation.model_benchmark) on synthetic studies whose answer is
known: seeds made by the modified model (beta 9.4, A 42.4, phi 0.45) plus independent Gaussian
noise of standard deviation sigma on every component of every frame. Then
- the global weighted fit recovers (beta, A) within a few of its jackknife errors;
- the generating model's mean square error per seed is sigma^2 / (<nn>_12^ss)^2 on average, in
  sample and held out (it has nothing to learn from the held-out angles);
- in the paired comparison the generating model beats G-W on <nn>'_12 (difference < 0)."""

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.evaluation import model_benchmark as mb
from suspension_fabric.evaluation import model_targets
from suspension_fabric.models import fabric_models as fm

PHI, BETA, A, SIGMA = 0.45, 9.4, 42.4, 0.002
STARTUP = np.linspace(0.0, 5.0, 101)
ROTATION = np.linspace(0.0, 2.0, 41)
THETAS = np.array([0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0])
FABRIC0 = 0.03 * np.eye(3)
TRUE = {"beta": BETA, "A": A}


def table(seed, theta, strains, tensors) -> pd.DataFrame:
    frame = pd.DataFrame({"seed": seed, "theta": theta, "strain": strains})
    for name, (i, j) in COMPONENTS.items():
        frame[name] = tensors[:, i, j]
    return frame


def noisy(tensors, rng):
    noise = SIGMA * rng.normal(size=tensors.shape)
    return tensors + 0.5 * (noise + np.swapaxes(noise, -1, -2)) * np.where(np.eye(3, dtype=bool), 1.0, np.sqrt(2.0))


@pytest.fixture(scope="module")
def curves():
    rng = np.random.default_rng(5)
    startup_exact = fm.startup_shear(fm.MODIFIED, STARTUP, TRUE, PHI, FABRIC0)
    rotation_exact = fm.shear_rotation(fm.MODIFIED, np.radians(THETAS), ROTATION, TRUE, PHI, 5.0, FABRIC0)
    startup, rotation = [], []
    for seed in range(1, 9):
        first = noisy(startup_exact, rng)
        first[0] = FABRIC0  # every seed starts from the same fabric (the models start from the seed mean)
        startup.append(table(seed, 0.0, STARTUP, first))
        for theta, exact in zip(THETAS, rotation_exact):
            rotation.append(table(seed, theta, ROTATION, noisy(exact, rng)))
    return mb.seed_curves(pd.concat(startup), pd.concat(rotation), 2.0, (2.0, 5.0))


def test_noise_on_each_component_has_the_stated_variance():
    """The symmetrised noise: diagonal sd sigma, off-diagonal sd sigma (scaled by sqrt 2 after averaging)."""
    sample = noisy(np.zeros((20000, 3, 3)), np.random.default_rng(0))
    assert np.std(sample[:, 0, 0]) == pytest.approx(SIGMA, rel=0.03)
    assert np.std(sample[:, 0, 1]) == pytest.approx(SIGMA, rel=0.03)


def test_the_global_fit_recovers_the_generating_parameters(curves):
    fitted = mb.global_fit_with_errors(fm.MODIFIED, curves, PHI, 5.0, {"beta": 12.0, "A": 30.0})
    for name, value in TRUE.items():
        error = fitted["errors"][name]
        assert np.isfinite(error) and error > 0
        assert abs(fitted["parameters"][name] - value) < 4 * error, (name, fitted["parameters"][name], error)
    # chi^2 per point for the right model: the weights are 1/s^2 with s the standard error of the mean
    # of n = 8 seeds estimated from them, and E[sigma^2 / s^2] = (n - 1)/(n - 3) = 7/5 for Gaussian noise
    assert fitted["chi2"] / fitted["n_points"] == pytest.approx(7 / 5, rel=0.1)


def test_the_generating_model_scores_the_noise_variance_in_sample_and_held_out(curves):
    expected = SIGMA**2 / curves.n12_ss**2
    _, rotation = mb.model_curves(fm.MODIFIED, TRUE, PHI, curves, 5.0)
    in_sample = mb.seed_errors(rotation, curves)
    assert in_sample.shape == (8, 6)
    assert in_sample.mean() == pytest.approx(expected, rel=0.1)
    held = mb.held_out_errors(fm.MODIFIED, curves, PHI, 5.0, TRUE, folds=3)
    assert held.mean() == pytest.approx(expected, rel=0.1)


def test_angle_folds_split_the_angles_by_stride():
    folds = mb.angle_folds(THETAS, 3)
    assert [f.tolist() for f in folds] == [[0.0, 90.0, 180.0], [30.0, 120.0], [60.0, 150.0]]
    assert len(mb.angle_folds(THETAS, 50)) == len(THETAS)  # leave one angle out at most
    with pytest.raises(ValueError, match="at least two folds"):
        mb.angle_folds([0.0], 4)


def test_the_leaderboard_ranks_the_generating_model_first_on_the_held_out_shear_component(curves):
    models = {"gw": fm.GW, "modified": fm.MODIFIED}
    steady = {
        "gw": {"parameters": {"beta": 11.0}, "errors": {"beta": 0.1}},
        "modified": {"parameters": dict(TRUE), "errors": {"beta": 0.1, "A": 0.2}},
    }
    board, parameters, held_out = mb.leaderboard(models, steady, curves, PHI, 5.0, folds=3, reference="gw")
    assert set(board["mode"]) == {"steady", "global"} and len(board) == 2 * 2 * 6
    assert set(parameters["parameter"]) == {"beta", "A"}
    row = board.set_index(["model", "mode", "component"])
    assert row.loc[("gw", "steady", "n12"), "held_out_difference_vs_gw"] == 0.0
    assert row.loc[("modified", "steady", "n12"), "held_out_difference_high_vs_gw"] < 0.0
    assert row.loc[("modified", "global", "n12"), "held_out_difference_high_vs_gw"] < 0.0
    assert np.isnan(row.loc[("gw", "steady", "n12"), "aic"]) and np.isfinite(row.loc[("gw", "global", "n12"), "aic"])

    # the refined-model targets: the generating model, scored against G-W, shares the simulation's
    # overshoot near 90 degrees (C6's statistic below 0) and holds its steady state exactly
    exact = fm.steady_state(fm.MODIFIED, TRUE, PHI)
    targets = {name: {"mean": exact[i, j]} for name, (i, j) in COMPONENTS.items()}
    card = model_targets.scorecard(models, held_out, curves, PHI, targets, (2.0, 5.0), reference="gw")
    assert set(zip(card["model"], card["mode"])) == {("gw", "global"), ("modified", "steady"), ("modified", "global")}
    generating = card.set_index(["model", "mode"]).loc[("modified", "steady")]
    assert generating["overshoot_T6_high"] < 0 and generating["overshoot_met"]
    assert generating["steady_met"] and abs(generating["steady_n12_relative"]) < 1e-6
    assert generating["n12_target_met"], generating


def test_a_numerically_integrated_model_continues_from_its_startup_curve_exactly(curves):
    """For a model without an exact propagator, model_curves starts the rotations from the last
    frame of its startup curve instead of integrating the startup again: the ODE solver's last
    step ends on the interval's end whatever the output grid, so the two agree to the bit."""
    params = {"beta": 11.0}
    _, continued = mb.model_curves(fm.GW_HYBRID, params, PHI, curves, 5.0)
    again = fm.shear_rotation(
        fm.GW_HYBRID, np.radians(curves.thetas), curves.rotation_strains, params, PHI, 5.0, curves.fabric0
    )
    np.testing.assert_array_equal(continued, again)

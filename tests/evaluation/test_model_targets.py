"""The refined-model targets (suspension_fabric.evaluation.model_targets) on curves whose answer is known.

- Held-out target: T = 0.5 (E_ref - f) - (E_model - f) per seed, met where its t-interval lies
  above 0; the noise floor f is the between-seed variance of the simulated curves.
- Overshoot (claim C6's statistic): X12 = int over the strains where the model's r12 > 1 of
  (r12 - 1) dgamma; for r12 = 1 + a sin(pi gamma / 2) on [0, 2], X12 = 4 a / pi. T6 = 0.25
  X12(model) - X12(sim), met unless its interval lies above 0.
- Steady state: within 3% on the diagonal and 1% on <nn>_12.
"""

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis.seed_statistics import t_interval
from suspension_fabric.evaluation import model_targets as mt
from suspension_fabric.evaluation.model_benchmark import SeedCurves

N12_SS, BUMP = -0.1, 0.2
STRAINS = np.linspace(0.0, 2.0, 401)
THETAS = np.array([0.0, 90.0, 105.0])
OFFSETS = np.array([0.004, -0.003, 0.001, -0.002, 0.0])  # per seed: the simulated r12 - 1


def tensors(r12) -> np.ndarray:
    """Fabric tensors (..., 3, 3) with <nn>_12 = r12 <nn>_12^ss and an isotropic diagonal."""
    out = np.zeros((*np.shape(r12), 3, 3))
    out[..., [0, 1, 2], [0, 1, 2]] = 1.0 / 3.0
    out[..., 0, 1] = out[..., 1, 0] = np.asarray(r12) * N12_SS
    return out


def curves(bump_in_simulation: float) -> SeedCurves:
    """Five seeds; after each rotation r12 = 1 + offset_seed + b sin(pi gamma / 2) at 90 and 105
    degrees (b = ``bump_in_simulation``), 1 + offset_seed at 0; every seed's startup at r12 = 1."""
    startup_strains = np.linspace(0.0, 5.0, 11)
    startup = np.stack([tensors(np.ones_like(startup_strains)) for _ in OFFSETS])
    bump = np.sin(np.pi * STRAINS / 2.0)
    flat = [tensors(np.full_like(STRAINS, 1.0 + o)) for o in OFFSETS]
    bumped = [tensors(1.0 + o + bump_in_simulation * bump) for o in OFFSETS]
    rotation = np.stack([np.stack([f, b, b]) for f, b in zip(flat, bumped)])
    return SeedCurves(
        np.arange(1, 6), startup_strains, startup, THETAS, STRAINS, rotation, startup[:, 0].mean(axis=0), N12_SS
    )


def model_prediction(bump: float) -> np.ndarray:
    """The model's curves after rotation (angles, R, 3, 3): r12 = 1 at 0, 1 + bump sin(pi gamma / 2)
    at 90 and 105."""
    bumped = tensors(1.0 + bump * np.sin(np.pi * STRAINS / 2.0))
    return np.stack([tensors(np.ones_like(STRAINS)), bumped, bumped])


def test_a_model_overshooting_where_the_simulation_does_not_fails_the_overshoot_target():
    result = mt.overshoot_table(model_prediction(BUMP), N12_SS, curves(0.0), (2.0, 5.0))
    assert result["angles"] == "90, 105"
    assert result["X12_model"] == pytest.approx(4 * BUMP / np.pi, rel=1e-4)
    # the simulation's X12 is its offset integrated over the model's window (0, 2), per seed
    assert result["X12_sim"] == pytest.approx(2.0 * OFFSETS.mean(), abs=1e-6)
    assert result["T6"] == pytest.approx(0.25 * 4 * BUMP / np.pi - 2.0 * OFFSETS.mean(), rel=1e-3)
    assert result["T6_low"] > 0 and not result["met"]


def test_an_overshoot_the_simulation_shares_and_no_overshoot_at_all_meet_the_target():
    shared = mt.overshoot_table(model_prediction(BUMP), N12_SS, curves(BUMP), (2.0, 5.0))
    assert shared["T6"] == pytest.approx(-0.75 * 4 * BUMP / np.pi - 2.0 * OFFSETS.mean(), rel=1e-3)
    assert shared["met"]
    flat = mt.overshoot_table(model_prediction(0.0), N12_SS, curves(BUMP), (2.0, 5.0))
    assert flat["X12_model"] == 0.0 and flat["met"]


def test_one_prediction_per_seed_scores_as_the_shared_prediction_when_they_agree():
    shared = mt.overshoot_table(model_prediction(BUMP), N12_SS, curves(0.0), (2.0, 5.0))
    per_seed = np.broadcast_to(model_prediction(BUMP), (5, *model_prediction(BUMP).shape))
    assert mt.overshoot_table(per_seed, N12_SS, curves(0.0), (2.0, 5.0))["T6"] == pytest.approx(shared["T6"], rel=1e-12)


def test_the_noise_floor_is_the_between_seed_variance_of_the_simulated_curves():
    """<nn>_12 differs between seeds by offset x <nn>_12^ss at every strain after the rotation: its
    floor is var(offsets) (ddof 1) in units of (<nn>_12^ss)^2; the isotropic diagonal has none."""
    floor = mt.noise_floor(curves(BUMP))
    assert floor[3] == pytest.approx(np.var(OFFSETS, ddof=1), rel=1e-9)
    assert floor[[0, 1, 2, 4, 5]] == pytest.approx(0.0, abs=1e-20)


def test_the_floor_per_seed_is_its_jackknife_pseudo_value():
    """Seed i's value is n var(offsets) - (n - 1) var(offsets without i) (ddof 1, n = 5): their
    mean is the floor itself (the variance is an unbiased U-statistic)."""
    per_seed = mt.noise_floor_per_seed(curves(BUMP))
    n = len(OFFSETS)
    expected = [n * np.var(OFFSETS, ddof=1) - (n - 1) * np.var(np.delete(OFFSETS, i), ddof=1) for i in range(n)]
    assert per_seed[:, 3] == pytest.approx(expected, rel=1e-9)
    assert per_seed.mean(axis=0) == pytest.approx(mt.noise_floor(curves(BUMP)), rel=1e-9, abs=1e-20)


def test_the_held_out_target_is_met_only_below_half_the_reference_error_net_of_the_floor():
    c = curves(BUMP)
    floor = mt.noise_floor(c)
    rng = np.random.default_rng(3)
    jitter = 0.01 * rng.normal(size=(5, 6))
    reference = floor + 1.0 + jitter
    for candidate_net, met in ((0.3, True), (0.6, False)):
        candidate = floor + candidate_net + jitter[::-1]
        table = mt.target_table(candidate, reference, c).set_index("component")
        # the floor subtracted per seed as its pseudo-value (the same mean, its error in the interval)
        floors = mt.noise_floor_per_seed(c)[:, 3]
        expected = t_interval(0.5 * (reference[:, 3] - floors) - (candidate[:, 3] - floors))
        assert table.loc["n12", "target_statistic"] == pytest.approx(expected.mean, rel=1e-9)
        assert table.loc["n12", "target_low"] == pytest.approx(expected.low, rel=1e-9)
        assert bool(table.loc["n12", "target_met"]) is met


def test_the_steady_state_tolerances_are_three_percent_on_the_diagonal_and_one_on_the_shear():
    targets = {"n11": {"mean": 0.5}, "n22": {"mean": 0.6}, "n33": {"mean": 0.6}, "n12": {"mean": -0.1}}
    fabric = np.array([[0.5 * 1.029, -0.1 * 1.011, 0.0], [-0.1 * 1.011, 0.6 * 0.965, 0.0], [0.0, 0.0, 0.6]])
    rows = {r["component"]: r for r in mt.steady_rows(fabric, targets)}
    assert rows["n11"]["within"] and not rows["n22"]["within"] and not rows["n12"]["within"]
    assert rows["n12"]["relative_difference"] == pytest.approx(0.011)
    assert all(not r["within"] for r in mt.steady_rows(np.full((3, 3), np.nan), targets))


def test_the_scorecard_page_names_only_the_models_meeting_every_target():
    """Two rows, one meeting every target: both tables list both, the closing sentence names the
    one, with its note pointed to; an empty scorecard says so."""
    base = {"level": 0.95, "share": 0.5, "overshoot_angles": "90", "overshoot_T6": 0.01}
    base |= {"overshoot_T6_low": -0.02, "overshoot_T6_high": 0.04, "overshoot_met": True}
    for c in mt.SHEAR_COMPONENTS:
        base |= {f"{c}_net": 0.01, f"{c}_low": 0.005, f"{c}_high": 0.015, f"{c}_reference_net": 0.03}
        base |= {f"{c}_target_statistic": 0.005, f"{c}_target_low": 0.001, f"{c}_target_high": 0.009}
    base |= {f"steady_{c}_relative": 0.001 for c in mt.STEADY_TOLERANCE}
    good = base | {"model": "good", "label": "good model", "mode": "steady", "all_met": True, "steady_met": True}
    good |= {f"{c}_target_met": True for c in mt.SHEAR_COMPONENTS}
    bad = good | {"model": "bad", "label": "bad model", "all_met": False, "n12_target_met": False}
    page = mt.scorecard_markdown(pd.DataFrame([good, bad]), "G-W", {"good": "found here"})
    assert page.count("| good model | steady |") == 2 and page.count("| bad model | steady |") == 2
    assert "good model: found here." in page
    assert page.rstrip().endswith("every target is met by good model (steady fit, see the note above).")
    assert "no model meets every target" in mt.scorecard_markdown(pd.DataFrame([bad]), "G-W")
    assert "No model besides the reference" in mt.scorecard_markdown(pd.DataFrame(), "G-W")

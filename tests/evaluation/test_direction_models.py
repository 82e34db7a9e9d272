"""Fabric models after a change of flow direction (evaluation.direction_models) on curves made by
G-W itself (beta 11) plus a per-seed offset c_s on <nn>_12 at every strain: G-W's error on a seed is
c_s^2 / n12_ss^2 (in units of the steady <nn>_12), the floor's pseudo-values average to var(c) /
n12_ss^2, so G-W's net error is (mean(c^2) - var(c)) / n12_ss^2; "no transient" misses the whole
transient, so G-W beats the jump at every window; two identical points differ by exactly 0 (paired
per seed)."""

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.evaluation import direction_models as dm
from suspension_fabric.evaluation.model_benchmark import SeedCurves
from suspension_fabric.models.fabric_models import resolve_models, shear_rotation, startup_shear
from suspension_fabric.reporting.direction_models_fragments import direction_models_summary

PHI, BETA = 0.54, 11.0
OFFSETS = np.array([0.002, -0.001, 0.0005, -0.0015])
THETAS = np.array([0.0, 90.0, 180.0])


def _curves() -> SeedCurves:
    gw = resolve_models(["gw"])["gw"]
    startup_strains, rotation_strains = np.linspace(0.0, 4.0, 201), np.linspace(0.0, 1.0, 51)
    fabric0 = np.eye(3) * 0.1
    startup = startup_shear(gw, startup_strains, {"beta": BETA}, PHI, fabric0)
    rotation = shear_rotation(gw, np.radians(THETAS), rotation_strains, {"beta": BETA}, PHI, 4.0, fabric0)

    def offset(tensors, c):
        shifted = np.array(tensors, copy=True)
        shifted[..., 0, 1] += c
        shifted[..., 1, 0] += c
        return shifted

    startup_seeds = np.stack([offset(startup, c) for c in OFFSETS])
    rotation_seeds = np.stack([offset(rotation, c) for c in OFFSETS])
    n12_ss = float(startup_seeds[:, startup_strains >= 2.0, 0, 1].mean())
    return SeedCurves(np.arange(1, 5), startup_strains, startup_seeds, THETAS, rotation_strains, rotation_seeds,
                      fabric0, n12_ss)  # fmt: skip


@pytest.fixture(scope="module")
def scores():
    curves = _curves()
    models = resolve_models(["gw"])
    fitted = {"gw": {"parameters": {"beta": BETA}}}
    first = dm.point_scores(models, fitted, curves, PHI, 4.0, (2.0, 4.0), "low", [0.5, 1.0])
    second = dm.point_scores(models, fitted, curves, PHI, 4.0, (2.0, 4.0), "high", [0.5, 1.0])
    return curves, pd.concat([first, second], ignore_index=True)


def test_g_w_on_its_own_curves_scores_its_offsets_net_of_the_floor(scores):
    curves, table = scores
    gw = table[(table["model"] == "gw") & (table["component"] == "n12") & (table["point"] == "low")]
    gw = gw[gw["window"] == 1.0]
    for theta in (90.0, 180.0):
        rows = gw[gw["theta"] == theta].sort_values("seed")
        np.testing.assert_allclose(rows["error"], OFFSETS**2 / curves.n12_ss**2, rtol=1e-6)
        np.testing.assert_allclose(rows["floor"].mean(), np.var(OFFSETS, ddof=1) / curves.n12_ss**2, rtol=1e-9)
    # <nn>_23 is 0 for every model after a reversal: left out; kept after 90 degrees
    assert set(table[table["theta"] == 180.0]["component"]) == {"n12"}
    assert set(table[table["theta"] == 90.0]["component"]) == {"n12", "n23"}
    assert 0.0 not in set(table["theta"])


def test_g_w_predicts_its_own_transient_and_identical_points_do_not_differ(scores):
    _, table = scores
    skill = dm.skill_table(table, {"gw": "G-W (Eq. 1)"})
    gw = skill[skill["model"] == "gw"]
    assert (gw["skill_low"] > 0).all() and (gw["verdict"] == "beats the jump").all()
    assert set(gw["window"]) == {0.5, 1.0}
    baseline = skill[skill["model"] == dm.NO_TRANSIENT]
    assert baseline["p"].isna().all() and (baseline["net_error"] > gw["net_error"].max()).all()
    comparison = dm.state_comparison(table, {"gw": "G-W (Eq. 1)"})
    assert set(comparison["point"]) == {"high"} and set(comparison["versus"]) == {"low"}
    np.testing.assert_allclose(comparison["difference"], 0.0, atol=1e-15)
    assert (comparison["difference_low"] <= 0).all() and (comparison["difference_high"] >= 0).all()
    assert (comparison["p_holm"] == 1.0).all()
    assert (comparison["seeds"] == 4).all()
    page = direction_models_summary(skill, comparison, {"low": "σ/σ₀ 0.01", "high": "σ/σ₀ 1"}, 1.0)
    assert "| σ/σ₀ 0.01 | rotation by 90° | ⟨nn⟩′₂₃ | G-W (Eq. 1) |" in page
    assert "| G-W (Eq. 1) | reversal | ⟨nn⟩′₁₂ | σ/σ₀ 1 − σ/σ₀ 0.01 |" in page
    assert "| net error, W = 1 | gain, W = 1 | gain, W = 0.5 |" in page

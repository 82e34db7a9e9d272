"""Stress relations as plug-ins (suspension_fabric.models.stress_relations) and their benchmark
(suspension_fabric.evaluation.stress_benchmark), against answers known by construction.

Forms: gw is H = <nnnn>:E^, C = <nnnn>:E^_c (suspension_fabric.evaluation.stress_model.relation_terms);
gw_jamming multiplies C by (1 - Z/Z_J)^-2 with Z = 2 Tr<nn>, infinite for Z >= Z_J.
Coefficients: a_H = sigma^lub_12 / H_12(<nn>^ss) and a_C = sigma^con_12 / C_12(<nn>^ss), so the
relation reproduces the steady sigma_12 parts exactly, and eta_r = 1 + 2.5 phi + their sum.
Benchmark: synthetic seeds whose fabric follows the modified model (its own startup and
rotations) and whose stress is
the jamming relation with Z_J = 5 plus independent Gaussian noise; the global fit recovers
Z_J, the generating relation scores sigma^2 / eta_ss^2 in and out of sample, and G-W scores worse
(paired difference < 0 for the jamming relation)."""

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.evaluation import stress_benchmark as sb
from suspension_fabric.evaluation.stress_model import relation_terms
from suspension_fabric.models import fabric_models as fm
from suspension_fabric.models import stress_relations as sr

PHI, Z_J, SIGMA = 0.45, 5.0, 0.02
A_H, A_C = 25.0, 20.0
STARTUP = np.linspace(0.0, 20.0, 201)  # the modified model is steady by 15
ROTATION = np.linspace(0.0, 2.0, 41)
THETAS = np.array([0.0, 45.0, 90.0, 135.0, 180.0])
MODIFIED = {"beta": 9.4, "A": 42.4}
SEEDS = (1, 2, 3, 4, 5, 6)


def random_fabric(rng, trace):
    m = rng.normal(size=(3, 3))
    spd = m @ m.T + 3 * np.eye(3)
    return trace * spd / np.trace(spd)


def test_forms_of_the_built_in_relations():
    """gw: (H, C) = relation_terms; gw_jamming: (H, C (1 - Z/Z_J)^-2), Z = 2 Tr<nn>, infinite at Z >= Z_J."""
    rng = np.random.default_rng(1)
    fabrics = np.stack([random_fabric(rng, t) for t in (0.5, 1.2, 1.7, 2.2)])  # Z = 1, 2.4, 3.4, 4.4
    hydro, contact = relation_terms(fabrics)
    h, c = sr.GW_RELATION.forms(fabrics, {})
    np.testing.assert_array_equal(h, hydro)
    np.testing.assert_array_equal(c, contact)
    h, c = sr.GW_JAMMING.forms(fabrics, {"Z_J": 4.0})
    np.testing.assert_array_equal(h, hydro)
    for k, z in enumerate((1.0, 2.4, 3.4)):
        np.testing.assert_allclose(c[k], contact[k] / (1 - z / 4.0) ** 2, rtol=1e-12)
    assert np.all(np.isinf(c[3]))


@pytest.mark.parametrize("relation, params", [(sr.GW_RELATION, {}), (sr.GW_JAMMING, {"Z_J": 4.5})])
def test_coefficients_reproduce_the_steady_shear_stress(relation, params):
    """At the steady fabric: lubrication_12 = sigma^lub_12, contact_12 = sigma^con_12,
    eta_r = 1 + 2.5 phi + both; for gw_jamming the steady N1, N2, Pi equal gw's (a_C absorbs the
    constant factor of the steady state)."""
    steady = random_fabric(np.random.default_rng(2), 1.7)
    steady[0, 1] = steady[1, 0] = -0.1  # contacts along compression, as in shear
    coefficient = sr.coefficients(relation, steady, 2.9, 10.5, params)
    out = sr.relation_stress(relation, steady, coefficient, params, PHI)
    assert out["lubrication_12"] == pytest.approx(2.9, rel=1e-12)
    assert out["contact_12"] == pytest.approx(10.5, rel=1e-12)
    assert out["eta_r"] == pytest.approx(1 + 2.5 * PHI + 13.4, rel=1e-12)
    gw = sr.relation_stress(sr.GW_RELATION, steady, sr.coefficients(sr.GW_RELATION, steady, 2.9, 10.5, {}), {}, PHI)
    for name in ("N1", "N2", "Pi"):
        assert out[name] == pytest.approx(gw[name], rel=1e-12)


def test_relation_errors_name_the_problem(tmp_path):
    """Bad keys, a shape parameter called a_H, parameters out of bounds, a steady fabric beyond
    Z_J, unknown entries and files that hold no StressRelation: RelationError naming them."""
    with pytest.raises(sr.RelationError, match="must be an identifier"):
        sr.StressRelation(key="my relation", label="x", forms=sr.GW_RELATION.forms)
    with pytest.raises(sr.RelationError, match="not a_H or a_C"):
        sr.StressRelation(key="r", label="x", forms=sr.GW_RELATION.forms, parameters=(fm.Parameter("a_H", 0, 1, 0.5),))
    with pytest.raises(sr.RelationError, match="Z_J = 20.0 outside"):
        sr.GW_JAMMING.check({"Z_J": 20.0})
    steady = random_fabric(np.random.default_rng(3), 2.0)  # Z = 4
    with pytest.raises(sr.RelationError, match="must be positive and finite"):
        sr.coefficients(sr.GW_JAMMING, steady, 1.0, 1.0, {"Z_J": 3.5})
    with pytest.raises(sr.RelationError, match="expected a built-in key"):
        sr.load_relation("jamming")
    (tmp_path / "mine.py").write_text("NOT_A_RELATION = 3\n")
    with pytest.raises(
        sr.RelationError, match="is int, expected a suspension_fabric.models.stress_relations.StressRelation"
    ):
        sr.load_relation(f"{tmp_path / 'mine.py'}:NOT_A_RELATION")
    with pytest.raises(sr.RelationError, match="not found"):
        sr.load_relation(f"{tmp_path / 'absent.py'}:X")
    with pytest.raises(sr.RelationError, match="two entries have the key 'gw'"):
        sr.resolve_relations(["gw", "suspension_fabric.models.stress_relations:GW_RELATION"])
    assert list(sr.resolve_relations(["gw", "gw_jamming"])) == ["gw", "gw_jamming"]


def fabric_frame(seed, theta, strains, tensors, step0):
    frame = pd.DataFrame(
        {"seed": seed, "theta": theta, "N": 100, "phi": PHI, "step": step0 + np.arange(len(strains)), "strain": strains}
    )
    for name, (i, j) in COMPONENTS.items():
        frame[name] = tensors[:, i, j]
    frame["Z"] = 2 * np.trace(tensors, axis1=1, axis2=2)
    return frame


def stress_frame(fabric, tensors, rng, coefficient):
    truth = sr.relation_stress(sr.GW_JAMMING, tensors, coefficient, {"Z_J": Z_J}, PHI)
    frame = fabric[["seed", "theta", "step"]].copy()
    for name in ("lubrication_12", "contact_12", "eta_r", "N1", "N2", "Pi"):
        frame[name] = truth[name] + rng.normal(scale=SIGMA, size=len(frame))
    return frame


@pytest.fixture(scope="module")
def synthetic():
    """Per seed: the modified model's fabric (startup from a small isotropic fabric, rotations
    from its own state at strain 5) and the stresses of the jamming relation (coefficients of that
    steady state) plus independent noise SIGMA."""
    model = fm.MODIFIED
    fabric0 = 0.03 * np.eye(3)
    startup = fm.startup_shear(model, STARTUP, MODIFIED, PHI, fabric0)
    rotation = fm.shear_rotation(model, np.radians(THETAS), ROTATION, MODIFIED, PHI, 20.0, fabric0)
    steady = startup[STARTUP >= 15.0].mean(axis=0)
    truth = sr.coefficients(sr.GW_JAMMING, steady, 2.9, 10.5, {"Z_J": Z_J})
    rng = np.random.default_rng(7)
    tables = {name: [] for name in ("startup", "rotation", "stress_startup", "stress_rotation")}
    for seed in SEEDS:
        scale = 1.0
        frame = fabric_frame(seed, 0.0, STARTUP, scale * startup, 0)
        tables["startup"].append(frame)
        tables["stress_startup"].append(stress_frame(frame, scale * startup, rng, truth))
        for k, theta in enumerate(THETAS):
            frame = fabric_frame(seed, theta, ROTATION, scale * rotation[k], 1000)
            tables["rotation"].append(frame)
            tables["stress_rotation"].append(stress_frame(frame, scale * rotation[k], rng, truth))
    frames = {name: pd.concat(value, ignore_index=True) for name, value in tables.items()}
    return sb.stress_curves(
        frames["startup"], frames["rotation"], frames["stress_startup"], frames["stress_rotation"], 2.0, (15.0, 20.0)
    ), frames


def test_the_global_fit_recovers_z_j(synthetic):
    curves, _ = synthetic
    assert curves.rotation_fabric.shape == (len(SEEDS), len(THETAS), len(ROTATION), 3, 3)
    assert 2 * np.trace(curves.steady_fabric, axis1=1, axis2=2).max() < Z_J
    fitted = sb.fit_shape(sr.GW_JAMMING, curves)
    assert fitted["Z_J"] == pytest.approx(Z_J, abs=0.02)
    assert sb.fit_shape(sr.GW_RELATION, curves) == {}


def test_leaderboard_scores_the_generating_relation_at_the_noise(synthetic):
    """The generating relation's held-out mean square error of eta_r after rotation is
    ~ (sigma / eta_ss)^2 (the noise it cannot predict); G-W's is larger, and the paired
    difference (jamming - gw) has its interval below 0; the table has every scored quantity."""
    curves, _ = synthetic
    board, parameters = sb.relation_leaderboard(sr.BUILT_IN, curves, folds=3, reference="gw")
    assert set(board["quantity"]) == set(sb.SCORED)
    rotation = board[board["quantity"] == "eta_r rotation"].set_index("relation")
    noise = (SIGMA / curves.eta_ss) ** 2
    assert rotation.loc["gw_jamming", "held_out_mse"] == pytest.approx(noise, rel=0.15)
    assert rotation.loc["gw", "held_out_mse"] > 3 * noise
    assert rotation.loc["gw_jamming", "held_out_difference_high_vs_gw"] < 0
    assert rotation.loc["gw", "held_out_difference_vs_gw"] == 0
    assert rotation.loc["gw", "mode"] == "steady" and rotation.loc["gw_jamming", "mode"] == "global"
    z_j = parameters[(parameters["relation"] == "gw_jamming") & (parameters["parameter"] == "Z_J")].iloc[0]
    assert z_j["value"] == pytest.approx(Z_J, abs=0.02) and 0 < z_j["error"] < 0.05
    assert set(parameters[parameters["relation"] == "gw"]["parameter"]) == {"a_H", "a_C"}


def test_stress_curves_errors(synthetic):
    """Frames of the fabric and stress tables that do not match, and a single seed, are errors."""
    _, frames = synthetic
    args = (frames["startup"], frames["rotation"], frames["stress_startup"], frames["stress_rotation"])
    with pytest.raises(ValueError, match="share only"):
        sb.stress_curves(args[0], args[1], args[2].iloc[1:], args[3], 2.0, (15.0, 20.0))
    one = [f[f["seed"] == 1] for f in args]
    with pytest.raises(ValueError, match="at least two seeds"):
        sb.stress_curves(*one, 2.0, (15.0, 20.0))
    with pytest.raises(ValueError, match="below the window 3"):
        sb.stress_curves(*args, 3.0, (15.0, 20.0))

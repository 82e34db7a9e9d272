"""The sparse-regression fabric model (suspension_fabric.models.sparse_fabric) and its discovery
(suspension_fabric.evaluation.model_discovery) against answers known exactly: G-W written in the
library, frame indifference, a model recovered from its own trajectories."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from scipy.spatial.transform import Rotation

from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.analysis.frames import simple_shear_gradient, sym_to_vec
from suspension_fabric.evaluation import model_benchmark
from suspension_fabric.evaluation import model_discovery as md
from suspension_fabric.models import fabric_models
from suspension_fabric.models.fabric_models import ModelError, flow_of, load_model
from suspension_fabric.models.sparse_fabric import (
    LIBRARY,
    ORDER,
    corotational,
    library_terms,
    read_model_file,
    sparse_model,
    write_model_file,
)

PHI, BETA = 0.45, 11.0
FLOW = flow_of(simple_shear_gradient())


def random_fabrics(n: int, seed: int = 0) -> np.ndarray:
    vectors = np.random.default_rng(seed).normal(size=(n, 5, 3))
    return np.einsum("nki,nkj->nij", vectors, vectors) / 5.0


def gw_in_the_library(beta: float = BETA) -> dict[str, float]:
    """G-W's right-hand side minus the co-rotational part, regressed on the terms of order <= 1 at
    random fabrics: the paper's closure is linear, so the fit is exact."""
    fabrics = random_fabrics(100)
    target = fabric_models.GW.rhs(fabrics, FLOW, {"beta": beta}, PHI) - corotational(fabrics, FLOW)
    names = [name for name in LIBRARY if ORDER[name] <= 1]
    columns = sym_to_vec(library_terms(fabrics, FLOW, names)).transpose(1, 0, 2).reshape(len(names), -1).T
    coefficients, *_ = np.linalg.lstsq(columns, sym_to_vec(target).ravel(), rcond=None)
    return dict(zip(names, coefficients))


def test_g_w_lies_in_the_span_of_the_first_order_terms():
    """G-W with the paper's closure is affine in <nn>; written in the library it is the same model."""
    model = sparse_model(gw_in_the_library())
    assert model.affine
    fabrics = random_fabrics(20, seed=1)
    np.testing.assert_allclose(
        model.rhs(fabrics, FLOW, {"rate": 1.0}, PHI),
        fabric_models.GW.rhs(fabrics, FLOW, {"beta": BETA}, PHI),
        atol=1e-12,
    )


def test_every_term_turns_with_the_flow():
    """Frame indifference: for any rotation R, Theta(R X R^T; R L R^T) = R Theta(X; L) R^T, and so
    for the whole right-hand side of a model with every term."""
    rotation = Rotation.from_euler("xyz", [0.3, -1.1, 2.0]).as_matrix()
    fabric = random_fabrics(1, seed=2)[0]
    turned = flow_of(rotation @ simple_shear_gradient() @ rotation.T)
    model = sparse_model({name: 0.1 * (k + 1) for k, name in enumerate(LIBRARY)})
    here = model.rhs(fabric, FLOW, {"rate": 1.0}, PHI)
    there = model.rhs(rotation @ fabric @ rotation.T, turned, {"rate": 1.0}, PHI)
    np.testing.assert_allclose(there, rotation @ here @ rotation.T, atol=1e-12)


def test_the_weak_form_of_a_models_own_trajectory_is_solved_by_its_coefficients():
    """Along an exact trajectory, X(b) - X(a) - int corotational = sum_k c_k int Theta_k, to
    Simpson's rule's error (h = 0.02)."""
    coefficients = gw_in_the_library()
    strains = np.linspace(0.0, 3.0, 151)
    path = fabric_models.startup_shear(fabric_models.GW, strains, {"beta": BETA}, PHI)
    A, y = md.weak_form_system([(strains, path)], list(coefficients))
    assert A.shape == (37 * 6, len(coefficients))  # windows of 4 steps sharing their ends
    np.testing.assert_allclose(A @ np.array(list(coefficients.values())), y, atol=2e-5)


def test_the_constrained_fit_holds_the_steady_state_exactly():
    rng = np.random.default_rng(4)
    A, y = rng.normal(size=(200, 6)), rng.normal(size=200)
    C, d = rng.normal(size=(2, 6)), rng.normal(size=2)
    support = np.array([True, True, False, True, True, True])
    c = md.constrained_least_squares(A, y, support, (C, d))
    assert c[2] == 0.0
    np.testing.assert_allclose(C @ c, d, atol=1e-12)
    # a constraint the least-squares solution already satisfies changes nothing
    free = np.zeros(6)
    free[support] = np.linalg.lstsq(A[:, support], y, rcond=None)[0]
    np.testing.assert_allclose(md.constrained_least_squares(A, y, support, (C, C @ free)), free, atol=1e-10)


def _run_table(seed, theta, strains, fabrics) -> pd.DataFrame:
    table = pd.DataFrame({"seed": seed, "theta": theta, "N": 1000, "phi": PHI, "step": 0, "strain": strains})
    for name, (i, j) in COMPONENTS.items():
        table[name] = fabrics[:, i, j]
    return table.assign(Z=2.0 * np.trace(fabrics, axis1=1, axis2=2))


#: A fast G-W (slowest relaxation rate 3.7 per unit strain) is steady within the steady window
#: [2, 5] as the simulations are; at the paper's beta it is still relaxing there.
FAST_BETA = 60.0


@pytest.fixture(scope="module")
def g_w_runs():
    """Three seeds of a fast G-W (startup from no contacts, rotations every 45 degrees), each with
    small independent noise (1e-4) so that the seeds differ."""
    rng = np.random.default_rng(5)
    startup_strains, rotation_strains = np.linspace(0.0, 5.0, 251), np.linspace(0.0, 3.0, 151)
    thetas = np.array([0.0, 45.0, 90.0, 135.0, 180.0])
    params = {"beta": FAST_BETA}
    startup = fabric_models.startup_shear(fabric_models.GW, startup_strains, params, PHI)
    rotations = fabric_models.shear_rotation(fabric_models.GW, np.radians(thetas), rotation_strains, params, PHI)
    startups, rotation_tables = [], []
    for seed in (1, 2, 3):

        def noisy(x):
            return x + 1e-4 * rng.normal(size=x.shape) * (x != 0)

        startups.append(_run_table(seed, 0.0, startup_strains, noisy(startup)))
        for theta, path in zip(thetas, rotations):
            rotation_tables.append(_run_table(seed, theta, rotation_strains, noisy(path)))
    return pd.concat(startups, ignore_index=True), pd.concat(rotation_tables, ignore_index=True)


def test_discovery_on_g_w_data_predicts_the_held_out_angles_as_g_w_does(g_w_runs):
    """On data made by G-W, the chosen model predicts each held-out fold of angles (fitted on the
    others and the startup) within the noise: its error is that of G-W itself to a few times the
    noise floor ((1e-4 / <nn>_12^ss)^2 ~ 1e-6 per component). The library cannot tell every term
    apart on such data (some combinations vanish along the trajectories), so the coefficients are
    not compared term by term."""
    startup_runs, rotation_runs = g_w_runs
    curves = model_benchmark.seed_curves(startup_runs, rotation_runs, 2.0, (2.0, 5.0))
    found = md.discover(startup_runs, rotation_runs, curves, PHI, 5.0, 2, (2.0, 5.0))
    _, exact = model_benchmark.model_curves(fabric_models.GW, {"beta": FAST_BETA}, PHI, curves, 5.0)
    floor = model_benchmark.seed_errors(exact, curves).sum(axis=1)
    assert found["held_out"].sum(axis=1).max() < 1e-4, (found["held_out"].sum(axis=1), floor)
    assert floor.max() < 1e-5
    table = md.coefficient_table(found)
    assert set(table["term"]) == set(found["coefficients"]) and (table["error"] >= 0).all()
    chosen = found["supports"].iloc[found["chosen"]]
    assert chosen["held_out_error"] <= found["supports"]["held_out_error"].min() + chosen["held_out_se"] + 1e-15


def test_a_model_file_round_trips_and_bad_files_are_named(tmp_path):
    coefficients = gw_in_the_library()
    path = write_model_file(tmp_path / "model.json", coefficients, dict.fromkeys(coefficients, 0.1), {"study": "x"})
    loaded = load_model(str(path))
    fabrics = random_fabrics(3)
    np.testing.assert_allclose(
        loaded.rhs(fabrics, FLOW, {"rate": 1.0}, PHI), sparse_model(coefficients).rhs(fabrics, FLOW, {"rate": 1.0}, PHI)
    )
    with pytest.raises(ModelError, match="not found"):
        read_model_file(tmp_path / "missing.json")
    record = json.loads(path.read_text())
    record["coefficients"]["X^3"] = 1.0
    (tmp_path / "bad.json").write_text(json.dumps(record))
    with pytest.raises(ModelError, match=r"bad.json: sparse model terms \['X\^3'\]"):
        read_model_file(tmp_path / "bad.json")
    (tmp_path / "other.json").write_text(json.dumps(dict(record, kind="neural")))
    with pytest.raises(ModelError, match="kind 'neural'; expected format 1, kind 'sparse'"):
        read_model_file(tmp_path / "other.json")


def test_the_quadratic_form_of_a_model_is_its_right_hand_side():
    """Every combination of library terms is at most quadratic in X, so b + M v + T(v, v) from
    values at 28 fabrics reproduces it anywhere; a model with every term evaluates through it."""
    from suspension_fabric.models.sparse_fabric import quadratic_form

    values = {name: np.sin(k + 1.0) for k, name in enumerate(LIBRARY)}
    fabrics = random_fabrics(7, seed=8)

    def combination(x):
        return np.einsum("k,...kij->...ij", np.array(list(values.values())), library_terms(x, FLOW, list(values)))

    b, M, T = quadratic_form(combination)
    v = sym_to_vec(fabrics)
    np.testing.assert_allclose(
        b + v @ M.T + np.einsum("ijk,nj,nk->ni", T, v, v), sym_to_vec(combination(fabrics)), atol=1e-12
    )
    model = sparse_model(values)
    np.testing.assert_allclose(
        model.rhs(fabrics, FLOW, {"rate": 0.7}, PHI),
        corotational(fabrics, FLOW) + 0.7 * combination(fabrics),
        atol=1e-12,
    )


def test_the_steady_state_from_the_fitted_one_is_the_integrated_one(tmp_path):
    """A model holding a given steady fabric at r = 1 (its file records it): Newton's method from it
    at another rate finds the state that integrating from no contacts reaches."""
    coefficients = gw_in_the_library(FAST_BETA) | {"X.X": -0.05}
    model = sparse_model(coefficients)
    anchor = fabric_models.startup_shear(model, [40.0], {"rate": 1.0}, PHI)[0]
    path = write_model_file(tmp_path / "m.json", coefficients, dict.fromkeys(coefficients, 0.0), {}, anchor)
    loaded = read_model_file(path)
    assert loaded.steady is not None
    for rate in (1.0, 1.4):
        integrated = fabric_models.startup_shear(model, [60.0], {"rate": rate}, PHI)[0]
        np.testing.assert_allclose(fabric_models.steady_state(loaded, {"rate": rate}, PHI), integrated, atol=1e-8)

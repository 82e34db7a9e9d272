"""The fabric-model interface (suspension_fabric.models.fabric_models): the built-in models through the
interface equal the paper's equations (suspension_fabric.models.gillissen_wilson), the general ODE path equals the
exact affine propagation and a relaxation law's analytic solution, the generic steady fit recovers
known parameters, and bad models or entries stop with an error naming them."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from suspension_fabric.analysis import frames
from suspension_fabric.analysis.frames import simple_shear_gradient
from suspension_fabric.models import fabric_models as fm
from suspension_fabric.models import gillissen_wilson as model

PHI = 0.45
STRAINS = np.linspace(0.0, 3.0, 7)
THETAS = np.radians([0.0, 45.0, 90.0, 135.0])
SHEAR = simple_shear_gradient()
STUDY = {"study": "s", "seeds": [1], "angles_deg": [0]}
FABRIC0 = frames.vec_to_sym([0.03, 0.025, 0.028, -0.004, 0.001, 0.0])


def relaxation(target):
    """d<nn>/dgamma = -rate (<nn> - target): <nn>(gamma) = target + (<nn>(0) - target) exp(-rate gamma)."""
    return lambda fabric, flow, p, phi: -p["k"] * (np.asarray(fabric) - target) + 0.0 * flow.grad_hat


def relaxation_model(affine, **changes):
    target = frames.vec_to_sym([0.05, 0.03, 0.04, -0.02, 0.0, 0.0])
    return fm.FabricModel(
        key="relax",
        label="relaxation",
        parameters=(fm.Parameter("k", 0.0, 10.0, 1.0),),
        steady_targets=("12",),
        rhs=relaxation(target),
        affine=affine,
        **changes,
    ), target


@pytest.mark.parametrize("affine", [True, False])
def test_a_relaxation_law_integrates_to_its_exponential(affine):
    relax, target = relaxation_model(affine)
    got = fm.integrate(relax, FABRIC0, SHEAR, STRAINS, {"k": 1.7}, PHI)
    exact = target + (FABRIC0 - target) * np.exp(-1.7 * STRAINS)[:, None, None]
    np.testing.assert_allclose(got, exact, rtol=1e-8, atol=1e-11)
    np.testing.assert_allclose(fm.steady_state(relax, {"k": 1.7}, PHI), target, atol=1e-9)


@pytest.mark.parametrize("fabric_model, beta, A", [(fm.GW, 10.9, None), (fm.MODIFIED, 9.4, 42.4)])
def test_the_paper_models_through_the_interface_equal_its_equations(fabric_model, beta, A):
    params = {"beta": beta} if A is None else {"beta": beta, "A": A}
    M, b = fm.affine_system(fabric_model, fm.flow_of(SHEAR), params, PHI)
    M_paper, b_paper = model.affine_rhs(SHEAR, beta, A, PHI)
    np.testing.assert_allclose(M, M_paper, atol=1e-14)
    np.testing.assert_allclose(b, b_paper, atol=1e-14)
    np.testing.assert_allclose(
        fm.shear_rotation(fabric_model, THETAS, STRAINS, params, PHI, 5.0, FABRIC0),
        model.shear_rotation(THETAS, STRAINS, beta, A, PHI, 5.0, FABRIC0),
        atol=1e-13,
    )
    np.testing.assert_allclose(
        fm.steady_state(fabric_model, params, PHI), model.steady_state_ode(beta, A, PHI), atol=1e-12
    )


def test_the_ode_path_equals_the_exact_propagation_for_the_modified_model():
    params = {"beta": 9.4, "A": 42.4}
    as_ode = dataclasses.replace(fm.MODIFIED, affine=False, steady=None, fit=None)
    np.testing.assert_allclose(
        fm.shear_rotation(as_ode, THETAS, STRAINS, params, PHI, 5.0, FABRIC0),
        fm.shear_rotation(fm.MODIFIED, THETAS, STRAINS, params, PHI, 5.0, FABRIC0),
        atol=1e-9,
    )
    np.testing.assert_allclose(fm.steady_state(as_ode, params, PHI), model.steady_state_ode(9.4, 42.4, PHI), atol=1e-9)


def test_the_generic_steady_fit_recovers_the_exact_fit():
    target = model.steady_state_ode(9.4, 42.4, PHI)
    generic = dataclasses.replace(fm.MODIFIED, steady=None, fit=None)
    fitted = fm.fit_steady(generic, {"11": target[0, 0], "12": target[0, 1]}, PHI)
    assert fitted["beta"] == pytest.approx(9.4, rel=1e-6) and fitted["A"] == pytest.approx(42.4, rel=1e-6)
    exact = fm.fit_steady(fm.MODIFIED, {"11": target[0, 0], "12": target[0, 1]}, PHI)
    assert exact == pytest.approx({"beta": 9.4, "A": 42.4}, rel=1e-9)


def test_separate_rates_reduce_to_the_modified_model_and_fit_three_components():
    """beta_e = beta_c = beta is the modified model; its steady 11, 33, 12 give back the three rates."""
    same = {"beta_e": 9.4, "beta_c": 9.4, "A": 42.4}
    np.testing.assert_allclose(
        fm.shear_rotation(fm.SEPARATE_RATES, THETAS, STRAINS, same, PHI, 5.0, FABRIC0),
        model.shear_rotation(THETAS, STRAINS, 9.4, 42.4, PHI, 5.0, FABRIC0),
        atol=1e-13,
    )
    rates = {"beta_e": 12.0, "beta_c": 7.0, "A": 30.0}
    steady = fm.steady_state(fm.SEPARATE_RATES, rates, PHI)
    targets = {"11": steady[0, 0], "33": steady[2, 2], "12": steady[0, 1]}
    assert fm.fit_steady(fm.SEPARATE_RATES, targets, PHI) == pytest.approx(rates, rel=1e-9)  # its exact fit
    generic = dataclasses.replace(fm.SEPARATE_RATES, fit=None)
    assert fm.fit_steady(generic, targets, PHI) == pytest.approx(rates, rel=1e-6)  # bounded least squares


def test_a_model_declared_affine_that_is_not_is_refused():
    quadratic = fm.FabricModel(
        key="quad",
        label="q",
        parameters=(fm.Parameter("k", 0.0, 1.0, 0.5),),
        steady_targets=("12",),
        affine=True,
        rhs=lambda x, flow, p, phi: -p["k"] * np.asarray(x) @ np.asarray(x),
    )
    with pytest.raises(fm.ModelError, match="quad is declared affine but"):
        fm.integrate(quadratic, FABRIC0, SHEAR, STRAINS, {"k": 0.5}, PHI)


def test_parameters_are_checked_by_name_and_bounds():
    with pytest.raises(fm.ModelError, match=r"modified: parameters \['beta'\] given, expected \['beta', 'A'\]"):
        fm.steady_state(fm.MODIFIED, {"beta": 9.4}, PHI)
    with pytest.raises(fm.ModelError, match=r"gw: beta = -1.0 outside \[0.001, 10000.0\]"):
        fm.steady_state(fm.GW, {"beta": -1.0}, PHI)
    with pytest.raises(fm.ModelError, match="steady_targets"):
        fm.FabricModel(
            key="bad",
            label="b",
            parameters=(fm.Parameter("k", 0, 1, 0.5),),
            steady_targets=("12", "11"),
            rhs=lambda *a: 0,
        )


def test_models_load_from_a_key_a_module_or_a_file(tmp_path):
    assert fm.load_model("gw") is fm.GW
    assert fm.load_model("suspension_fabric.models.fabric_models:SEPARATE_RATES") is fm.SEPARATE_RATES
    (tmp_path / "mine.py").write_text(
        "import dataclasses\nfrom suspension_fabric.models import fabric_models as fm\n"
        "MINE = dataclasses.replace(fm.GW, key='mine', label='my G-W copy')\nNOT_A_MODEL = 3\n"
    )
    mine = fm.load_model(f"{tmp_path}/mine.py:MINE")
    assert mine.key == "mine" and mine.rhs is fm.GW.rhs
    assert list(fm.resolve_models(["gw", f"{tmp_path}/mine.py:MINE"])) == ["gw", "mine"]
    for spec, message in [
        ("nonsense", "expected a built-in key"),
        (f"{tmp_path}/none.py:X", "not found"),
        (f"{tmp_path}/mine.py:NOT_A_MODEL", "is int, expected"),
        ("no_such_module_xyz:M", "cannot import no_such_module_xyz"),
    ]:
        with pytest.raises(fm.ModelError, match=message):
            fm.load_model(spec)
    with pytest.raises(fm.ModelError, match="two entries have the key 'gw'"):
        fm.resolve_models(["gw", "suspension_fabric.models.fabric_models:GW"])


def test_the_config_names_a_bad_model_entry_before_anything_runs(tmp_path):
    from suspension_fabric.study.config import ConfigError, validate_config

    assert validate_config({**STUDY})["models"]["fabric"] == ["gw", "modified", "separate_rates"]
    with pytest.raises(ConfigError, match=r"config key 'models.fabric': model 'gw_typo': expected a built-in key"):
        validate_config({**STUDY, "models": {"fabric": ["gw", "gw_typo"]}})
    with pytest.raises(ConfigError, match=r"config key 'models.fabric'"):
        validate_config({**STUDY, "models": {"fabric": []}})


def test_two_exact_separate_rates_solutions_are_told_apart_by_the_unfitted_component():
    """Steady <nn>_11, _33, _12 reached by two rate sets (the test study's); <nn>_22 picks one."""
    targets = {"11": 0.223325, "33": 0.173348, "12": -0.141949}
    with pytest.raises(fm.ModelError, match="2 stable, physical solutions"):
        fm.fit_steady(fm.SEPARATE_RATES, targets, PHI)
    for beta_e in (8.5459, 115.727):
        near = {"beta_e": beta_e, "beta_c": 15.868 if beta_e < 50 else 61.154, "A": 4.5087 if beta_e < 50 else 71.229}
        n22 = fm.steady_state(fm.SEPARATE_RATES, near, PHI)[1, 1]
        fitted = fm.fit_steady(fm.SEPARATE_RATES, {**targets, "22": n22}, PHI)
        assert fitted["beta_e"] == pytest.approx(beta_e, rel=1e-3)


def test_g_w_with_the_hybrid_closure_is_g_w_where_the_closures_agree():
    """At an isotropic fabric (det(a) = 1/27, so f = 0) the hybrid closure is the paper's: the
    right-hand sides agree; elsewhere they differ, and the steady state found by Newton's method
    is the one integration from no contacts reaches."""
    flow = fm.flow_of(simple_shear_gradient())
    params = {"beta": 11.0}
    iso = 0.6 * np.eye(3)
    np.testing.assert_allclose(
        fm.GW_HYBRID.rhs(iso, flow, params, 0.45), fm.GW.rhs(iso, flow, params, 0.45), atol=1e-14
    )
    aligned = np.diag([0.8, 0.3, 0.2]) + 0.1 * (np.eye(3)[[0]].T @ np.eye(3)[[1]] + np.eye(3)[[1]].T @ np.eye(3)[[0]])
    assert not np.allclose(fm.GW_HYBRID.rhs(aligned, flow, params, 0.45), fm.GW.rhs(aligned, flow, params, 0.45))
    steady = fm.steady_state(fm.GW_HYBRID, params, 0.45)
    integrated = fm.startup_shear(fm.GW_HYBRID, [60.0], params, 0.45)[0]
    np.testing.assert_allclose(steady, integrated, atol=1e-9)


def fabrics_with_an_empty_one(count: int) -> np.ndarray:
    """Random positive semi-definite fabrics (count, 3, 3), the first without contacts (trace 0)."""
    shape = np.random.default_rng(7).normal(size=(count, 3, 3)) * 0.2
    fabrics = shape @ np.swapaxes(shape, -1, -2)
    fabrics[0] = 0.0
    return fabrics


def every_term_sparse_model():
    from suspension_fabric.models.sparse_fabric import LIBRARY, sparse_model

    return sparse_model({name: np.sin(k + 1.0) for k, name in enumerate(LIBRARY)})


@pytest.mark.parametrize(
    "make_model, params", [(lambda: fm.GW_HYBRID, {"beta": 37.0}), (every_term_sparse_model, {"rate": 1.3})]
)
def test_a_vector_form_is_its_right_hand_side(make_model, params):
    """A model's vector_form (the solver's fast path) gives the same dv/dgamma as its tensor rhs, to
    rounding: for one flow, a batch of equal flows and (where it takes them) a batch of turned
    flows, on fabrics that include one without contacts (where the hybrid closure's a = I/3)."""
    fabric_model = make_model()
    fabrics = fabrics_with_an_empty_one(6)
    vectors = frames.sym_to_vec(fabrics)
    one = fm.flow_of(SHEAR)
    equal = fm.Flow(*(np.broadcast_to(t, fabrics.shape) for t in one))
    turned = fm.flow_of(frames.to_basis(SHEAR, frames.rotation_about_gradient(np.linspace(0.0, 3.0, 6))))
    for flow in (one, equal, turned):
        expected = frames.sym_to_vec(fabric_model.rhs(fabrics, flow, params, PHI))
        np.testing.assert_allclose(fm.vector_rhs(fabric_model, flow, params, PHI)(vectors), expected, atol=1e-14)
    assert fabric_model.vector_form(one, params, PHI) is not None
    single = fm.vector_rhs(fabric_model, one, params, PHI)(vectors[3])
    np.testing.assert_allclose(single, frames.sym_to_vec(fabric_model.rhs(fabrics[3], one, params, PHI)), atol=1e-14)


def test_integration_through_the_vector_form_follows_the_right_hand_side():
    """The solver's path through G-W-hybrid's vector form and through its tensor rhs (the form
    removed) give the same startup and rotation transients to the integration's tolerance."""
    params = {"beta": 21.0}
    both = (fm.GW_HYBRID, dataclasses.replace(fm.GW_HYBRID, vector_form=None))
    fast, slow = (fm.shear_rotation(m, THETAS, STRAINS, params, PHI, 2.0) for m in both)
    np.testing.assert_allclose(fast, slow, rtol=1e-8, atol=1e-11)
    fast, slow = (fm.integrate_segment(m, FABRIC0, STRAINS, params, PHI, 30.0) for m in both)
    np.testing.assert_allclose(fast, slow, rtol=1e-8, atol=1e-11)

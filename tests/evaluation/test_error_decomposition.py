"""G-W's error taken apart (suspension_fabric.evaluation.error_decomposition) against answers known
exactly: a "simulation" that is G-W itself, whose fourth moment is the paper's closure of its
second, must come out with no error in any variant and any stress source."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.integrate import solve_ivp

from suspension_fabric.analysis.fabric import COMPONENTS, FOURTH_MOMENT_COMPONENTS
from suspension_fabric.analysis.frames import (
    rotation_about_gradient,
    simple_shear_gradient,
    sym_to_vec,
    to_basis,
    vec_to_sym,
)
from suspension_fabric.evaluation import error_decomposition as ed
from suspension_fabric.models import fabric_models
from suspension_fabric.models.gillissen_wilson import hinch_leal_closure
from suspension_fabric.models.stress_relations import GW_RELATION, relation_stress

PHI = 0.45


def test_solve_forced_is_exact_for_a_forcing_linear_between_the_strains():
    """dv/dgamma = M v + b + g(gamma) with g linear between nodes: the interval-wise exponential
    solution equals a tight Runge-Kutta integration of the same piecewise-linear g."""
    rng = np.random.default_rng(1)
    M = rng.normal(size=(6, 6)) - 3.0 * np.eye(6)
    b, v0 = rng.normal(size=6), rng.normal(size=6)
    strains = np.concatenate([np.linspace(0.0, 1.0, 26), [1.07, 1.3]])  # uneven steps too
    forcing = rng.normal(size=(len(strains), 6))

    def rhs(gamma, v):
        g = np.array([np.interp(gamma, strains, forcing[:, k]) for k in range(6)])
        return M @ v + b + g

    reference = solve_ivp(
        rhs, (0.0, strains[-1]), v0, t_eval=strains, rtol=1e-12, atol=1e-12, method="DOP853", max_step=0.01
    ).y.T
    np.testing.assert_allclose(ed.solve_forced(M, b, v0, strains, forcing), reference, rtol=1e-8, atol=1e-9)


def test_solve_forced_refuses_strains_that_do_not_increase():
    with pytest.raises(ValueError, match="strains must increase"):
        ed.solve_forced(np.eye(6), np.zeros(6), np.zeros(6), [0.0, 0.0], np.zeros((2, 6)))


def test_the_rates_that_balance_a_models_own_steady_state_are_its_rates():
    """At the steady state of (1) with rates (b_e, b_c, a) and <nnnn> = closure(<nn>), the right-hand
    side vanishes, so measured_rates returns the rates, measured_beta returns beta when they are all
    beta, and steady_residual is zero."""
    rates = (5.0, 16.0, 17.0)
    params = dict(zip(("beta_e", "beta_c", "A"), rates))
    steady = fabric_models.steady_state(fabric_models.SEPARATE_RATES, params, PHI)
    fourth = hinch_leal_closure(steady)
    np.testing.assert_allclose(ed.measured_rates(steady, fourth, PHI), rates, rtol=1e-9)
    np.testing.assert_allclose(ed.steady_residual(steady, fourth, rates, PHI), 0.0, atol=1e-12)
    gw = fabric_models.steady_state(fabric_models.GW, {"beta": 11.0}, PHI)
    assert ed.measured_beta(gw, hinch_leal_closure(gw), PHI) == pytest.approx(11.0, rel=1e-10)


def test_each_variant_reproduces_g_w_when_the_fourth_moment_is_its_closure():
    """Along a G-W trajectory whose <nnnn> is the closure of its <nn>: the closure variants equal it
    to round-off (the correction vanishes), the measured ones to the interpolation of the forcing,
    O(h^2) for the step h = 0.02."""
    beta = 11.0
    start = to_basis(fabric_models.steady_state(fabric_models.GW, {"beta": beta}, PHI), rotation_about_gradient(2.0))
    strains = np.linspace(0.0, 2.0, 101)
    path = fabric_models.integrate(fabric_models.GW, start, simple_shear_gradient(), strains, {"beta": beta}, PHI)
    fourth = hinch_leal_closure(path)
    for variant in ed.FABRIC_VARIANTS:
        predicted = ed.gw_with_fourth_moment(start, strains, fourth, path, (beta,) * 3, PHI, variant)
        tolerance = 1e-3 if variant.startswith("measured") else 1e-12
        np.testing.assert_allclose(predicted, path, atol=tolerance, err_msg=variant)
    with pytest.raises(ValueError, match="unknown variant"):
        ed.gw_with_fourth_moment(start, strains, fourth, path, (beta,) * 3, PHI, "nonsense")


def _fourth_columns(fabrics) -> dict:
    fourth = hinch_leal_closure(fabrics)
    return {name: fourth[(slice(None), *index)] for name, index in FOURTH_MOMENT_COMPONENTS.items()}


def _frames(seed, theta, strains, fabrics) -> pd.DataFrame:
    table = pd.DataFrame({"seed": seed, "theta": theta, "strain": strains})
    for name, (i, j) in COMPONENTS.items():
        table[name] = fabrics[:, i, j]
    return table.assign(**_fourth_columns(fabrics))


def _stress(table: pd.DataFrame, coefficient) -> pd.DataFrame:
    fabrics = np.stack(
        [[[row[f"n{min(i, j) + 1}{max(i, j) + 1}"] for j in range(3)] for i in range(3)] for _, row in table.iterrows()]
    )
    values = relation_stress(GW_RELATION, fabrics, coefficient, {}, PHI)
    return table[["seed", "theta", "strain"]].assign(
        eta_r=values["eta_r"],
        N1=values["N1"],
        N2=values["N2"],
        Pi=values["Pi"],
        lubrication_12=values["lubrication_12"],
        contact_12=values["contact_12"],
    )


@pytest.fixture(scope="module")
def g_w_study():
    """Three seeds, each G-W itself with its own beta (its startup at its steady state, rotations by
    0 (the control), 45, 90 and 180 degrees), <nnnn> its closure, the stress the G-W relation of its fabric."""
    startups, rotations = [], []
    strains_startup, strains_rotation = np.linspace(0.0, 5.0, 51), np.linspace(0.0, 2.0, 101)
    for seed, beta in ((1, 10.5), (2, 11.0), (3, 11.6)):
        steady = fabric_models.steady_state(fabric_models.GW, {"beta": beta}, PHI)
        startups.append(_frames(seed, 0.0, strains_startup, np.broadcast_to(steady, (51, 3, 3))))
        for theta in (0.0, 45.0, 90.0, 180.0):
            start = to_basis(steady, rotation_about_gradient(np.radians(theta)))
            path = fabric_models.integrate(
                fabric_models.GW, start, simple_shear_gradient(), strains_rotation, {"beta": beta}, PHI
            )
            rotations.append(_frames(seed, theta, strains_rotation, path))
    startup, rotation = pd.concat(startups, ignore_index=True), pd.concat(rotations, ignore_index=True)
    coefficient = {"a_H": 3.0, "a_C": 40.0}
    return startup, rotation, _stress(startup, coefficient), _stress(rotation, coefficient)


def test_a_g_w_simulation_has_no_error_to_take_apart(g_w_study):
    """Every variant under every criterion recovers each seed's beta (its steady state is G-W's own
    fixed point, where the 12 component of (1) vanishes), and has no error beyond the forcing's
    interpolation; the control (theta = 0) is scored and subtracted per seed."""
    scores, stress = ed.decompose(*g_w_study, PHI, (2.0, 5.0), 2.0)
    pairs = {(v, c) for c, variants in ed.CRITERIA.items() for v in variants}
    assert set(zip(scores["variant"], scores["criterion"])) == pairs
    assert set(scores["theta"]) == {0.0, 45.0, 90.0, 180.0}
    closure = scores[scores["variant"].isin(["closure", "closure_corrected", "closure_corrected_rates"])]
    assert closure["mse"].max() < 1e-20
    # the measured variants: only the forcing's linear interpolation, O(h^2) at h = 0.02, far below
    # the smallest error a real study gives (1e-2)
    assert scores["mse"].max() < 1e-5
    # the seeds differ: each floor (a between-seed variance, the mean of its per-seed pseudo-values) > 0
    rotated = scores[scores["theta"] != 0.0]
    assert rotated.groupby(["theta", "component", "variant", "criterion"])["floor"].mean().min() > 0.0
    np.testing.assert_allclose(scores["steady_residual"], 0.0, atol=1e-10)
    for (variant, criterion), rows in scores[scores["variant"] != "closure_corrected_rates"].groupby(
        ["variant", "criterion"]
    ):
        if variant == "measured_rates":
            continue
        rates = rows.groupby("seed")["beta_e"].first().to_numpy()
        np.testing.assert_allclose(rates, [10.5, 11.0, 11.6], rtol=1e-9, err_msg=f"{variant}, {criterion}")
    # the trace of (1): every single-rate steady state has Eh_e:<nn> = phi/6
    np.testing.assert_allclose(scores["steady_extension"], PHI / 6.0, rtol=1e-9)

    steady = stress[stress["theta"].isna()]
    np.testing.assert_allclose(steady["predicted"], steady["simulated"], rtol=1e-9, atol=1e-9)
    assert stress["mse"].max() < 1e-5

    table = ed.decomposition_table(scores)
    assert set(table["angles"]) == set(ed.ANGLE_GROUPS) and set(table["criterion"]) == set(ed.CRITERIA)
    # net of the floor, a perfect model scores minus the floor: the mean over seeds and angles
    pooled = scores[
        (scores["variant"] == "closure")
        & (scores["criterion"] == "balance")
        & (scores["component"] == "n12")
        & (scores["theta"] != 0.0)
    ]
    row = table[
        (table["angles"] == "all")
        & (table["variant"] == "closure")
        & (table["criterion"] == "balance")
        & (table["component"] == "n12")
    ].iloc[0]
    assert row["net_mse"] == pytest.approx((pooled["mse"] - pooled["floor"]).mean(), rel=1e-12)
    # net of the control: per seed, the mean over the rotations minus the seed's own theta = 0 score
    control = scores[
        (scores["variant"] == "closure")
        & (scores["criterion"] == "balance")
        & (scores["component"] == "n12")
        & (scores["theta"] == 0.0)
    ].set_index("seed")["mse"]
    expected = (pooled.groupby("seed")["mse"].mean() - control).mean()
    assert row["minus_control"] == pytest.approx(expected, rel=1e-9, abs=1e-30)
    control_rows = table[table["angles"] == ed.CONTROL]
    assert control_rows["difference"].isna().all()
    summary = ed.summary_markdown(table, ed.stress_decomposition_table(stress), scores)
    assert "Reading, plainly:" in summary and "<nn" not in summary and "theta" not in summary
    assert "control (θ = 0)" in summary and "Holm-adjusted" in summary


@pytest.mark.parametrize("model", ["gw", "gw_hybrid"])
def test_the_trace_of_a_single_rate_model_is_balanced_only_at_eh_e_nn_phi_over_6(model):
    """d tr<nn>/dgamma = -b_e Eh_e:<nn> + (phi/15)(b_c + 3a/2) whenever <nnnn> contracts to <nn>
    (the convection and 2 Eh:<nnnn> cancel in the trace; tr Eh_c = -1/2 in simple shear): with one
    rate beta, at any <nn> the model's trace rate is beta (phi/6 - Eh_e:<nn>), and every steady state
    has Eh_e:<nn> = phi/6 whatever beta."""
    fabric_model = fabric_models.resolve_models([model])[model]
    flow = fabric_models.flow_of(simple_shear_gradient())
    rng = np.random.default_rng(3)
    for beta in (4.0, 11.0, 40.0):
        params = {"beta": beta}
        for _ in range(3):
            root = rng.normal(size=(3, 3))
            fabric = root @ root.T / 3.0 + 0.2 * np.eye(3)
            rate = np.trace(fabric_model.rhs(fabric, flow, params, PHI))
            assert rate == pytest.approx(beta * (PHI / 6.0 - ed.steady_extension(fabric)), rel=1e-9, abs=1e-12)
        steady = fabric_models.steady_state(fabric_model, params, PHI)
        assert ed.steady_extension(steady) == pytest.approx(PHI / 6.0, rel=1e-9)


def test_the_corrected_closure_rate_puts_its_own_fixed_point_on_the_measured_n12():
    """corrected_fixed_point_beta: with the closure's steady error M - C(N) held, the fixed point of
    (1) at that beta has <nn>_12 = N_12 (and with no error it is G-W's own beta, fit_gw's)."""
    beta = 11.0
    steady = fabric_models.steady_state(fabric_models.GW, {"beta": beta}, PHI)
    assert ed.corrected_fixed_point_beta(steady, hinch_leal_closure(steady), PHI) == pytest.approx(beta, rel=1e-9)
    excess = np.zeros((3, 3, 3, 3))
    excess[0, 0, 0, 0] = excess[1, 1, 1, 1] = 0.02
    found = ed.corrected_fixed_point_beta(steady, hinch_leal_closure(steady) + excess, PHI)
    params = {"beta_e": found, "beta_c": found, "A": found}
    flow = fabric_models.flow_of(simple_shear_gradient())
    M, b = fabric_models.affine_system(fabric_models.SEPARATE_RATES, flow, params, PHI)
    forcing = -sym_to_vec(np.einsum("kl,ijkl->ij", ed.gw_drive(found), excess))
    fixed = vec_to_sym(np.linalg.solve(M, -(b + forcing)))
    assert fixed[0, 1] == pytest.approx(steady[0, 1], rel=1e-9) and found != pytest.approx(beta, rel=1e-3)


def test_tables_without_the_fourth_moment_are_refused_by_name(g_w_study):
    startup, rotation, stress_startup, stress_rotation = g_w_study
    bare = startup.drop(columns=list(FOURTH_MOMENT_COMPONENTS)).assign(
        **dict.fromkeys(FOURTH_MOMENT_COMPONENTS, np.nan)
    )
    with pytest.raises(ValueError, match="fourth moment"):
        ed.decompose(bare, rotation, stress_startup, stress_rotation, PHI, (2.0, 5.0), 2.0)
    missing = stress_rotation[stress_rotation["theta"] != 90.0]
    with pytest.raises(ValueError, match=r"seed 1, theta = 90: no stress table"):
        ed.decompose(startup, rotation, stress_startup, missing, PHI, (2.0, 5.0), 2.0)

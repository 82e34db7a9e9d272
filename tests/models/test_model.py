"""Tests of the G-W and modified G-W fabric models (suspension_fabric.models.gillissen_wilson).

Every expected value is either an analytic identity stated in the test docstring or
an independent computation (the explicit fourth-rank closure, scipy's solve_ivp).
"""

import itertools

import numpy as np
import pytest

from suspension_fabric.analysis import frames
from suspension_fabric.models import gillissen_wilson as model

RNG = np.random.default_rng(20261121)
PARAMS = [(10.9, None, 0.45), (9.4, 42.4, 0.45), (5.0, 20.0, 0.30), (3.5, 1.0, 0.55), (30.0, 2.0, 0.40)]
SHEAR = frames.simple_shear_gradient()


def random_fabric(scale=0.3):
    """A random symmetric positive-definite tensor, as a fabric."""
    a = RNG.normal(size=(3, 3))
    return scale * (a @ a.T + 0.5 * np.eye(3))


def random_rotation():
    q, r = np.linalg.qr(RNG.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def explicit_rhs(fabric, grad, beta, A, phi):
    """Eq. 2 written index by index with the full fourth-rank closure (independent of model)."""
    e = 0.5 * (grad + grad.T)
    gammadot = np.sqrt(2 * np.sum(e * e))
    lh, eh = grad / gammadot, e / gammadot
    w, v = np.linalg.eigh(eh)
    e_ext = sum(w[k] * np.outer(v[:, k], v[:, k]) for k in range(3) if w[k] > 0)
    e_comp = sum(w[k] * np.outer(v[:, k], v[:, k]) for k in range(3) if w[k] < 0)
    q = model.hinch_leal_closure(fabric)
    return (
        lh @ fabric
        + fabric @ lh.T
        - 2 * np.einsum("kl,ijkl->ij", lh, q)
        - beta * (np.einsum("kl,ijkl->ij", e_ext, q) + phi / 15 * 2 * e_comp)
        - A * phi / 15 * np.trace(e_comp) * np.eye(3)
    )


# ------------------------------------------------------------------ closure
def test_closure_contraction_returns_fabric():
    """<n_i n_j n_k n_k> = <n_i n_j> for every pair of contracted indices (any trace)."""
    fabric = random_fabric()
    q = model.hinch_leal_closure(fabric)
    for contraction in ("ijkk->ij", "ikjk->ij", "ikkj->ij", "kijk->ij", "kikj->ij", "kkij->ij"):
        np.testing.assert_allclose(np.einsum(contraction, q), fabric, atol=1e-14)


def test_closure_is_fully_symmetric():
    """<n_i n_j n_k n_l> is invariant under all 24 permutations of (i, j, k, l)."""
    q = model.hinch_leal_closure(random_fabric())
    for perm in itertools.permutations(range(4)):
        np.testing.assert_allclose(np.transpose(q, perm), q, atol=1e-15)


def test_closure_exact_for_isotropic_fabric():
    """For <nn> = c delta the closure equals the isotropic moment (c/5)(d_ij d_kl + d_ik d_jl + d_il d_jk)."""
    c = 0.7
    eye = np.eye(3)
    iso = np.einsum("ij,kl->ijkl", eye, eye) + np.einsum("ik,jl->ijkl", eye, eye) + np.einsum("il,jk->ijkl", eye, eye)
    np.testing.assert_allclose(model.hinch_leal_closure(c * eye), c / 5 * iso, atol=1e-15)


def test_contract_closure_matches_full_tensor():
    """The expanded contraction T:<nnnn> equals T_kl <n_i n_j n_k n_l> for a non-symmetric T."""
    fabric, tensor = random_fabric(), RNG.normal(size=(3, 3))
    expected = np.einsum("kl,ijkl->ij", tensor, model.hinch_leal_closure(fabric))
    np.testing.assert_allclose(model.contract_closure(tensor, fabric), expected, atol=1e-14)


# --------------------------------------------------------------- kinematics
def test_simple_shear_split():
    """L = e1 e2: gammadot = 1, Eh_e = (1/2) v_e v_e, Eh_c = -(1/2) v_c v_c with v_e,c = (e1 +- e2)/sqrt 2."""
    _, eh, e_ext, e_comp, gammadot = model.split_strain_rate(3.0 * SHEAR)
    assert gammadot == pytest.approx(3.0)
    v_e, v_c = np.array([1, 1, 0]) / np.sqrt(2), np.array([1, -1, 0]) / np.sqrt(2)
    np.testing.assert_allclose(e_ext, 0.5 * np.outer(v_e, v_e), atol=1e-15)
    np.testing.assert_allclose(e_comp, -0.5 * np.outer(v_c, v_c), atol=1e-15)
    np.testing.assert_allclose(e_ext + e_comp, eh, atol=1e-15)


def test_uniaxial_compression_has_two_extensional_directions():
    """L = diag(-1, 1/2, 1/2): Eh_c is along e1 only and Eh_e spans e2, e3 (general split)."""
    _, _, e_ext, e_comp, _ = model.split_strain_rate(np.diag([-1.0, 0.5, 0.5]))
    assert np.count_nonzero(np.abs(np.diag(e_ext)) > 1e-12) == 2
    assert np.count_nonzero(np.abs(np.diag(e_comp)) > 1e-12) == 1 and e_comp[0, 0] < 0


def test_rhs_is_rate_independent():
    """d<nn>/dgamma depends on L only through L / gammadot."""
    fabric = random_fabric()
    np.testing.assert_allclose(
        model.fabric_rhs(fabric, 7.5 * SHEAR, 9.4, 42.4, 0.45), model.fabric_rhs(fabric, SHEAR, 9.4, 42.4, 0.45)
    )


# --------------------------------------------------------------- equations
@pytest.mark.parametrize("beta, A, phi", PARAMS)
def test_rhs_matches_explicit_equation(beta, A, phi):
    """fabric_rhs equals Eq. 2 written out with the full closure, for a random fabric and flow."""
    fabric, grad = random_fabric(), RNG.normal(size=(3, 3))
    grad -= np.trace(grad) / 3 * np.eye(3)
    A_value = beta if A is None else A
    np.testing.assert_allclose(
        model.fabric_rhs(fabric, grad, beta, A, phi), explicit_rhs(fabric, grad, beta, A_value, phi), atol=1e-13
    )


def test_A_equal_beta_is_gillissen_wilson():
    """Eq. 2 with A = beta is Eq. 1: -beta((phi/15)(2 Eh_c + Tr(Eh_c) delta)) as one term."""
    fabric, beta, phi = random_fabric(), 7.3, 0.41
    _, _, e_ext, e_comp, _ = model.split_strain_rate(SHEAR)
    q = model.hinch_leal_closure(fabric)
    eq1 = (
        SHEAR @ fabric
        + fabric @ SHEAR.T
        - 2 * np.einsum("kl,ijkl->ij", SHEAR, q)
        - beta * (np.einsum("kl,ijkl->ij", e_ext, q) + phi / 15 * (2 * e_comp + np.trace(e_comp) * np.eye(3)))
    )
    np.testing.assert_allclose(model.fabric_rhs(fabric, SHEAR, beta, None, phi), eq1, atol=1e-14)
    np.testing.assert_allclose(model.fabric_rhs(fabric, SHEAR, beta, beta, phi), eq1, atol=1e-14)


def test_trace_balance():
    """Convection conserves Tr<nn>: d Tr<nn>/dgamma = -beta Eh_e:<nn> - (phi/15)(2 beta + 3 A) Tr(Eh_c)."""
    fabric, beta, A, phi = random_fabric(), 6.0, 25.0, 0.45
    grad = RNG.normal(size=(3, 3))
    grad -= np.trace(grad) / 3 * np.eye(3)
    _, _, e_ext, e_comp, _ = model.split_strain_rate(grad)
    expected = -beta * np.sum(e_ext * fabric) - phi / 15 * (2 * beta + 3 * A) * np.trace(e_comp)
    assert np.trace(model.fabric_rhs(fabric, grad, beta, A, phi)) == pytest.approx(expected, rel=1e-12)


# --------------------------------------------------------------- steady state
@pytest.mark.parametrize("beta, A, phi", PARAMS)
def test_steady_state_is_ode_fixed_point(beta, A, phi):
    """The (label-corrected) closed form equals the fixed point -M^-1 b, where the rhs vanishes,
    and a long solve_ivp integration from no contacts converges to it."""
    closed = model.steady_state(beta, A, phi)
    fixed = model.steady_state_ode(beta, A, phi)
    np.testing.assert_allclose(closed, fixed, atol=1e-13)
    np.testing.assert_allclose(model.fabric_rhs(closed, SHEAR, beta, A, phi), 0.0, atol=1e-13)
    long_run = model.integrate_fabric_ode(np.zeros((3, 3)), SHEAR, np.array([0.0, 300.0]), beta, A, phi)[-1]
    np.testing.assert_allclose(long_run, fixed, atol=1e-9)


@pytest.mark.parametrize("beta, A, phi", PARAMS)
def test_printed_closed_form_has_22_and_33_exchanged(beta, A, phi):
    """Paper's printed 11 and 12 match Eq. 2's fixed point; its 22 is the fixed point's 33 and vice versa."""
    printed = model.steady_state(beta, A, phi, as_printed=True)
    fixed = model.steady_state_ode(beta, A, phi)
    np.testing.assert_allclose(printed[[0, 0], [0, 1]], fixed[[0, 0], [0, 1]], atol=1e-13)
    np.testing.assert_allclose(printed[1, 1], fixed[2, 2], atol=1e-13)
    np.testing.assert_allclose(printed[2, 2], fixed[1, 1], atol=1e-13)
    assert abs(printed[1, 1] - fixed[1, 1]) > 1e-3  # the labels really differ for these parameters


def test_steady_state_symmetry_and_sign():
    """Simple shear: <nn>_13 = <nn>_23 = 0 by symmetry and <nn>_12 < 0 (contacts along e1 - e2) for beta > 3."""
    fabric = model.steady_state_ode(10.9, None, 0.45)
    assert fabric[0, 2] == pytest.approx(0, abs=1e-15) and fabric[1, 2] == pytest.approx(0, abs=1e-15)
    assert fabric[0, 1] < 0 and model.is_stable(10.9)


# --------------------------------------------------------------- integration
def test_exact_integration_matches_solve_ivp():
    """expm propagation equals scipy DOP853 integration of the rhs, random fabric and flow direction."""
    fabric0, grad = random_fabric(), random_rotation() @ SHEAR @ random_rotation().T
    strains = np.linspace(0, 4, 21)
    exact = model.integrate_fabric(fabric0, grad, strains, 9.4, 42.4, 0.45)
    reference = model.integrate_fabric_ode(fabric0, grad, strains, 9.4, 42.4, 0.45)
    np.testing.assert_allclose(exact, reference, atol=1e-9)


def test_integration_is_batched_over_flows_and_fabrics():
    """A batch of (fabric, L) pairs gives the same as integrating each pair alone."""
    fabrics = np.stack([random_fabric() for _ in range(4)])
    grads = np.stack([random_rotation() @ SHEAR @ random_rotation().T for _ in range(4)])
    strains = np.linspace(0, 2, 5)
    batch = model.integrate_fabric(fabrics, grads, strains, 10.9, None, 0.45)
    assert batch.shape == (4, 5, 3, 3)
    for k in range(4):
        np.testing.assert_allclose(batch[k], model.integrate_fabric(fabrics[k], grads[k], strains, 10.9, None, 0.45))


def test_frame_indifference():
    """Rotating flow and initial fabric by Q rotates the solution: X[Q X0 Q^T, Q L Q^T] = Q X[X0, L] Q^T."""
    q = random_rotation()
    fabric0 = random_fabric()
    strains = np.linspace(0, 3, 7)
    plain = model.integrate_fabric(fabric0, SHEAR, strains, 9.4, 42.4, 0.45)
    rotated = model.integrate_fabric(q @ fabric0 @ q.T, q @ SHEAR @ q.T, strains, 9.4, 42.4, 0.45)
    np.testing.assert_allclose(rotated, q @ plain @ q.T, atol=1e-12)


# ------------------------------------------------------------ shear rotation
def test_rotation_equals_integration_under_rotated_flow():
    """shear_rotation = integrating the lab-frame fabric under L' = e1' e2, then reading it in (e1', e2, e3')."""
    theta, strains = 1.1, np.linspace(0, 3, 13)
    before = model.startup_shear(np.array([5.0]), 9.4, 42.4, 0.45)[0]
    basis = frames.rotation_about_gradient(theta)  # rows e1', e2, e3'
    lab_gradient = np.outer(basis[0], basis[1])  # gammadot e1' e2
    lab = model.integrate_fabric(before, lab_gradient, strains, 9.4, 42.4, 0.45)
    np.testing.assert_allclose(
        model.shear_rotation(theta, strains, 9.4, 42.4, 0.45), frames.to_basis(lab, basis), atol=1e-12
    )


@pytest.mark.parametrize("beta, A", [(10.9, None), (9.4, 42.4)])
def test_rotation_parity(beta, A):
    """<nn>'_12 (and diagonal) are even in theta, <nn>'_23 and <nn>'_13 odd (mirror e3 -> -e3)."""
    thetas = np.deg2rad(np.arange(0, 181, 15))
    strains = np.linspace(0, 5, 26)
    plus = model.shear_rotation(thetas, strains, beta, A, 0.45)
    minus = model.shear_rotation(-thetas, strains, beta, A, 0.45)
    for i, j in [(0, 0), (1, 1), (2, 2), (0, 1)]:
        np.testing.assert_allclose(minus[..., i, j], plus[..., i, j], atol=1e-12)
    for i, j in [(1, 2), (0, 2)]:
        np.testing.assert_allclose(minus[..., i, j], -plus[..., i, j], atol=1e-12)
    assert np.abs(plus[..., 1, 2]).max() > 0.01  # the odd components are not trivially zero


def test_values_just_after_rotation():
    """From the steady state: <nn>'_12 = cos(theta) <nn>_12^ss and <nn>'_23 = sin(theta) <nn>_12^ss at 0+."""
    beta, A, phi = 9.4, 42.4, 0.45
    steady = model.steady_state_ode(beta, A, phi)
    thetas = np.deg2rad(np.arange(-180, 181, 5))
    after = model.shear_rotation(thetas, np.array([0.0, 50.0]), beta, A, phi, startup_strain=3.0, fabric0=steady)
    np.testing.assert_allclose(after[:, 0, 0, 1], np.cos(thetas) * steady[0, 1], atol=1e-13)
    np.testing.assert_allclose(after[:, 0, 1, 2], np.sin(thetas) * steady[0, 1], atol=1e-13)
    np.testing.assert_allclose(after[:, 1], np.broadcast_to(steady, after[:, 1].shape), atol=1e-8)  # recovers


def test_reversal_flips_shear_component():
    """theta = pi is a shear reversal: <nn>'_12 = -<nn>_12^ss just after, and the transient is non-monotonic in Z."""
    steady = model.steady_state_ode(10.9, None, 0.45)
    after = model.shear_rotation(np.pi, np.linspace(0, 5, 51), 10.9, None, 0.45, fabric0=steady)
    assert after[0, 0, 1] == pytest.approx(-steady[0, 1], abs=1e-13)
    traces = np.trace(after, axis1=-2, axis2=-1)
    assert traces.min() < np.trace(steady) - 1e-3  # contacts are lost, then rebuilt


# -------------------------------------------------------------------- fits
@pytest.mark.parametrize("beta", [4.0, 10.9, 50.0])
def test_fit_gw_recovers_beta(beta):
    """fit_gw(<nn>_12^ss(beta), phi) = beta."""
    n12 = model.steady_state_ode(beta, None, 0.45)[0, 1]
    assert model.fit_gw(n12, 0.45) == pytest.approx(beta, rel=1e-9)


@pytest.mark.parametrize("beta, A", [(9.4, 42.4), (10.9, 10.9), (6.0, 3.0), (20.0, 100.0)])
def test_fit_modified_recovers_parameters(beta, A):
    """fit_modified(<nn>_11^ss, <nn>_12^ss, phi) = (beta, A), despite the spurious pole at beta = 8."""
    steady = model.steady_state_ode(beta, A, 0.45)
    fit_beta, fit_A = model.fit_modified(steady[0, 0], steady[0, 1], 0.45)
    assert fit_beta == pytest.approx(beta, rel=1e-8) and fit_A == pytest.approx(A, rel=1e-8)


def test_fits_reproduce_paper_parameters():
    """The paper's reported parameters are self-consistent: the steady state of (9.4, 42.4) has
    nearly the same <nn>_12 as G-W at 10.9, as both were fitted to one simulated <nn>_12."""
    n12_mod = model.steady_state_ode(9.4, 42.4, 0.45)[0, 1]
    assert model.fit_gw(n12_mod, 0.45) == pytest.approx(10.9, abs=0.1)


# --------------------------------------------------------------- bad inputs
@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: model.steady_state(10.0, None, -0.1), "phi"),
        (lambda: model.steady_state(10.0, None, 1.2), "phi"),
        (lambda: model.steady_state(-1.0, None, 0.45), "beta"),
        (lambda: model.steady_state(np.nan, None, 0.45), "beta"),
        (lambda: model.fabric_rhs(np.full((3, 3), np.nan), SHEAR, 10.0), "fabric"),
        (lambda: model.fabric_rhs(np.arange(9.0).reshape(3, 3), SHEAR, 10.0), "symmetric"),
        (lambda: model.fabric_rhs(np.eye(3), np.zeros((3, 3)), 10.0), "gammadot"),
        (lambda: model.integrate_fabric(np.eye(3), SHEAR, np.array([-1.0, 1.0]), 10.0), "strains"),
        (lambda: model.fit_gw(np.inf, 0.45), "n12"),
        (lambda: model.fit_gw(-0.1, -0.45), "phi"),
        (lambda: model.fit_gw(0.05, 0.45), "negative"),
        (lambda: model.fit_gw(-0.5, 0.45), "G-W can only reach"),
        (lambda: model.fit_modified(-0.2, -0.1, 0.45), "_11"),
        (lambda: model.fit_modified(0.05, -0.2, 0.45), "no stable, physical"),
        (lambda: model.shear_rotation(0.1, np.linspace(0, 1, 3), 10.0, startup_strain=np.nan), "startup_strain"),
    ],
)
def test_bad_inputs_raise_clear_errors(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_gw_shear_limit_matches_ode():
    """The bound quoted by fit_gw, <nn>_12^ss / phi -> -28/45 as beta -> infinity, holds for the ODE fixed point."""
    assert model.steady_state_ode(1e7, None, 0.45)[0, 1] / 0.45 == pytest.approx(-model._GW_N12_LIMIT, rel=1e-5)

"""Absolute values of the shear, pump and rotation resistances of pair_style lubricate/sf.

The plugin tests in test_lammps_plugin.py check the squeeze force against Reynolds' formula
and the other modes only through identities (Newton's third law, angular momentum at
contact, rigid rotation), which a factor common to all of them would survive. Here two
spheres at a known gap slide past each other or one of them spins, in still fluid (no fix:
no drag, no imposed flow), and ``run 0`` gives the force and torque on each sphere, which
are compared with the leading-order near-field resistance matrix of Jeffrey & Onishi (1984)
written out below from the textbook (Kim & Karrila 1991, ch. 11), not from the plugin.

Reference (sphere 1 = atom 1 of radius a1, sphere 2 = atom 2 of radius a2):
    d = (x2 - x1)/|x2 - x1|,  lambda = a2/a1,  xi = 2 (r - a1 - a2)/(a1 + a2),
    L = log(1/xi_r),  xi_r = max(xi, 0) + delta,  everything 0 for xi >= h_out.
    (F1, F2, T1, T2) = -R (U1, U2, W1, W2),  R = [[A, B^T], [B, C]] (symmetric, 12 x 12), with
    A_ab = 3 pi mu (a_a + a_b)   [X^A_ab dd + Y^A_ab (I - dd)]
    B_ab = pi mu (a_a + a_b)^2   Y^B_ab eps.d          ((eps.d)_ij = eps_ijk d_k)
    C_ab = pi mu (a_a + a_b)^3   [X^C_ab dd + Y^C_ab (I - dd)]
    and the singular parts (J&O 1984; K&K Tables 11.3-11.12):
      X^A_11 = g1/xi,                     g1    = 2 l^2/(1+l)^3
      Y^A_11 = g2A L,                     g2A   = (4/15) l (2 + l + 2 l^2)/(1+l)^3
      Y^B_11 = g2B L,                     g2B   = -(1/5) l (4 + l)/(1+l)^2
      Y^C_11 = g2C L,                     g2C   = (2/5) l/(1+l)
      -(1/2)(1+l) X^A_12 = g1/xi,  -(1/2)(1+l) Y^A_12 = g2A L,  -(1/4)(1+l)^2 Y^B_12 = g2B L,
      Y^C_12 = g4C L,                     g4C   = (4/5) l^2/(1+l)^4
      X^C: no singular term (twist is left out, as in Mari et al. 2014),
    the 22 and 21 functions from f_ab(l) = f_(3-a)(3-b)(1/l) (A and C) and
    Y^B_ab(l) = -Y^B_(3-a)(3-b)(1/l) (the direction d flips).
Regularisation (delta) and cutoff (h_out) are the model's, as documented in
simulation/lammps/plugin_source/README.md.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_lammps_plugin import DELTA, ETA_F, H_OUT, make_system

from suspension_fabric.simulation.lammps import plugin_path

pytestmark = pytest.mark.lammps

LEVI_CIVITA = np.zeros((3, 3, 3))
for _i, _j, _k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    LEVI_CIVITA[_i, _j, _k], LEVI_CIVITA[_i, _k, _j] = 1.0, -1.0


@pytest.fixture(scope="module", autouse=True)
def built_plugin():
    return plugin_path()


# ----------------------------------------------------------- Jeffrey & Onishi (1984)


def _g1(l):
    return 2.0 * l**2 / (1.0 + l) ** 3


def _g2_ya(l):
    return 4.0 / 15.0 * l * (2.0 + l + 2.0 * l**2) / (1.0 + l) ** 3


def _g2_yb(l):
    return -0.2 * l * (4.0 + l) / (1.0 + l) ** 2


def _g2_yc(l):
    return 0.4 * l / (1.0 + l)


def _g4_yc(l):
    return 0.8 * l**2 / (1.0 + l) ** 4


def _functions_11_12(l, xi_r):
    """Dimensionless (X^A, Y^A, Y^B, X^C, Y^C) for (a, b) = (1, 1) and (1, 2) at size ratio l."""
    log_term = np.log(1.0 / xi_r)
    f11 = dict(XA=_g1(l) / xi_r, YA=_g2_ya(l) * log_term, YB=_g2_yb(l) * log_term, XC=0.0, YC=_g2_yc(l) * log_term)
    f12 = dict(
        XA=-2.0 / (1.0 + l) * _g1(l) / xi_r,
        YA=-2.0 / (1.0 + l) * _g2_ya(l) * log_term,
        YB=-4.0 / (1.0 + l) ** 2 * _g2_yb(l) * log_term,
        XC=0.0,
        YC=_g4_yc(l) * log_term,
    )
    return f11, f12


def jeffrey_onishi_resistance(a1, a2, d, gap, mu=ETA_F, delta=DELTA, h_out=H_OUT):
    """12 x 12 grand resistance matrix R of the pair (see the module docstring), or zeros."""
    xi = 2.0 * gap / (a1 + a2)
    R = np.zeros((12, 12))
    if xi >= h_out:
        return R
    xi_r = max(xi, 0.0) + delta
    l = a2 / a1
    dd = np.outer(d, d)
    perp = np.eye(3) - dd
    eps_d = np.einsum("ijk,k->ij", LEVI_CIVITA, d)
    f11, f12 = _functions_11_12(l, xi_r)
    f22, f21 = _functions_11_12(1.0 / l, xi_r)  # f_ab(l) = f_(3-a)(3-b)(1/l) ...
    f22["YB"], f21["YB"] = -f22["YB"], -f21["YB"]  # ... with a sign flip for Y^B
    functions = {(0, 0): f11, (0, 1): f12, (1, 0): f21, (1, 1): f22}
    radii = (a1, a2)
    for (a, b), f in functions.items():
        s = radii[a] + radii[b]
        A = 3.0 * np.pi * mu * s * (f["XA"] * dd + f["YA"] * perp)
        B = np.pi * mu * s**2 * f["YB"] * eps_d
        C = np.pi * mu * s**3 * (f["XC"] * dd + f["YC"] * perp)
        R[3 * a : 3 * a + 3, 3 * b : 3 * b + 3] = A
        R[6 + 3 * a : 9 + 3 * a, 3 * b : 3 * b + 3] = B
        R[6 + 3 * a : 9 + 3 * a, 6 + 3 * b : 9 + 3 * b] = C
    R[:6, 6:] = R[6:, :6].T  # B~ = B^T: the grand resistance matrix is symmetric
    return R


def test_reference_matrix_is_symmetric_and_matches_the_reynolds_squeeze():
    """Self-check of the reference: R = R^T (reciprocal theorem) needs A_21 = A_12^T and
    C_21 = C_12^T from the l -> 1/l relations, and its squeeze block gives
    F = 6 pi mu (a1 a2/(a1+a2))^2 V/h_r (h_r = (a1+a2) xi_r/2) for spheres closing at speed V."""
    a1, a2, gap = 0.5, 0.9, 0.003
    d = np.array([0.0, 0.6, 0.8])
    R = jeffrey_onishi_resistance(a1, a2, d, gap)
    np.testing.assert_allclose(R, R.T, rtol=0, atol=1e-12 * np.abs(R).max())
    velocities = np.concatenate([0.2 * d, -0.3 * d, np.zeros(6)])
    force_1 = -(R @ velocities)[:3]
    h_r = 0.5 * (a1 + a2) * (2 * gap / (a1 + a2) + DELTA)
    expected = 6 * np.pi * ETA_F * (a1 * a2 / (a1 + a2)) ** 2 * 0.5 / h_r
    np.testing.assert_allclose(force_1, -expected * d, rtol=1e-12)


# ------------------------------------------------------------------- LAMMPS values

SIZE_RATIOS = [1.0, 1.4, 0.4]  # a2/a1 with a1 = 0.5: equal, larger second, smaller second
REDUCED_GAPS = [-0.002, 0.0005, 0.01, 0.049, 0.06]  # overlap, near, mid, at the cutoff, beyond


def lammps_forces_and_torques(a1, a2, d, gap, u1, u2, w1, w2):
    """Force and torque on each sphere from `run 0` (pair lubricate/sf only, no fix)."""
    x1 = np.array([4.0, 4.5, 5.0])
    x2 = x1 + (a1 + a2 + gap) * d
    lmp = make_system([(*x1, 2 * a1, u1, w1), (*x2, 2 * a2, u2, w2)])
    lmp.command("run 0 post no")
    nlocal = lmp.extract_global("nlocal")
    order = np.argsort(lmp.numpy.extract_atom("id")[:nlocal])
    f = lmp.numpy.extract_atom("f")[:nlocal][order].copy()
    t = lmp.numpy.extract_atom("torque")[:nlocal][order].copy()
    lmp.close()
    return f, t


def unit(vector):
    vector = np.asarray(vector, dtype=float)
    return vector / np.linalg.norm(vector)


def check_against_reference(size_ratio, reduced_gap, velocities):
    a1, a2 = 0.5, 0.5 * size_ratio
    d = unit([1.0, -2.0, 0.7])
    gap = 0.5 * reduced_gap * (a1 + a2)
    u1, u2, w1, w2 = (np.asarray(v, dtype=float) for v in velocities(d))
    f, t = lammps_forces_and_torques(a1, a2, d, gap, u1, u2, w1, w2)
    expected = -jeffrey_onishi_resistance(a1, a2, d, gap) @ np.concatenate([u1, u2, w1, w2])
    expected_f, expected_t = expected[:6].reshape(2, 3), expected[6:].reshape(2, 3)
    scale = np.abs(expected).max()
    if reduced_gap >= H_OUT:
        assert scale == 0.0
        np.testing.assert_array_equal(f, 0.0)
        np.testing.assert_array_equal(t, 0.0)
        return
    np.testing.assert_allclose(f, expected_f, rtol=1e-9, atol=1e-11 * scale)
    np.testing.assert_allclose(t, expected_t, rtol=1e-9, atol=1e-11 * scale)
    return expected_f, expected_t


@pytest.mark.parametrize("size_ratio", SIZE_RATIOS)
@pytest.mark.parametrize("reduced_gap", REDUCED_GAPS)
def test_sliding_pair_matches_jeffrey_onishi(size_ratio, reduced_gap):
    """Sphere 1 slides with U1 = 0.7 t1, sphere 2 with U2 = -0.4 t2 (t1, t2 two different unit
    vectors perpendicular to d), no spin: the shear (A) and pump (B) blocks alone give
    F1 = -6 pi mu a1 Y^A_11 U1 - 3 pi mu (a1+a2) Y^A_12 U2 = -6 pi mu a1 g2A L (U1 - U2) = -F2,
    T1 = -4 pi mu a1^2 Y^B_11 U1 x d - pi mu (a1+a2)^2 Y^B_12 U2 x d,
    T2 = -pi mu (a1+a2)^2 Y^B_21 U1 x d - 4 pi mu a2^2 Y^B_22 U2 x d
    (and no normal force), matched to 1e-9 relative; zero beyond h_out."""

    def velocities(d):
        t1 = unit(np.cross(d, [0.0, 0.0, 1.0]))
        t2 = unit(np.cross(d, t1) + 0.5 * t1)
        return 0.7 * t1, -0.4 * t2, np.zeros(3), np.zeros(3)

    result = check_against_reference(size_ratio, reduced_gap, velocities)
    if result is not None:  # the check is not empty: a sizeable shear force and pump torque
        expected_f, expected_t = result
        assert np.linalg.norm(expected_f[0]) > 10.0 and np.linalg.norm(expected_t[1]) > 1.0


@pytest.mark.parametrize("size_ratio", SIZE_RATIOS)
@pytest.mark.parametrize("reduced_gap", REDUCED_GAPS)
@pytest.mark.parametrize("spinning", [1, 2])
def test_spinning_sphere_matches_jeffrey_onishi(size_ratio, reduced_gap, spinning):
    """One sphere spins with W = 1.3 w (w a unit vector with a component along d, which the
    twist-free model ignores), both at rest: the pump (B^T) and rotation (C) blocks give, for
    sphere 1 spinning, F1 = -4 pi mu a1^2 Y^B_11 d x W = -F2 (to leading order),
    T1 = -8 pi mu a1^3 Y^C_11 (I - dd) W, T2 = -pi mu (a1+a2)^3 Y^C_21 (I - dd) W, and the
    images under 1 <-> 2 for sphere 2 spinning; matched to 1e-9 relative; zero beyond h_out."""

    def velocities(d):
        w = 1.3 * unit([0.3, 1.0, -0.4])
        zero = np.zeros(3)
        return (zero, zero, w, zero) if spinning == 1 else (zero, zero, zero, w)

    result = check_against_reference(size_ratio, reduced_gap, velocities)
    if result is not None:
        expected_f, expected_t = result
        assert np.linalg.norm(expected_f[0]) > 1.0 and np.linalg.norm(expected_t, axis=1).min() > 0.1


def test_general_motion_of_unequal_pair_matches_jeffrey_onishi():
    """Random velocities and spins of both spheres (a2/a1 = 1.4, xi = 0.004): the whole
    leading-order matrix at once, F = -R U with the squeeze, shear, pump and rotation blocks
    (X^A_11 = g1/xi only: the model keeps the 1/xi term of the squeeze, as Mari et al. 2014)."""
    rng = np.random.default_rng(3)
    u1, u2, w1, w2 = rng.normal(size=(4, 3))
    check_against_reference(1.4, 0.004, lambda d: (u1, u2, w1, w2))

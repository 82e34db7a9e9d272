"""Rotary shear for real: segments whose flow direction turns (turning_deg_per_strain != 0), run
through simulation/lammps/inputs/segment.lmp with the project's plugin force model.

A rotary segment turns the flow direction f(t) = (cos t, sin t, 0) (simulation frame, z the
gradient) as t(gamma) = t0 + w gamma, gamma the strain since the segment started, w the turning
rate in radians per unit strain; segment.lmp imposes it with ``fix deform ... xz variable ...
yz variable ...`` and the plugin reads the velocity gradient L = gammadot f e_z from the box
rates: u_inf(x) = gammadot (z - zlo) f, Omega_inf = (gammadot/2) e_z x f = (gammadot/2)
(-sin t, cos t, 0), E = (gammadot/2)(f e_z + e_z f).

The runs go through :func:`run_segment` (tilts, resume) or through the very command it builds,
``lammps_command(segment.lmp, variables)`` with the same variables (:func:`run_segment_script`),
when a test needs the velocities and spins of the spheres: then ``lammps_dir`` (segment.lmp's
documented folder of its included scripts) points to a folder whose shear_defaults.lmp and
forces_sf.lmp include the project's own and whose shear_run.lmp adds a dump of x, v and omega
before including the project's shear_run.lmp; segment.lmp itself runs unchanged.

Systems of 1 to 3 spheres in small periodic boxes, hand-written data files, 10^3 to 10^4
implicit steps (fix hydro/implicit/sf, solved to 1e-12: one CG iteration for these pair
graphs); about a second of LAMMPS each.
Units: strain rate 1, d_small = 1, rho = 1, time = strain.

The first step of each launch of a rotary segment sees the imposed flow only through the
plugin's fix flow_rate/sf (fix deform gives 'variable' tilts their rates at the end of the first
step): test_first_step_of_a_rotary_segment_feels_the_imposed_flow and the resume test check it.
"""

from __future__ import annotations

import json
import os
import signal
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_lubrication_values import jeffrey_onishi_resistance

from suspension_fabric.io.dumpio import iter_dump_frames, iter_frame_blocks
from suspension_fabric.io.protocols import Segment
from suspension_fabric.io.resources import LAMMPS_SCRIPTS_DIR
from suspension_fabric.simulation.lammps import (
    COMPLETION_MARKER,
    ForceModel,
    LammpsRunError,
    ShearSettings,
    read_stress_table,
    run_segment,
)
from suspension_fabric.simulation.lammps.plugin import plugin_path
from suspension_fabric.simulation.lammps.process import failure_reason, lammps_command, lammps_processes_in, launch

pytestmark = pytest.mark.lammps


@pytest.fixture(scope="module")
def force_model():
    # a tight implicit solve, so that the comparisons below see the dynamics, not the solver
    return ForceModel(plugin=plugin_path(), solver_tol=1e-12)


# ------------------------------------------------------------------------------- helpers


def write_data(path, spheres, box, tilt=(0.0, 0.0, 0.0)):
    """A LAMMPS data file (atom style sphere, density 1, at rest) of ``spheres`` = [(diameter,
    x, y, z), ...] in the box 0..lx, 0..ly, 0..lz with tilts (xy, xz, yz); type 1 = d < 1.2, 2 = larger."""
    (lx, ly, lz), (xy, xz, yz) = (float(v) for v in box), (float(v) for v in tilt)
    lines = [
        "spheres written by tests/simulation/test_lammps_rotary.py",
        "",
        f"{len(spheres)} atoms",
        "2 atom types",
        "",
    ]
    lines += [f"0 {lx!r} xlo xhi", f"0 {ly!r} ylo yhi", f"0 {lz!r} zlo zhi", f"{xy!r} {xz!r} {yz!r} xy xz yz"]
    lines += ["", "Atoms # sphere", ""]
    for atom_id, (diameter, x, y, z) in enumerate(spheres, start=1):
        diameter, x, y, z = (float(value) for value in (diameter, x, y, z))
        lines.append(f"{atom_id} {1 if diameter < 1.2 else 2} {diameter!r} 1 {x!r} {y!r} {z!r} 0 0 0")
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


def run_segment_script(workdir: Path, segment: Segment, data_file: Path, force_model, settings, motion_every: int):
    """segment.lmp from the packing ``data_file`` with the variables run_segment passes, plus a dump
    ``motion.dump`` (id type radius x y z xu yu zu vx vy vz omegax omegay omegaz) every
    ``motion_every`` steps; returns the run's folder."""
    hook = workdir / "lammps"
    hook.mkdir(parents=True)
    for name in ("shear_defaults.lmp", "forces_sf.lmp"):
        (hook / name).write_text(f"include {LAMMPS_SCRIPTS_DIR / name}\n")
    (hook / "shear_run.lmp").write_text(
        f"dump motion all custom {motion_every} motion.dump id type radius x y z xu yu zu "
        "vx vy vz omegax omegay omegaz\n"
        "dump_modify motion sort id format float %.17g\n"
        f"include {LAMMPS_SCRIPTS_DIR / 'shear_run.lmp'}\n"
    )
    variables = {
        "lammps_dir": str(hook),
        "start_from": "packing",
        "start_file": str(data_file),
        "segment_index": "0",
        "flow_angle_deg": repr(segment.flow_angle_deg),
        "turning_deg_per_strain": repr(segment.turning_deg_per_strain),
        **force_model.variables(),
        **settings.variables(),
        "strain_total": repr(segment.strain),
    }
    result = launch(lammps_command(LAMMPS_SCRIPTS_DIR / "segment.lmp", variables), workdir)
    reason = failure_reason(result, "SHEAR_RUN_COMPLETE")
    assert reason is None, f"{reason}\n{result.watcher.tail()}"
    return workdir


def read_motion(path):
    """{step: (zlo, {column: values sorted by id})} of a motion dump."""
    frames = {}
    for step, lines in iter_frame_blocks(path):
        zlo = float(lines[7].split()[0])
        columns = lines[8].split()[2:]
        table = np.loadtxt(lines[9:], ndmin=2)
        table = table[np.argsort(table[:, columns.index("id")])]
        frames[step] = (zlo, {name: table[:, k] for k, name in enumerate(columns)})
    return frames


def vectors(atoms, *names):
    return np.column_stack([atoms[name] for name in names])


def flow_direction(t):
    """f(t) and e_z x f(t) for angles t (radians), shape (..., 3)."""
    t = np.asarray(t, dtype=float)
    zero = np.zeros_like(t)
    return np.stack([np.cos(t), np.sin(t), zero], -1), np.stack([-np.sin(t), np.cos(t), zero], -1)


# ------------------------------------------------------------------ 1. the box follows the flow


def test_box_tilts_follow_the_turning_flow(tmp_path, force_model):
    """The tilts of a rotary segment integrate the turning tilt rates gammadot lz (cos t, sin t):
    xz(gamma) = xz0 + lz (sin t - sin t0)/w and yz(gamma) = yz0 - lz (cos t - cos t0)/w (w in
    radians per strain), up to box flips, which change xz by a multiple of lx and yz by one of ly
    (xy = 0), and keep |xz| <= lx/2, |yz| <= ly/2 (within the one step a flip waits for).
    Checked on every row of the stress table (to 1e-10 d, the table's 12 digits) for a
    segment from a packing in a tilted 4 x 7 x 5 box (2 strain at 90 deg/strain from t0 = 30
    deg: xz and yz both flip) and for the segment continuing from its checkpoint (1.5 strain
    at -120 deg/strain from t0 = 210 deg), whose tilts start where the first ended. One
    sphere; dt = 1e-3 (the box is a prescribed function of the step, and the implicit drag of a
    lone sphere is stable at any dt)."""
    box, tilt = (4.0, 7.0, 5.0), (0.0, 1.0, -0.5)
    data = write_data(tmp_path / "one.data", [(1.0, 1.0, 2.0, 2.5)], box, tilt)
    settings = ShearSettings(
        dt=1e-3, dump_strain=0.1, table_strain=0.01, thermo_strain=0.1, restart_strain=1.0, max_stress_jitter=None
    )
    first = Segment(2.0, 30.0, 90.0)
    second = Segment(1.5, first.end_angle_deg, -120.0)
    run = dict(force_model=force_model, settings=settings, progress=None)
    first_run = run_segment(tmp_path / "first", first, data_file=data, **run)
    second_run = run_segment(tmp_path / "second", second, restart_file=first_run.checkpoint_file, **run)

    lx, ly, lz = box
    tables = []
    for segment, result in ((first, first_run), (second, second_run)):
        table = read_stress_table(result.table_file)
        tables.append(table)
        np.testing.assert_allclose(table["strain"], np.arange(len(table["strain"])) * 0.01, atol=1e-12)
        np.testing.assert_array_equal(table["lz"], lz)
        w = np.radians(segment.turning_deg_per_strain)
        t0, t = np.radians(segment.flow_angle_deg), np.radians(segment.flow_angle_at(table["strain"]))
        xz = table["xz"][0] + lz * (np.sin(t) - np.sin(t0)) / w
        yz = table["yz"][0] - lz * (np.cos(t) - np.cos(t0)) / w
        flips_x, flips_y = (table["xz"] - xz) / lx, (table["yz"] - yz) / ly
        np.testing.assert_allclose(flips_x, np.round(flips_x), rtol=0, atol=1e-10 / lx)
        np.testing.assert_allclose(flips_y, np.round(flips_y), rtol=0, atol=1e-10 / ly)
        one_step = settings.dt * lz  # the largest tilt change in one step
        assert np.abs(table["xz"]).max() <= lx / 2 + one_step
        assert np.abs(table["yz"]).max() <= ly / 2 + one_step
        if segment is first:  # the check is not empty: both tilts flipped
            assert np.ptp(np.round(flips_x)) >= 1 and np.ptp(np.round(flips_y)) >= 1
    # the first segment started from the data file's tilts, the second from the first's last ones
    assert (tables[0]["xz"][0], tables[0]["yz"][0]) == tilt[1:]
    assert (tables[1]["xz"][0], tables[1]["yz"][0]) == (tables[0]["xz"][-1], tables[0]["yz"][-1])


# ---------------------------------------------------------- 2. a free sphere follows the flow

TURNING_DEG = 120.0
FREE_DT = 1e-4
FREE_BOX = (6.0, 7.0, 5.5)


@pytest.fixture(scope="module")
def free_spheres(tmp_path_factory, force_model):
    """Three spheres (d = 1, 1.4, 1) at heights 0.9, 2.7, 4.5 in a tilted 6 x 7 x 5.5 box: in z
    they stay 1.8 apart (images included), far beyond the lubrication range 1.2 (1 + h_out/2),
    so each feels only its drag. A rotary segment of 0.3 strain at 120 deg/strain from 40 deg."""
    workdir = tmp_path_factory.mktemp("free")
    spheres = [(1.0, 1.0, 2.0, 0.9), (1.4, 3.0, 5.0, 2.7), (1.0, 5.0, 1.0, 4.5)]
    data = write_data(workdir / "free.data", spheres, FREE_BOX, (0.0, 0.8, -0.4))
    settings = ShearSettings(dt=FREE_DT, dump_strain=0.05, table_strain=0.01, thermo_strain=0.05, restart_strain=1.0)
    segment = Segment(0.3, 40.0, TURNING_DEG)
    run_segment_script(workdir / "run", segment, data, force_model, settings, motion_every=500)
    return segment, read_motion(workdir / "run" / "motion.dump")


def test_free_spheres_move_and_spin_with_the_turning_flow(free_spheres, force_model):
    """A free sphere follows the turning flow at every instant, lagging it by its inertial
    relaxation time. Its equation of motion m dv/dt = 3 pi eta d (u_inf(x, t) - v),
    I domega/dt = pi eta d^3 (Omega_inf(t) - omega) with u_inf = gammadot (z - zlo) f(t),
    Omega_inf = (gammadot/2) e_z x f(t), f turning at w, has after its transient the exact solution
        v = gammadot (z - zlo) [f(t) - w T f_perp(t)] / (1 + (w T)^2),   f_perp = e_z x f,
        omega = (gammadot/2) [f_perp(t) + w T_r f(t)] / (1 + (w T_r)^2),
    i.e. u_inf and Omega_inf of a time T earlier (to O((w T)^2)), with T = tau = m/(3 pi eta d)
    = d^2/(18 eta) and T_r = I/(pi eta d^3) = d^2/(60 eta) (Stokes number 1/eta_f: 2.5e-4 and
    7.5e-5 strain at d = 1). The integrator adds one time step to each lag, T = tau + dt: backward
    Euler in the drag, with the flow of the box rates fix deform set at the end of the step before.
    Checked for the three spheres at strains 0.05 ... 0.3 (hundreds of relaxation times after
    the start) to 1e-6 gammadot lz for v and 1e-6 gammadot for omega, which covers the
    O(w^2 dt tau) ~ 1e-7 difference between the scheme and the shifted exact solution (measured
    6e-8 and 3e-8). The lags themselves, |v - u_inf(x, t)| = w T gammadot (z - zlo) = 3.3e-3 at
    z - zlo = 4.5 and |omega - Omega_inf| = w T_r gammadot/2 = 1.8e-4, are 600x and 180x the
    tolerances: a sphere without inertia (following u_inf(x, t) itself), a lag of another size or
    a flow turning the other way would fail. A sphere cannot equal u_inf(x, t) at every instant of
    a turning flow more closely than w tau |u|: the tight statement is the lagged one."""
    segment, frames = free_spheres
    eta = force_model.eta_f
    w = np.radians(segment.turning_deg_per_strain)
    checked = 0
    for step, (zlo, atoms) in sorted(frames.items()):
        strain = step * FREE_DT
        if strain < 0.05 - 1e-12:
            continue
        f, f_perp = flow_direction(np.radians(segment.flow_angle_at(strain)))
        d = 2.0 * atoms["radius"][:, None]
        lag, spin_lag = d**2 / (18.0 * eta) + FREE_DT, d**2 / (60.0 * eta) + FREE_DT
        height = vectors(atoms, "z")[:, :1] - zlo
        v_exact = height * (f - w * lag * f_perp) / (1.0 + (w * lag) ** 2)
        omega_exact = 0.5 * (f_perp + w * spin_lag * f) / (1.0 + (w * spin_lag) ** 2)
        v, omega = vectors(atoms, "vx", "vy", "vz"), vectors(atoms, "omegax", "omegay", "omegaz")
        np.testing.assert_allclose(v, v_exact, rtol=0, atol=1e-6 * FREE_BOX[2], err_msg=f"strain {strain}")
        np.testing.assert_allclose(omega, omega_exact, rtol=0, atol=1e-6, err_msg=f"strain {strain}")
        lag_seen = np.linalg.norm(v - height * f, axis=1)
        np.testing.assert_allclose(lag_seen, w * lag[:, 0] * height[:, 0], rtol=1e-3)
        checked += 1
    assert checked == 6


@pytest.fixture(scope="module")
def first_step(tmp_path_factory, force_model):
    """Velocity after one step of a sphere (d = 1, z - zlo = 4.5) starting at rest, in a steady
    segment at 40 deg (turning 0) and in a rotary one from 40 deg, and the backward-Euler
    value (1 - c) u_inf(x, t0) of the steady one."""
    workdir = tmp_path_factory.mktemp("first_step")
    data = write_data(workdir / "one.data", [(1.0, 1.0, 2.0, 4.5)], (6.0, 6.0, 6.0))
    dt = FREE_DT
    settings = ShearSettings(dt=dt, dump_strain=dt, table_strain=dt, thermo_strain=dt, restart_strain=1.0)
    mass, drag = np.pi / 6.0, 3.0 * np.pi * force_model.eta_f
    keep = (mass / dt) / (mass / dt + drag)  # c, the share of the old velocity relative to the flow
    f, _ = flow_direction(np.radians(40.0))
    velocities = {}
    for turning in (0.0, TURNING_DEG):
        segment = Segment(3 * dt, 40.0, turning)
        run = run_segment_script(workdir / f"turning{turning:g}", segment, data, force_model, settings, 1)
        zlo, atoms = read_motion(run / "motion.dump")[1]
        velocities[turning] = vectors(atoms, "vx", "vy", "vz")[0]
    return velocities, (1.0 - keep) * (atoms["z"][0] - zlo) * f


def test_first_step_of_a_rotary_segment_feels_the_imposed_flow(first_step):
    """After its first step, a sphere that starts at rest has the velocity backward Euler gives
    in the imposed flow at the segment's start, v_1 = (1 - c) u_inf(x, t0) with
    c = (m/dt) / (m/dt + 3 pi eta d) (0.714 at d = 1, dt = 1e-4), whether the flow turns or not:
    in the steady segment (fix deform erate) to round-off, in the rotary one (fix deform
    variable) up to the w dt = 2e-4 rad the flow turns in one step (atol 1e-3 on |v_1| = 1.3).
    Without fix flow_rate/sf the rotary sphere stays at rest (v_1 = 0): fix deform gives the
    'variable' tilts their rates only at the end of the first step."""
    velocities, expected = first_step
    np.testing.assert_allclose(velocities[0.0], expected, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(velocities[TURNING_DEG], expected, rtol=0, atol=1e-3)


# ------------------------------------------------------- 3. two spheres squeezed by a turning flow

PAIR_RADII = (0.5, 0.7)
PAIR_GAP = 0.015  # reduced gap 2 h/(a1 + a2) = 0.025 < h_out
PAIR_SEGMENT = Segment(1.0, 0.0, 180.0)
PAIR_START = 0.02  # strain at which the reference leaves the LAMMPS trajectory


def pair_data(path):
    """Spheres of d = 1 and 1.4 at surface gap 0.015, the line of centres (-1, 0, 1)/sqrt(2) on
    the compressional axis of the flow at t0 = 0 (f = x), in a cubic box of 6."""
    first = np.array([3.0, 3.0, 2.5])
    second = first + (sum(PAIR_RADII) + PAIR_GAP) * np.array([-1.0, 0.0, 1.0]) / np.sqrt(2.0)
    return write_data(path, [(2 * PAIR_RADII[0], *first), (2 * PAIR_RADII[1], *second)], (6.0, 6.0, 6.0))


def pair_reference(segment: Segment, start_strain: float, state, strains, zlo, force_model):
    """Positions and velocities at ``strains`` of the two spheres of PAIR_RADII from ``state`` =
    (x, v, omega) (2 x 3 each) at ``start_strain``: m_i dv_i/dt = -3 pi eta d_i (v_i - u_inf(x_i, t))
    + F_i, I_i domega_i/dt = -pi eta d_i^3 (omega_i - Omega_inf(t)) + T_i, where (F, T) = -R (v_i -
    Omega_inf x x_i, omega_i - Omega_inf) with R the leading-order Jeffrey & Onishi resistance
    matrix at the current gap (test_lubrication_values.py, independent of the plugin): the pair
    resists its motion relative to the imposed rotation, so the strain part E(t) of the flow, which
    the drags impose, squeezes it. Solved by scipy (Radau, rtol 1e-8: 2e-10 d on the gap)."""
    radii = np.array(PAIR_RADII)
    mass = np.pi / 6.0 * (2.0 * radii) ** 3
    inverse_mass = 1.0 / np.concatenate([np.repeat(mass, 3), np.repeat(0.4 * mass * radii**2, 3)])
    eta = force_model.eta_f
    drag = np.concatenate([np.repeat(6.0 * np.pi * eta * radii, 3), np.repeat(8.0 * np.pi * eta * radii**3, 3)])
    w, t0 = np.radians(segment.turning_deg_per_strain), np.radians(segment.flow_angle_deg)

    def flow(strain, x):
        f, f_perp = flow_direction(t0 + w * strain)
        rotation = 0.5 * f_perp
        separation = x[1] - x[0]
        r = np.linalg.norm(separation)
        resistance = jeffrey_onishi_resistance(
            *radii, separation / r, r - radii.sum(), mu=eta, delta=force_model.delta, h_out=force_model.h_out
        )
        imposed = np.concatenate([(x[0, 2] - zlo) * f, (x[1, 2] - zlo) * f, rotation, rotation])
        rigid = np.concatenate([np.cross(rotation, x[0]), np.cross(rotation, x[1]), rotation, rotation])
        return f, resistance, imposed, rigid

    def rhs(strain, y):
        x, velocities = y[:6].reshape(2, 3), y[6:]
        _, resistance, imposed, rigid = flow(strain, x)
        acceleration = inverse_mass * (-drag * (velocities - imposed) - resistance @ (velocities - rigid))
        return np.concatenate([velocities[:6], acceleration])

    def jacobian(strain, y):  # exact in the velocities, by differences in the positions
        _, resistance, _, _ = flow(strain, y[:6].reshape(2, 3))
        J = np.zeros((18, 18))
        J[:6, 6:12] = np.eye(6)
        J[6:, 6:] = -inverse_mass[:, None] * (np.diag(drag) + resistance)
        base = rhs(strain, y)
        for column in range(6):
            shifted = y.copy()
            shifted[column] += 1e-7
            J[6:, column] = (rhs(strain, shifted)[6:] - base[6:]) / 1e-7
        return J

    y0 = np.concatenate([np.ravel(part) for part in state])
    solution = solve_ivp(
        rhs, (start_strain, strains[-1]), y0, method="Radau", rtol=1e-8, atol=1e-11, t_eval=strains, jac=jacobian
    )
    assert solution.success, solution.message
    return solution.y[:6].T.reshape(-1, 2, 3), solution.y[6:12].T.reshape(-1, 2, 3)


def pair_errors(tmp_path, dt, force_model):
    """Gap, line of centres and approach velocity of the pair in LAMMPS at dt and in the reference
    at strains 0.1, 0.2, ..., 1.0, the reference started from the LAMMPS state at PAIR_START."""
    settings = ShearSettings(dt=dt, dump_strain=0.02, table_strain=0.01, thermo_strain=0.1, restart_strain=1.0)
    every = round(0.02 / dt)
    run = run_segment_script(
        tmp_path / f"dt{dt:g}", PAIR_SEGMENT, pair_data(tmp_path / "pair.data"), force_model, settings, every
    )
    frames = read_motion(run / "motion.dump")
    strains = np.arange(1, 11) * 0.1
    zlo, atoms = frames[round(PAIR_START / dt)]
    start = tuple(
        vectors(atoms, *names) for names in (("xu", "yu", "zu"), ("vx", "vy", "vz"), ("omegax", "omegay", "omegaz"))
    )
    x_exact, v_exact = pair_reference(PAIR_SEGMENT, PAIR_START, start, strains, zlo, force_model)
    result = {}
    for label, positions, velocities in (
        (
            "lammps",
            [vectors(frames[round(s / dt)][1], "xu", "yu", "zu") for s in strains],
            [vectors(frames[round(s / dt)][1], "vx", "vy", "vz") for s in strains],
        ),
        ("exact", x_exact, v_exact),
    ):
        separation = np.array([x[1] - x[0] for x in positions])
        r = np.linalg.norm(separation, axis=1)
        e = separation / r[:, None]
        approach = np.einsum("ij,ij->i", np.array([v[1] - v[0] for v in velocities]), e)
        result[label] = dict(gap=r - sum(PAIR_RADII), e=e, approach=approach, r=r)
    return strains, result


def test_two_spheres_squeeze_and_part_as_the_flow_turns(tmp_path, force_model):
    """Two spheres (d = 1, 1.4) at gap 0.015, their line of centres e on the compressional axis of
    the flow at t0 = 0, in rotary shear at 180 deg/strain for 1 strain: the imposed strain rate
    E(t) = (gammadot/2)(f e_z + e_z f) pushes them together at first (e.E.e < 0), and, as f
    turns by 180 degrees, pulls them apart. Their gap h(gamma), line of centres e(gamma) and
    approach velocity dh/dt = (v_2 - v_1).e follow the exact solution of the equations of motion
    with drag and the Jeffrey & Onishi lubrication resistance at the instantaneous E(t), Omega(t)
    (pair_reference; the rotary analogue of the squeeze test in test_lammps_implicit.py), started
    from the LAMMPS state at strain 0.02. The integration is first order in dt: at dt = 1e-4
    the gap agrees to 3e-5 d (0.25% of its 0.012 excursion; measured 2.2e-5), the approach
    velocity to 6e-5 (measured 4e-5, against |dh/dt| up to 0.036) and e to 2e-4 (measured
    1.4e-4), and at dt = 2e-4 the errors double (ratio 2 +- 0.2 at the last, largest one; measured
    2.00): the run converges to the exact solution. The lubrication matters: dh/dt is 3-7% of
    the affine r e.E.e, and the pair stays in the lubrication range without touching
    (0 < xi < h_out; the reference has no contact force)."""
    errors = {}
    for dt in (1e-4, 2e-4):
        strains, result = pair_errors(tmp_path, dt, force_model)
        lammps, exact = result["lammps"], result["exact"]
        errors[dt] = {
            "gap": np.abs(lammps["gap"] - exact["gap"]),
            "approach": np.abs(lammps["approach"] - exact["approach"]),
            "e": np.linalg.norm(lammps["e"] - exact["e"], axis=1),
        }
    assert errors[1e-4]["gap"].max() < 3e-5
    assert errors[1e-4]["approach"].max() < 6e-5
    assert errors[1e-4]["e"].max() < 2e-4
    for quantity in ("gap", "e"):
        assert errors[2e-4][quantity][-1] / errors[1e-4][quantity][-1] == pytest.approx(2.0, abs=0.2), quantity

    # the check is not empty: squeezed, then parted, within the lubrication range, far from affine
    gap = exact["gap"]
    assert gap.argmin() not in (0, len(gap) - 1) and gap[-1] > PAIR_GAP > gap.min()
    reduced = 2.0 * gap / sum(PAIR_RADII)
    assert 0.0 < reduced.min() and reduced.max() < force_model.h_out
    f, _ = flow_direction(np.radians(PAIR_SEGMENT.flow_angle_at(strains)))
    affine = exact["r"] * np.einsum("ij,ij->i", exact["e"], f) * exact["e"][:, 2]  # r e.E.e, gammadot = 1
    assert np.all(np.abs(exact["approach"]) < 0.1 * np.abs(affine))


# ------------------------------------------------------------------ 4. resume across a kill

RESUME_DT = 1e-4
RESUME_SETTINGS = ShearSettings(
    dt=RESUME_DT, dump_strain=0.01, table_strain=0.001, thermo_strain=0.0005, restart_strain=0.1
)
RESUME_SEGMENT = Segment(0.6, 30.0, 150.0)
REVERSAL_SEGMENT = Segment(0.6, -90.0)


def source_index(run) -> int:
    """The segment index of a finished run, from its record."""
    return json.loads((run.output_dir / COMPLETION_MARKER).read_text())["flow_segment"]["index"]


KILL_STRAIN = 0.2


@pytest.fixture(scope="module", params=["rotary", "reversal"])
def resumed(request, tmp_path_factory, force_model):
    """The squeezed pair of test 3 sheared steadily along x for 0.05 strain (to step 500), then
    the segment to resume: ``rotary``, RESUME_SEGMENT (index 1, 0.6 strain at 150 deg/strain from
    30 deg) from that checkpoint; ``reversal``, a fixed-angle segment two deep (0.05 strain at
    90 deg, then REVERSAL_SEGMENT, 0.6 strain at -90 deg, index 2, from step 1000). Each is
    run twice through run_segment: whole, and killed (SIGKILL of lmp from the
    progress callback, once thermo has reached strain 0.2: the restart files of steps 1000 and
    2000 are complete, LAMMPS writes restarts before thermo) then run again, which resumes from
    the latest restart file. lmp cannot finish before it is killed: with a thermo row (~150 bytes)
    every 5 steps, the 64 KiB pipe to the runner holds ~2000 steps, and LAMMPS blocks on it.
    Returns (whole, resumed, restart step)."""
    workdir = tmp_path_factory.mktemp("resume")
    run = dict(force_model=force_model, settings=RESUME_SETTINGS)
    startup = run_segment(
        workdir / "startup", Segment(0.05), data_file=pair_data(workdir / "pair.data"), progress=None, **run
    )
    segment, source = RESUME_SEGMENT, startup
    if request.param == "reversal":
        segment = REVERSAL_SEGMENT
        source = run_segment(
            workdir / "rotation", Segment(0.05, 90.0), restart_file=startup.checkpoint_file, progress=None, **run
        )
    continued = dict(restart_file=source.checkpoint_file, **run)
    whole = run_segment(workdir / "whole", segment, progress=None, **continued)

    target = workdir / "resumed"
    killed = []

    def kill_after(_label, strain, _total, _elapsed):
        if strain >= KILL_STRAIN and not killed:
            killed.extend(lammps_processes_in(workdir / ".resumed.partial"))
            for pid in killed:
                os.killpg(pid, signal.SIGKILL)

    with pytest.raises(LammpsRunError, match="partial run kept"):
        run_segment(target, segment, progress=kill_after, progress_interval=0.0, **continued)
    assert killed, "the run ended before it could be killed"
    result = run_segment(target, segment, progress=None, **continued)
    assert json.loads((target / COMPLETION_MARKER).read_text())["flow_segment"]["index"] == source_index(source) + 1
    marker = json.loads((target / COMPLETION_MARKER).read_text())
    assert result.segments == 2 and len(marker["segments"]) == 2
    restart_step = marker["segments"][-1]["start_step"]
    return whole, result, restart_step


def test_resumed_segment_keeps_its_strain_and_tilts(resumed):
    """A segment killed after a restart at step 2000 or later and resumed from it (the runner
    passes step0 = the segment's first step, 500 or 1000; for rotary shear segment.lmp turns the
    flow and the tilts on from the launch strain of the resumed run) has the table of the
    uninterrupted one: the same rows (steps), strain = (step - 500) dt, tilts xz, yz, lz equal
    to the table's 12 digits, the rows up to the restart step identical (they are the killed
    run's own) and trajectory frames at the same steps. The resumed launch ran only the steps
    after a restart step of the segment (every 1000 steps, at or after 2000)."""
    whole, result, restart_step = resumed
    a, b = read_stress_table(whole.table_file), read_stress_table(result.table_file)
    first_step = whole.first_step
    assert first_step in (500, 1000)
    assert (result.first_step, result.last_step) == (first_step, whole.last_step) == (first_step, first_step + 6000)
    # a restart step (every 1000 steps) at or after step 2000, the last complete when lmp was killed
    assert restart_step % 1000 == 0 and 2000 <= restart_step < whole.last_step
    np.testing.assert_array_equal(b["step"], a["step"])
    np.testing.assert_allclose(b["strain"], (b["step"] - first_step) * RESUME_DT, rtol=0, atol=1e-12)
    for column in ("xz", "yz", "lz"):
        np.testing.assert_allclose(b[column], a[column], rtol=0, atol=1e-11, err_msg=column)
    before = a["step"] <= restart_step
    for column in a:
        np.testing.assert_array_equal(b[column][before], a[column][before], err_msg=column)
    steps_a = [frame.step for frame in iter_dump_frames(whole.dump_file)]
    assert [frame.step for frame in iter_dump_frames(result.dump_file)] == steps_a


def test_resumed_segment_is_the_same_run(resumed):
    """Two spheres in lubrication range, no contact, solved to 1e-12: a deterministic, non-chaotic
    run, so the resumed segment continues the uninterrupted one to round-off: every column of
    the stress table after the restart step within 1e-9 of its largest value (the stress, its
    kinetic and lubrication parts, the stresslets) and the positions of every dumped frame
    within 1e-9 d."""
    whole, result, restart_step = resumed
    a, b = read_stress_table(whole.table_file), read_stress_table(result.table_file)
    after = a["step"] > restart_step
    frames = [{f.step: f.positions for f in iter_dump_frames(run.dump_file)} for run in (whole, result)]
    mismatch = [
        column for column in a if np.abs(b[column][after] - a[column][after]).max() > 1e-9 * np.abs(a[column]).max()
    ]
    moved = max(np.abs(frames[1][step] - frames[0][step]).max() for step in frames[0])
    assert not mismatch
    assert moved <= 1e-9

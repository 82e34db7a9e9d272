"""Real LAMMPS runs of simulation/lammps/inputs/{pack,startup,rotate}.lmp through the Python runner.

Small systems (N = 60, strains of a few 1e-3: ~100 steps of the implicit integration at
dt = 2e-5, a few thousand explicit steps at 5e-7), seconds each, with the project's plugin
force model (built on demand by plugin_path()).
Units: strain rate 1, d_small = 1, time = strain.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from suspension_fabric.simulation.lammps import (
    COMPLETION_MARKER,
    ForceModel,
    LammpsRunError,
    ShearSettings,
    is_complete,
    iter_dump_frames,
    pack,
    read_stress_table,
    run_rotation,
    run_startup,
    stress_jitter,
)
from suspension_fabric.simulation.lammps.plugin import plugin_path
from suspension_fabric.simulation.lammps.process import ThermoWatcher
from suspension_fabric.simulation.lammps.rundir import KEPT_MARKER

pytestmark = pytest.mark.lammps

N_PARTICLES = 60
DT = 2.0e-5  # implicit hydrodynamics (the default integrator)
EXPLICIT_DT = 5.0e-7
SMALL_SETTINGS = ShearSettings(
    dt=DT, dump_strain=0.001, table_strain=0.0005, thermo_strain=0.0005, restart_strain=0.001
)
SMALL_RUN = dict(settings=SMALL_SETTINGS, progress=None)
EXPLICIT_RUN = dict(SMALL_RUN, settings=replace(SMALL_SETTINGS, dt=EXPLICIT_DT))


@pytest.fixture(scope="module")
def force_model():
    return ForceModel(plugin=plugin_path())


@pytest.fixture(scope="module")
def packing(tmp_path_factory):
    return pack(tmp_path_factory.mktemp("pack") / "packing", N_PARTICLES, phi=0.45, seed=7)


@pytest.fixture(scope="module")
def startup(tmp_path_factory, packing, force_model):
    return run_startup(
        tmp_path_factory.mktemp("startup") / "run", packing.data_file, 0.002, force_model=force_model, **SMALL_RUN
    )


def read_data_atoms(path):
    """(radii, positions, box edge rows) from a LAMMPS data file of atom style sphere."""
    lines = Path(path).read_text().splitlines()
    bounds = {}
    for line in lines:
        parts = line.split()
        if len(parts) == 4 and parts[2:] in (["xlo", "xhi"], ["ylo", "yhi"], ["zlo", "zhi"]):
            bounds[parts[2][0]] = float(parts[1]) - float(parts[0])
        if len(parts) == 6 and parts[3:] == ["xy", "xz", "yz"]:
            tilts = [float(p) for p in parts[:3]]
    start = next(k for k, line in enumerate(lines) if line.startswith("Atoms")) + 2
    rows = []
    for line in lines[start:]:
        if not line.strip():
            break
        rows.append([float(v) for v in line.split()[:7]])
    atoms = np.array(rows)
    xy, xz, yz = tilts
    box = np.array([[bounds["x"], 0, 0], [xy, bounds["y"], 0], [xz, yz, bounds["z"]]])
    return atoms[:, 2] / 2.0, atoms[:, 4:7], box


def brute_force_min_relative_gap(radii, positions, box):
    """Smallest (r - a_i - a_j) / (a_i + a_j) over all pairs and the 27 nearest images."""
    shifts = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)]) @ box
    smallest = np.inf
    for i in range(len(positions) - 1):
        d = positions[i + 1 :, None, :] - positions[i] + shifts[None, :, :]
        r = np.linalg.norm(d, axis=2).min(axis=1)
        contact = radii[i] + radii[i + 1 :]
        smallest = min(smallest, np.min((r - contact) / contact))
    return smallest


def brute_force_max_overlap(radii, positions, box):
    """Largest a_i + a_j - r over all pairs and the 27 nearest images (no shortcuts)."""
    shifts = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)]) @ box
    largest = -np.inf
    for i in range(len(positions) - 1):
        d = positions[i + 1 :, None, :] - positions[i] + shifts[None, :, :]
        r = np.linalg.norm(d, axis=2).min(axis=1)
        largest = max(largest, np.max(radii[i] + radii[i + 1 :] - r))
    return largest


def test_packing_reaches_target_phi_without_overlap_and_is_reproducible(packing, tmp_path):
    """pack(): phi equals the target, an independent all-pairs check finds no overlap
    above 1e-6 d and no gap below gap_margin = 2% of the contact distance, the 50:50 number split
    holds, the same seed gives a byte-identical data file and another seed a different one."""
    radii, positions, box = read_data_atoms(packing.data_file)
    volume_fraction = np.sum(4.0 / 3.0 * np.pi * radii**3) / abs(np.linalg.det(box))
    assert volume_fraction == pytest.approx(0.45, rel=1e-9)
    assert packing.phi == pytest.approx(0.45, rel=1e-9)
    assert brute_force_max_overlap(radii, positions, box) < 1e-6
    assert brute_force_min_relative_gap(radii, positions, box) > 0.02 - 1e-6  # gap_margin
    assert packing.max_overlap < 1e-6
    assert (packing.n_small, packing.n_large) == (30, 30)
    assert sorted(set(np.round(2 * radii, 12))) == [1.0, 1.4]
    assert is_complete(packing.output_dir)

    again = pack(tmp_path / "again", N_PARTICLES, phi=0.45, seed=7)
    assert again.data_file.read_bytes() == packing.data_file.read_bytes()
    other = pack(tmp_path / "other", N_PARTICLES, phi=0.45, seed=8)
    assert other.data_file.read_bytes() != packing.data_file.read_bytes()


def test_packing_split_by_volume(tmp_path):
    """split='volume' gives equal solid volumes of small and large spheres (to one particle)."""
    result = pack(tmp_path / "volume", 200, phi=0.45, seed=3, split="volume")
    assert result.n_small + result.n_large == 200
    assert abs(result.n_small * 1.0 - result.n_large * 1.4**3) <= 1.4**3
    assert result.phi == pytest.approx(0.45, rel=1e-9)


def test_startup_writes_outputs_and_strain_is_step_dt_rate(startup):
    """run_startup(): dump, table, checkpoint, log and completion marker (and the marker's kept copy,
    rundir.KEPT_MARKER) exist (the periodic restart files stay in the partial run and go with it);
    the table's strain equals step*dt*rate; the xz tilt
    grows as strain*lz and yz
    stays 0; dump frames come every dump_strain with id type radius x y z."""
    out = startup.output_dir
    assert sorted(p.name for p in out.iterdir()) == sorted(
        ["trajectory.dump", "stress.txt", "checkpoint.rst", "log.lammps", COMPLETION_MARKER, KEPT_MARKER]
    )
    assert not any(p.name.startswith(".") for p in out.parent.iterdir())
    table = read_stress_table(startup.table_file)
    np.testing.assert_allclose(table["strain"], table["step"] * DT * 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(table["strain"], np.arange(0, 0.002 + 1e-12, 0.0005), atol=1e-15)
    np.testing.assert_allclose(table["xz"], table["strain"] * table["lz"], rtol=1e-9, atol=1e-12)
    assert np.all(table["yz"] == 0.0)
    assert np.all(np.isfinite(table["pxz"])) and np.any(table["pxz"] != 0.0)
    assert startup.strain == pytest.approx(0.002, abs=1e-12)
    assert (startup.first_step, startup.last_step) == (0, round(0.002 / DT))
    frames = list(iter_dump_frames(startup.dump_file))
    assert [f.step for f in frames] == [round(k * 0.001 / DT) for k in range(3)]
    assert all(len(f.ids) == N_PARTICLES for f in frames)
    assert frames[-1].box.xz == pytest.approx(0.002 * frames[-1].box.lz, rel=1e-9)


@pytest.mark.parametrize("springs", ["explicit", "implicit"])
def test_restart_does_not_change_the_physics(tmp_path, force_model, springs):
    """A run of 0.002 + 0.002 strain with a restart in between (segment.lmp at flow angle 0
    from the checkpoint) matches an uninterrupted run of 0.004: positions agree to
    round-off just after the restart (1e-10 d) and stay close at the end (1e-6 d), and
    the stress table agrees closely (mean pxz over the second half within 1e-4). The
    packing has no gap margin, so frictional contacts (with tangential history) exist
    across the restart: pair granular's history (springs explicit) or the fix's springs
    (springs implicit, written as the fix's global restart state)."""
    force_model = replace(force_model, contact_springs=springs)
    packing = pack(tmp_path / "touching", N_PARTICLES, phi=0.45, seed=7, gap_margin=0.0)
    fine = dict(SMALL_RUN, settings=replace(SMALL_SETTINGS, dump_strain=0.0001))
    whole = run_startup(tmp_path / "whole", packing.data_file, 0.004, force_model=force_model, **fine)
    first = run_startup(tmp_path / "first", packing.data_file, 0.002, force_model=force_model, **fine)
    second = run_rotation(tmp_path / "second", first.checkpoint_file, 0.0, 0.002, force_model=force_model, **fine)
    restart_step, end_step = round(0.002 / DT), round(0.004 / DT)
    assert (second.first_step, second.last_step) == (restart_step, end_step)

    whole_frames = {f.step: f for f in iter_dump_frames(whole.dump_file)}
    second_frames = {f.step: f for f in iter_dump_frames(second.dump_file)}
    assert sorted(second_frames) == [s for s in sorted(whole_frames) if s >= restart_step]
    # read_restart re-wraps atoms through fractional coordinates: round-off only
    np.testing.assert_allclose(
        second_frames[restart_step].positions, whole_frames[restart_step].positions, rtol=0, atol=1e-12
    )
    deviation = {s: np.abs(second_frames[s].positions - whole_frames[s].positions).max() for s in second_frames}
    first_after = min(s for s in second_frames if s > restart_step)
    assert deviation[first_after] < 1e-10
    assert deviation[end_step] < 1e-6

    whole_table = read_stress_table(whole.table_file)
    second_table = read_stress_table(second.table_file)
    assert np.all(np.abs(second_table["contact_pxz"]) > 0.0)  # contacts carried over
    after = whole_table["step"] >= restart_step
    np.testing.assert_array_equal(second_table["step"], whole_table["step"][after])
    np.testing.assert_allclose(second_table["strain"], whole_table["strain"][after] - 0.002, atol=1e-15)
    np.testing.assert_allclose(second_table["xz"], whole_table["xz"][after], rtol=1e-12)
    late = second_table["step"] >= (restart_step + end_step) // 2
    assert np.mean(second_table["pxz"][late]) == pytest.approx(np.mean(whole_table["pxz"][after][late]), rel=1e-4)


@pytest.mark.parametrize("theta_deg", [30.0, 90.0, 135.0])
def test_rotation_turns_the_flow(tmp_path, startup, force_model, theta_deg):
    """segment.lmp at flow angle theta: d xz/dt : d yz/dt = cos theta : sin theta (each = rate*trig*lz),
    strain counts from the rotation step, and the first frame is the checkpoint state."""
    rotated = run_rotation(
        tmp_path / "rot", startup.checkpoint_file, theta_deg, 0.002, force_model=force_model, **SMALL_RUN
    )
    table = read_stress_table(rotated.table_file)
    assert table["strain"][0] == 0.0 and table["step"][0] == startup.last_step
    np.testing.assert_allclose(table["strain"], (table["step"] - startup.last_step) * DT, atol=1e-15)
    theta = np.radians(theta_deg)
    lz = table["lz"][0]
    slope_xz = np.polyfit(table["strain"], table["xz"], 1)[0]
    slope_yz = np.polyfit(table["strain"], table["yz"], 1)[0]
    assert slope_xz / lz == pytest.approx(np.cos(theta), abs=1e-9)
    assert slope_yz / lz == pytest.approx(np.sin(theta), abs=1e-9)
    assert table["xz"][0] == pytest.approx(0.002 * lz, rel=1e-9)  # carried over from startup
    last_startup = list(iter_dump_frames(startup.dump_file))[-1]
    first_rotated = next(iter_dump_frames(rotated.dump_file))
    np.testing.assert_allclose(first_rotated.positions, last_startup.positions, rtol=0, atol=1e-12)


def test_failed_run_raises_and_leaves_no_complete_output(tmp_path, packing, force_model):
    """An absurd time step (dt = 0.05) blows the run up: LammpsRunError names the cause and
    the kept partial run, output_dir does not exist, and the partial files sit in
    .blowup.partial (a killed run's restarts would be resumed from there) without a marker."""
    target = tmp_path / "blowup"
    blowup = ShearSettings(dt=0.05, dump_strain=0.05, table_strain=0.05, thermo_strain=0.05, restart_strain=0.5)
    with pytest.raises(LammpsRunError, match=r"(Lost atoms|non-finite|Non-numeric|overlap)(.|\n)*partial run kept"):
        run_startup(target, packing.data_file, 1.0, force_model=force_model, settings=blowup, progress=None)
    assert not target.exists()
    partial = tmp_path / ".blowup.partial"
    assert (partial / "segment-01" / "log.lammps").is_file()
    assert not (partial / COMPLETION_MARKER).exists() and not is_complete(partial)
    assert sorted(p.name for p in tmp_path.iterdir()) == [".blowup.partial"]


def test_rotation_refuses_an_unfinished_checkpoint(tmp_path, startup, force_model):
    """A checkpoint outside a finished run directory is refused unless asked for."""
    loose = tmp_path / "loose"
    loose.mkdir()
    (loose / "checkpoint.rst").write_bytes(startup.checkpoint_file.read_bytes())
    with pytest.raises(LammpsRunError, match="not in a finished run directory"):
        run_rotation(tmp_path / "rot", loose / "checkpoint.rst", 90.0, 0.001, force_model=force_model, **SMALL_RUN)


def test_stock_stand_in_model_runs(tmp_path, packing):
    """The development stand-in (lubricate/poly + drag by fix addforce) still runs; it cannot
    record the contact torque, so those columns are NaN (and its contact stress unsymmetrised)."""
    result = run_startup(
        tmp_path / "stock",
        packing.data_file,
        0.001,
        force_model=ForceModel(lubrication="stock", integrator="explicit", contact_springs="explicit"),
        **EXPLICIT_RUN,
    )
    assert is_complete(result.output_dir)
    table = read_stress_table(result.output_dir / "stress.txt")
    assert np.isnan(table["contact_torque_y"]).all() and np.isfinite(table["contact_pxz"]).all()


def test_two_mpi_ranks(tmp_path, packing, monkeypatch):
    """ranks=2 runs the explicit integrator under the environment's mpirun and reaches the
    same strain; its stress agrees with the serial run to 1e-6 over this short strain. Each
    rank runs one OpenMP thread even where the environment asks for more (Snakemake sets
    OMP_NUM_THREADS to a job's threads, i.e. the rank count)."""
    monkeypatch.setenv("OMP_NUM_THREADS", "2")
    explicit = ForceModel(plugin=plugin_path(), integrator="explicit", contact_springs="explicit")
    serial = run_startup(tmp_path / "serial", packing.data_file, 0.001, force_model=explicit, **EXPLICIT_RUN)
    parallel = run_startup(
        tmp_path / "mpi",
        packing.data_file,
        0.001,
        force_model=explicit,
        **dict(EXPLICIT_RUN, settings=replace(EXPLICIT_RUN["settings"], ranks=2)),
    )
    assert parallel.strain == pytest.approx(0.001, abs=1e-12)
    assert (
        "mpirun" in (parallel.output_dir / COMPLETION_MARKER).read_text()
        or "mpiexec" in (parallel.output_dir / COMPLETION_MARKER).read_text()
    )
    np.testing.assert_allclose(
        read_stress_table(parallel.table_file)["pxz"], read_stress_table(serial.table_file)["pxz"], rtol=1e-6
    )
    log = (parallel.output_dir / "log.lammps").read_text()
    assert "with 2 MPI tasks" in log and "1 OpenMP thread" in log


def test_implicit_and_explicit_integrators_agree_on_a_short_startup(tmp_path):
    """The implicit hydrodynamics at dt = 2e-5 and the explicit velocity Verlet at dt = 5e-7
    (40x smaller) integrate the same equations, both with the contacts of pair granular at
    kn = 1.25e9 (the implicit springs are compared with pair granular in
    test_lammps_implicit_contacts.py) and the implicit solve to 1e-5. Over 0.01 strain of a touching N = 60
    packing from rest, the particles end within 2 dt u_max of each other (u_max = lz
    gammadot, the largest imposed speed): the first-order implicit scheme lags the flow by
    about one step while the velocities build up (measured: a lag of 1.1 dt). The mean
    stresses over the second half (total, contact, lubrication; the implicit lubrication
    virial comes from the fix, the explicit one from the pair) and the summed contact torque
    (recorded by the pair in both) agree within 1%."""
    touching = pack(tmp_path / "touching", N_PARTICLES, phi=0.45, seed=11, gap_margin=0.0)
    settings = ShearSettings(dt=DT, dump_strain=0.005, table_strain=0.0005, thermo_strain=0.005, restart_strain=0.01)
    granular = ForceModel(plugin=plugin_path(), contact_springs="explicit", kn=1.25e9, solver_tol=1e-5)
    implicit = run_startup(
        tmp_path / "implicit", touching.data_file, 0.01, force_model=granular, settings=settings, progress=None
    )
    explicit = run_startup(
        tmp_path / "explicit",
        touching.data_file,
        0.01,
        force_model=replace(granular, integrator="explicit"),
        settings=replace(settings, dt=EXPLICIT_DT),
        progress=None,
    )
    last_implicit = list(iter_dump_frames(implicit.dump_file))[-1]
    last_explicit = list(iter_dump_frames(explicit.dump_file))[-1]
    lag_bound = 2.0 * DT * last_implicit.box.lz
    assert np.abs(last_implicit.positions - last_explicit.positions).max() < lag_bound
    a, b = read_stress_table(implicit.table_file), read_stress_table(explicit.table_file)
    late = a["strain"] >= 0.005
    for column in (
        "pxz",
        "press",
        "contact_pxz",
        "lubrication_pxz",
        "lubrication_pxx",
        "lubrication_pzz",
        "contact_torque_y",
    ):
        assert np.mean(b[column][late]) != 0.0
        assert np.mean(a[column][late]) == pytest.approx(np.mean(b[column][late]), rel=0.01), column


def test_overlap_check_agrees_with_brute_force_and_handles_tiny_boxes(tmp_path, force_model):
    """max_overlap_in_dump equals an all-pairs, all-images computation on a dump of
    random overlapping spheres in a tilted box (one box large enough for the neighbour
    search, one too small for it); an 8-particle LAMMPS run is checked end to end."""
    from suspension_fabric.io.dumpio import DumpFrame, TriclinicBox, write_lammps_dump
    from suspension_fabric.simulation.lammps import max_overlap_in_dump

    generator = np.random.default_rng(11)
    for n_atoms, length in ((80, 6.0), (6, 2.4)):
        box = TriclinicBox(length, length, length, 0.0, 0.4 * length, -0.3 * length, (1.0, -2.0, 0.5))
        fractional = generator.random((n_atoms, 3))
        positions = np.asarray(box.origin) + fractional @ box.edge_vectors
        radii = generator.choice([0.5, 0.7], n_atoms)
        path = write_lammps_dump(
            tmp_path / f"random{n_atoms}.dump",
            [DumpFrame(step=0, box=box, positions=positions, radii=radii)],
            float_format="%.17g",
        )
        largest, frames = max_overlap_in_dump(path)
        expected = brute_force_max_overlap(radii, positions, box.edge_vectors)
        assert frames == 1 and expected > 0.0
        assert largest == pytest.approx(expected, abs=1e-12)

    tiny = pack(tmp_path / "tiny", 8, phi=0.45, seed=5)
    run = run_startup(tmp_path / "tiny_run", tiny.data_file, 0.001, force_model=force_model, **SMALL_RUN)
    assert is_complete(run.output_dir) and run.max_overlap < 0.05


def test_thermo_watcher_reads_strain_and_flags_nan_and_errors():
    """The screen parser takes the strain from the v_strain column, flags a NaN thermo
    row and collects ERROR lines (the runner stops the run on either)."""
    watcher = ThermoWatcher()
    for line in [
        "   Step        v_strain         CPU            Pxz\n",
        "         0   0              0             -975.6\n",
        "      1000   0.001          0.14          -2291.7\n",
    ]:
        watcher.feed(line)
    assert watcher.strain == 0.001 and watcher.rows_seen == 2 and watcher.bad_thermo is None
    watcher.feed("      2000   0.002          0.31          nan\n")
    assert watcher.bad_thermo is not None and "nan" in watcher.bad_thermo
    watcher.feed("ERROR: Lost atoms: original 100 current 50 (src/thermo.cpp:526)\n")
    assert watcher.errors == ["ERROR: Lost atoms: original 100 current 50 (src/thermo.cpp:526)"]


def test_stress_jitter_separates_smooth_from_oscillating_tables():
    """stress_jitter is ~0 for a smooth stress history and ~1 when the lubrication stress
    flips between rows (the signature of a too large dt); a table without a window of 20
    rows is not judged (0), however much it flips."""
    strain = np.arange(200) * 0.001
    smooth = {k: -1000.0 + 50.0 * np.sin(strain) for k in ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")}
    smooth["strain"] = strain
    assert stress_jitter(smooth)[0] < 0.01
    flipping = dict(smooth, pxz=smooth["pxz"] + 800.0 * (-1.0) ** np.arange(200))
    jitter, lo, hi = stress_jitter(flipping)
    assert jitter > 0.5 and 0.0 <= lo < hi
    short = {name: values[:19] for name, values in flipping.items()}
    just_enough = {name: values[:20] for name, values in flipping.items()}
    assert stress_jitter(short, skip_strain=0.0)[0] == 0.0
    assert stress_jitter(just_enough, skip_strain=0.0)[0] > 0.5


def test_stress_jitter_ignores_the_impulsive_start():
    """The jump of the first rows after a start or rotation (velocities relax within
    ~m/(3 pi eta_f d) ~ 3e-4 strain) is physical: skipped by default, counted with skip_strain=0."""
    strain = 5.0 + np.arange(200) * 0.001  # a rotated run's table starts at its own strain 0
    table = {k: -1000.0 + 0.0 * strain for k in ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")}
    table["strain"] = strain - strain[0]
    table["pxz"] = table["pxz"].copy()
    table["pxz"][:5] = 1.0e5 * (-1.0) ** np.arange(5)  # ringing within the first 0.005 strain
    assert stress_jitter(table)[0] < 0.01
    assert stress_jitter(table, skip_strain=0.0)[0] > 1.0

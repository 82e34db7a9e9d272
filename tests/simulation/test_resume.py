"""Resume for real: a startup killed with SIGKILL part-way continues from its latest readable
restart file instead of strain 0, through the Python runner and through Snakemake.

N = 40 (test forces: eta_f = 1, kn = 5.6e5, dt = 1e-4), 15 strain = 150000 steps (~5 s),
restart files every 1.5 strain. "Continuous" means: the stitched stress table and trajectory hold
every output step of the uninterrupted run once, in order; up to the restart step they are the
uninterrupted run's own rows (the same deterministic serial run), and after it the dynamics is
the same (no jump at the next table row, positions within 1e-3 d half a strain later; the
late-time mean shear stress agrees within the statistical error, since the trajectories of a
chaotic system part ways).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

from suspension_fabric.io.dumpio import iter_dump_frames
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, pack, read_stress_table, run_startup
from suspension_fabric.simulation.lammps.plugin import plugin_path
from suspension_fabric.simulation.lammps.process import lammps_processes_in
from workflow_helpers import copy_workflow, snakemake

pytestmark = pytest.mark.lammps

STRAIN = 15.0
SETTINGS = dict(dt=1.0e-4, dump_strain=0.5, table_strain=0.01, thermo_strain=0.01, restart_strain=1.5)
FORCES = dict(eta_f=1.0, kn=5.6e5)
RESTART_STEPS = round(SETTINGS["restart_strain"] / SETTINGS["dt"])
LATE_STRAIN = 5.0


@pytest.fixture(scope="module")
def packing(tmp_path_factory):
    return pack(tmp_path_factory.mktemp("pack") / "packing", 40, seed=4)


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory, packing):
    return run_startup(
        tmp_path_factory.mktemp("whole") / "run",
        packing.data_file,
        STRAIN,
        force_model=ForceModel(plugin=plugin_path(), **FORCES),
        settings=ShearSettings(**SETTINGS),
        progress=None,
    )


RUNNER = f"""
import sys
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, run_startup
run_startup(sys.argv[1], sys.argv[2], {STRAIN}, force_model=ForceModel(plugin=sys.argv[3], **{FORCES}),
            settings=ShearSettings(**{SETTINGS}), overwrite=True, progress=None)
"""


def kill_after_restarts(
    process: subprocess.Popen, partial: Path, restarts: int = 2, also_kill_group: bool = False
) -> None:
    """Wait until ``restarts`` restart files exist in the partial run, then SIGKILL the lmp
    process group (and, with ``also_kill_group``, the group of ``process`` itself first)."""
    names = ["restart.a.rst", "restart.b.rst"][:restarts]
    deadline = time.monotonic() + 120
    while not all((partial / "segment-01" / name).is_file() for name in names):
        assert process.poll() is None, "the run ended before it was killed"
        assert time.monotonic() < deadline
        time.sleep(0.01)
    pids = lammps_processes_in(partial)
    assert pids, "no lmp process found to kill"
    if also_kill_group:
        os.killpg(process.pid, signal.SIGKILL)
    for pid in pids:
        try:
            os.killpg(pid, signal.SIGKILL)
        except ProcessLookupError:  # it died with its parent's pipe
            pass
    process.wait(timeout=60)
    assert process.returncode != 0


def start_and_kill(tmp_path: Path, packing) -> Path:
    output = tmp_path / "run"
    process = subprocess.Popen(
        [sys.executable, "-c", RUNNER, str(output), str(packing.data_file), str(plugin_path())],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    kill_after_restarts(process, tmp_path / ".run.partial")
    assert not output.exists()
    return output


def resume(output: Path, packing, capsys):
    result = run_startup(
        output,
        packing.data_file,
        STRAIN,
        force_model=ForceModel(plugin=plugin_path(), **FORCES),
        settings=ShearSettings(**SETTINGS),
        overwrite=True,
        progress=None,
    )
    return result, capsys.readouterr().err


def assert_continuous(result, uninterrupted, restart_step: int) -> None:
    a, b = read_stress_table(uninterrupted.table_file), read_stress_table(result.table_file)
    np.testing.assert_array_equal(b["step"], a["step"])  # every row once, in order
    np.testing.assert_allclose(np.diff(b["strain"]), SETTINGS["table_strain"], rtol=1e-9)
    before = a["step"] <= restart_step
    for column in a:  # the same deterministic run up to (and including) the restart step
        np.testing.assert_array_equal(b[column][before], a[column][before], err_msg=column)
    frames_a = {f.step: f.positions for f in iter_dump_frames(uninterrupted.dump_file)}
    frames_b = {f.step: f.positions for f in iter_dump_frames(result.dump_file)}
    assert list(frames_b) == list(frames_a)
    np.testing.assert_array_equal(frames_b[restart_step], frames_a[restart_step])
    # just after: no jump, the same dynamics up to round-off and the solver tolerance, which the
    # stiff contacts amplify (measured: 1.5e-3 relative in pxz 50 steps on, 1e-4 d after 1 strain)
    next_row = np.searchsorted(a["step"], restart_step) + 1
    assert abs(b["pxz"][next_row] - a["pxz"][next_row]) < 0.1 * a["pxz"].std()
    next_frame = restart_step + round(SETTINGS["dump_strain"] / SETTINGS["dt"])
    assert np.abs(frames_b[next_frame] - frames_a[next_frame]).max() < 1e-3
    # late times, past the restart and the parting of the trajectories: same statistics (block
    # means over 1 strain, 10 blocks)
    late = a["strain"] >= LATE_STRAIN
    rows = round((STRAIN - LATE_STRAIN) / SETTINGS["table_strain"])
    blocks_a = -a["pxz"][late][:rows].reshape(10, -1).mean(axis=1)
    blocks_b = -b["pxz"][late][:rows].reshape(10, -1).mean(axis=1)
    error = np.hypot(blocks_a.std(ddof=1), blocks_b.std(ddof=1)) / np.sqrt(10)
    assert abs(blocks_a.mean() - blocks_b.mean()) < 4 * error


@pytest.mark.fault("survived")
def test_a_killed_run_resumes_from_its_latest_restart(tmp_path, packing, uninterrupted, capsys):
    """SIGKILL after the second restart (strain 3): the rerun continues from restart.b at
    step 30000 (so only the steps after it are run again) and reaches the same outputs. The
    saving is counted in steps, not in wall time, which load on the machine would blur."""
    output = start_and_kill(tmp_path, packing)
    result, messages = resume(output, packing, capsys)
    restart_step = 2 * RESTART_STEPS
    assert f"at step {restart_step}" in messages and "restart.b.rst" in messages
    marker = json.loads((output / "run_complete.json").read_text())
    resumed = marker["segments"][-1]
    assert result.segments == 2 and resumed["start_step"] == restart_step
    assert_continuous(result, uninterrupted, restart_step)
    assert not (tmp_path / ".run.partial").exists()


@pytest.mark.fault("survived")
def test_a_corrupt_restart_falls_back_to_the_previous_one(tmp_path, packing, uninterrupted, capsys):
    """The newest restart file truncated to half (a kill while LAMMPS wrote it): the rerun says
    it is unreadable, continues from the previous restart (step 15000) and stays continuous."""
    output = start_and_kill(tmp_path, packing)
    newest = tmp_path / ".run.partial" / "segment-01" / "restart.b.rst"
    newest.write_bytes(newest.read_bytes()[: newest.stat().st_size // 2])
    result, messages = resume(output, packing, capsys)
    assert "restart.b.rst is unreadable" in messages and f"at step {RESTART_STEPS}" in messages
    assert result.segments == 2
    assert_continuous(result, uninterrupted, RESTART_STEPS)


@pytest.mark.fault("survived")
def test_no_readable_restart_restarts_from_zero(tmp_path, packing, uninterrupted, capsys):
    """Both restart files corrupt: the rerun says so, discards the partial run and starts from
    strain 0; the result is the uninterrupted run itself (same deterministic run)."""
    output = start_and_kill(tmp_path, packing)
    for name in ("restart.a.rst", "restart.b.rst"):
        (tmp_path / ".run.partial" / "segment-01" / name).write_bytes(b"LammpS RestartT garbage")
    result, messages = resume(output, packing, capsys)
    assert "no readable restart file" in messages and "starting from strain 0" in messages
    assert result.segments == 1
    a, b = read_stress_table(uninterrupted.table_file), read_stress_table(result.table_file)
    for column in a:
        np.testing.assert_array_equal(b[column], a[column], err_msg=column)


@pytest.mark.fault("survived")
def test_changed_settings_discard_the_partial_run(tmp_path, packing, capsys):
    """A partial run started with other settings is not continued: the message names the
    changed setting and the run starts from strain 0."""
    output = start_and_kill(tmp_path, packing)
    other = dict(SETTINGS, table_strain=0.02)
    result = run_startup(
        output,
        packing.data_file,
        STRAIN,
        force_model=ForceModel(plugin=plugin_path(), **FORCES),
        settings=ShearSettings(**other),
        overwrite=True,
        progress=None,
    )
    messages = capsys.readouterr().err
    assert "changed: variables.table_strain" in messages and "starting from strain 0" in messages
    assert result.segments == 1


@pytest.mark.workflow
@pytest.mark.fault("survived")
def test_snakemake_killed_with_its_simulation_resumes_it(tmp_path):
    """The whole Snakemake process group and its lmp SIGKILLed (a walltime or a reboot): the
    next `snakemake` (after --unlock; the workflow profile sets rerun-incomplete) continues the startup from
    its restart file, and the finished outputs equal those of an uninterrupted workflow run
    up to the restart step."""
    config = yaml.safe_load((Path(__file__).parents[2] / "config" / "test.yaml").read_text())
    config.update(study="resume", seeds=[1], angles_deg=[0])
    config["run"].update(startup_strain=STRAIN, rotation_strain=1.0, **{k: v for k, v in SETTINGS.items() if k != "dt"})
    config["analysis"]["steady_window"] = [LATE_STRAIN, STRAIN]
    config["verdicts"]["window"] = 1.0  # at least one frame (dump_strain 0.5) after a rotation
    target = "results/resume/seed1/startup/run_complete.json"

    whole = copy_workflow(tmp_path / "whole")
    (whole / "config" / "resume.yaml").write_text(yaml.safe_dump(config))
    first = snakemake(whole, "--configfile", "config/resume.yaml", "--", target)
    assert first.returncode == 0, first.stderr[-3000:]

    killed = copy_workflow(tmp_path / "killed")
    (killed / "config" / "resume.yaml").write_text(yaml.safe_dump(config))
    assert (
        snakemake(
            killed,
            "--configfile",
            "config/resume.yaml",
            "--",
            "results/resume/seed1/packing/packing.data",
        ).returncode
        == 0
    )
    process = subprocess.Popen(
        [
            str(Path(sys.executable).with_name("snakemake")),
            "--cores",
            "2",
            "--configfile",
            "config/resume.yaml",
            "--",
            target,
        ],
        cwd=killed,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    kill_after_restarts(process, killed / "results/resume/seed1/.startup.partial", also_kill_group=True)
    assert not (killed / target).exists()

    # a hard kill leaves Snakemake's lock behind: the recovery in docs/workflow.md is --unlock, then rerun
    assert snakemake(killed, "--configfile", "config/resume.yaml", "--unlock").returncode == 0
    rerun = snakemake(killed, "--configfile", "config/resume.yaml", "--", target)
    assert rerun.returncode == 0, rerun.stderr[-3000:]
    log = (killed / "results/resume/logs/shear_seed1_startup.log").read_text()
    assert f"at step {2 * RESTART_STEPS}" in log
    marker = json.loads((killed / target).read_text())
    assert len(marker["segments"]) == 2
    assert marker["segments"][-1]["start_step"] == 2 * RESTART_STEPS  # only the rest is run again
    a = read_stress_table(whole / "results/resume/seed1/startup/stress.txt")
    b = read_stress_table(killed / "results/resume/seed1/startup/stress.txt")
    np.testing.assert_array_equal(b["step"], a["step"])
    before = a["step"] <= 2 * RESTART_STEPS
    np.testing.assert_array_equal(b["pxz"][before], a["pxz"][before])

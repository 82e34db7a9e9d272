"""Bad input and faults: each gives a clear, early error naming the file or key, and nothing
already finished is lost. Real components throughout (LAMMPS, Snakemake, the test study)."""

from __future__ import annotations

import json
import os
import resource
import shutil
import subprocess
from pathlib import Path

import pytest
import yaml

from suspension_fabric.analysis import tables
from suspension_fabric.simulation.lammps import ForceModel, pack
from suspension_fabric.simulation.lammps.plugin import PluginBuildError, plugin_path, plugin_sources
from workflow_helpers import RESULTS, SNAKEMAKE, TEST_CONFIG, copy_workflow, job_counts, result_digests, snakemake

pytestmark = pytest.mark.workflow


@pytest.mark.fault("refused")
def test_a_missing_plugin_library_is_named():
    missing = Path("/nonexistent/libsuspension_fabric_lammps.so")
    with pytest.raises(FileNotFoundError, match="LAMMPS plugin library not found: /nonexistent/.*lammps.plugin"):
        ForceModel(plugin=missing).variables()


@pytest.mark.fault("refused")
def test_a_stale_plugin_library_is_refused(tmp_path):
    """A library older than a plugin source (the source was edited after the build) is refused
    with the name of the changed source and how to rebuild; a fresh copy is accepted."""
    library = tmp_path / "libcopy.so"
    shutil.copy2(plugin_path(), library)
    ForceModel(plugin=library).variables()  # as new as the build: fine
    source = plugin_sources()[0]
    old = source.stat().st_mtime - 3600
    os.utime(library, (old, old))
    with pytest.raises(
        PluginBuildError, match=rf"stale LAMMPS plugin library .*{source.name}(, [\w.]+)* changed.*rebuild"
    ):
        ForceModel(plugin=library).variables()


@pytest.mark.fault("named")
def test_a_dump_cut_mid_frame_fails_its_fabric_job_naming_the_file(study, tmp_path):
    """A trajectory cut inside a frame (a full disk, a copy broken off): rerunning its fabric
    job fails with the dump's path, frame and step; every other finished output is kept."""
    workdir = copy_workflow(tmp_path / "copy")
    shutil.copytree(study / "results", workdir / "results")
    shutil.copytree(study / ".snakemake", workdir / ".snakemake", ignore=shutil.ignore_patterns("locks", "incomplete"))
    shutil.copytree(study / "build", workdir / "build")
    dump = workdir / RESULTS / "seed1/startup/trajectory.dump"
    text = dump.read_text()
    dump.write_text(text[: len(text) - 200])
    finished = {
        p: p.stat().st_mtime_ns
        for p in (workdir / RESULTS).rglob("*.csv")
        if p != workdir / RESULTS / "seed1/startup/fabric.csv"
    }
    target = f"{RESULTS}/seed1/startup/fabric.csv"
    result = snakemake(workdir, *TEST_CONFIG, "--allowed-rules", "fabric_table", "--forcerun", target, "--", target)
    assert result.returncode != 0
    log = (workdir / RESULTS / "logs/fabric_seed1_startup.log").read_text()
    assert f"{RESULTS}/seed1/startup/trajectory.dump" in log and "truncated" in log and "step" in log
    assert {p: p.stat().st_mtime_ns for p in finished} == finished


@pytest.mark.fault("named")
def test_a_dump_cut_at_a_frame_boundary_is_caught_against_the_run_record(study, tmp_path):
    """A trajectory that lost its last frames whole parses as a shorter run: the fabric table
    compares its last frame with the step at which the run's record ends the segment (first step +
    strain / (dt rate)) and refuses it, naming the dump and both steps; the whole dump passes."""
    source = study / RESULTS / "seed1/startup"
    marker = source / "run_complete.json"
    assert len(tables.run_fabric_table(source / "trajectory.dump", marker, seed=1)) > 2
    text = (source / "trajectory.dump").read_text()
    cut = tmp_path / "trajectory.dump"
    cut.write_text(text[: text.rindex("ITEM: TIMESTEP")])  # the last frame removed at its header
    with pytest.raises(ValueError, match="truncated") as failure:
        tables.run_fabric_table(cut, marker, seed=1)
    assert str(cut) in str(failure.value) and "step" in str(failure.value)


@pytest.mark.fault("named")
def test_a_blow_up_in_one_job_lets_the_others_finish_with_keep_going(tmp_path):
    """Seed 2's packing given two nearly coincident spheres: its startup blows up (LAMMPS
    error, NaN or an overlap beyond run.max_overlap) and fails with the reason in its log,
    the partial or failed run kept for inspection; with --keep-going seed 1's startup, rotations and
    fabric tables all finish; rerunning does not touch them."""
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((workdir / "config/test.yaml").read_text())
    assert config["seeds"] == [1, 2]
    packings = [f"{RESULTS}/seed{s}/packing/packing.data" for s in (1, 2)]
    assert snakemake(workdir, *TEST_CONFIG, "--", *packings).returncode == 0
    data = workdir / packings[1]
    lines = data.read_text().splitlines(keepends=True)
    start = next(k for k, line in enumerate(lines) if line.startswith("Atoms")) + 2
    first, second = lines[start].split(), lines[start + 1].split()
    second[4:7] = [str(float(first[4]) + 0.05), first[5], first[6]]  # 0.05 d apart: overlap ~0.95 d
    lines[start + 1] = " ".join(second) + "\n"
    data.write_text("".join(lines))

    result = snakemake(workdir, *TEST_CONFIG, "--keep-going")
    assert result.returncode != 0
    log = (workdir / RESULTS / "logs/shear_seed2_startup.log").read_text()
    assert "LammpsRunError" in log and "LAMMPS startup (segment 0: 0.3 strain at 0 deg) run failed" in log
    assert any(reason in log for reason in ("Lost atoms", "non-finite", "overlap", "ERROR"))
    # kept for inspection: a run that stopped as .startup.partial, one that ended but failed its
    # checks (here the overlap bound) as startup.failed
    assert (workdir / RESULTS / "seed2/.startup.partial").is_dir() or (
        workdir / RESULTS / "seed2/startup.failed"
    ).is_dir()
    assert not (workdir / RESULTS / "seed2/startup/run_complete.json").exists()
    for run in ("startup", "rotation_theta0", "rotation_theta90"):
        assert (workdir / RESULTS / f"seed1/{run}/fabric.csv").is_file(), run
    finished = {p: p.stat().st_mtime_ns for p in (workdir / RESULTS / "seed1").rglob("*") if p.is_file()}
    again = snakemake(workdir, *TEST_CONFIG, "--keep-going")
    assert again.returncode != 0
    assert {p: p.stat().st_mtime_ns for p in finished} == finished


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("seeds", [1, 2, 1], "config key 'seeds': [1, 2, 1] has non-unique elements"),
        ("angles_deg", [0, 90, 90.0], "config key 'angles_deg': [0, 90, 90.0] has non-unique elements"),
        ("angles_deg", [30, 30.0000001], "config key 'angles_deg': angles collide after formatting"),
    ],
)
@pytest.mark.fault("refused")
def test_duplicate_seeds_or_angles_stop_before_any_job(tmp_path, key, value, message):
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((workdir / "config/test.yaml").read_text())
    config[key] = value
    (workdir / "config/bad.yaml").write_text(yaml.safe_dump(config))
    result = snakemake(workdir, "--configfile", "config/bad.yaml")
    assert result.returncode != 0 and message in result.stdout + result.stderr
    assert not (workdir / "results").exists()


@pytest.mark.fault("refused")
def test_pack_into_an_existing_folder_needs_overwrite(tmp_path):
    """Nothing finished is silently overwritten: a second pack into the same folder refuses."""
    first = pack(tmp_path / "packing", 20, seed=1)
    with pytest.raises(FileExistsError, match="pass overwrite=True"):
        pack(tmp_path / "packing", 20, seed=2)
    assert first.data_file.is_file()


# the run records of the test study's rotations
ROTATION_RECORDS = [
    f"{RESULTS}/seed{seed}/rotation_theta{angle}/run_complete.json" for seed in (1, 2) for angle in (0, 90)
]
LONGER_ROTATIONS = ["--config", "run={rotation_strain: 2.0}"]  # trajectories of about 0.6 MB
FAILED_RERUN = ["--config", "run={rotation_strain: 40.0}"]  # more than the small disk holds


def assert_failed_rerun_kept_the_study(workdir, result, before, message):
    """The rerun failed and its segments' logs say why; every finished run's data and every table is
    unchanged, and only the completion markers of the failed segments are gone (Snakemake deletes
    them, so that the failed segments are planned again)."""
    assert result.returncode != 0
    logs = [path.read_text() for path in (workdir / RESULTS / "logs").glob("shear_seed*_rotation_theta*.log")]
    assert any(message in log for log in logs), "\n".join(log[-800:] for log in logs)
    after = result_digests(workdir)
    gone = set(before) - set(after)
    assert gone and all(name.endswith("/run_complete.json") and "rotation_theta" in name for name in gone), gone
    assert after == {name: digest for name, digest in before.items() if name not in gone}


@pytest.mark.fault("named")
def test_a_file_size_limit_fails_the_rerun_naming_it_and_keeps_every_finished_run(finished_study):
    """The trajectory outgrows the file-size limit (ulimit -f, as a quota does): LAMMPS is killed by
    SIGXFSZ, the segment's log names the signal and its meaning, the finished runs' data stay as they
    were, and the same rerun without the limit continues the killed runs and finishes."""
    before = result_digests(finished_study)

    def limit_file_size():
        resource.setrlimit(resource.RLIMIT_FSIZE, (300_000, 300_000))

    result = subprocess.run(
        [str(SNAKEMAKE), "--cores", "2", *TEST_CONFIG, *LONGER_ROTATIONS],
        cwd=finished_study,
        capture_output=True,
        text=True,
        timeout=600,
        preexec_fn=limit_file_size,
    )
    assert_failed_rerun_kept_the_study(
        finished_study, result, before, "killed by SIGXFSZ (a file reached the file-size limit"
    )
    # the rotations only: the analysis after them is the same as after any rerun
    rerun = snakemake(finished_study, *TEST_CONFIG, *LONGER_ROTATIONS, "--", *ROTATION_RECORDS)
    assert rerun.returncode == 0, rerun.stderr[-3000:]
    for record in ROTATION_RECORDS:
        assert json.loads((finished_study / record).read_text())["flow_segment"]["strain"] == pytest.approx(2.0)


@pytest.fixture
def small_disk(finished_study, tmp_path):
    """The finished study on a file system with 3 MB free (a tmpfs; needs root)."""
    mount_point = tmp_path / "disk"
    mount_point.mkdir()
    size = sum(p.stat().st_size for p in finished_study.rglob("*") if p.is_file()) + 3_000_000
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(mount_point)], capture_output=True
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here: {mounted.stderr.decode().strip()}")
    try:
        shutil.copytree(finished_study, mount_point / "checkout", symlinks=True)
        yield mount_point / "checkout"
    finally:
        subprocess.run(["umount", "-l", str(mount_point)], check=True)


@pytest.mark.fault("named")
def test_a_full_disk_fails_the_rerun_naming_it_and_keeps_every_finished_run(small_disk):
    """The disk fills during the rerun (ENOSPC, not a limit): the job's log names it and the finished
    runs' data stay. With space freed (the unfinished runs' work folders removed) and the change
    dropped, the next run of the rotations finds the finished runs asked for, puts their markers
    back, simulates nothing, and the study is byte for byte as before (the analysis after restored
    runs is made again in tests/workflow/test_interrupted_rerun.py)."""
    before = result_digests(small_disk)
    result = snakemake(small_disk, *TEST_CONFIG, *FAILED_RERUN)
    assert_failed_rerun_kept_the_study(small_disk, result, before, "No space left on device")
    for work in (small_disk / RESULTS).glob("seed*/.rotation_theta*.partial"):
        shutil.rmtree(work)
    shutil.rmtree(small_disk / ".snakemake/backups", ignore_errors=True)
    again = snakemake(small_disk, *ROTATION_RECORDS, *TEST_CONFIG)
    assert again.returncode == 0, again.stderr[-3000:]
    assert "shear_segment" in job_counts(again.stdout + again.stderr)
    assert result_digests(small_disk) == before


@pytest.mark.fault("named")
def test_a_kn_too_soft_for_the_first_strains_pressure_fails_the_startups_stress_table(tmp_path):
    """The startup checks the stiffness against the pressure it measures in its first strain
    (engine_rule.check_first_strain: kn / (eta_f Pi) >= 3e4 / 1.5, Pi the mean over strain 0.5-1).
    The test study sheared to strain 1 at a tenth of its kn (allowed by raising
    run.max_contact_relaxation_strain) fails the startup's stress table naming forces.kn and the kn it
    needs; the finished startup run is kept."""
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((workdir / "config/test.yaml").read_text())
    config["seeds"] = [1]
    config["forces"]["kn"] /= 10.0
    config["run"].update(startup_strain=1.0, max_contact_relaxation_strain=0.1)
    soft = workdir / "config/soft.yaml"
    soft.write_text(yaml.safe_dump(config))
    table = f"{RESULTS}/seed1/startup/stress.csv"
    result = snakemake(workdir, "--configfile", str(soft), "--", table)
    assert result.returncode != 0
    log = (workdir / RESULTS / "logs/stress_seed1_startup.log").read_text()
    assert "config key 'forces.kn' = 5.6e+04 below the stiff limit" in log
    assert "Raise forces.kn to at least" in log and "run.engine: rule" in log
    assert (workdir / RESULTS / "seed1/startup/run_complete.json").is_file()
    assert not (workdir / table).exists()

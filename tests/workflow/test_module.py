"""This workflow imported as a module by another one (docs/workflow.md, "Using the workflow as a
module"): the Snakefile the docs show, in a folder outside the repository with its own config (the
test study under another name), runs the whole study there for real, and a second run has nothing
to do. Its fits are those of the session's direct run of the same study (conftest.py)."""

import json
import re
import shutil

import pandas as pd
import pytest
import yaml

from workflow_helpers import REPO, RESULTS, job_counts, snakemake

pytestmark = pytest.mark.workflow

STUDY = "imported"  # not the test study's name: the module runs the config it is given
PLACEHOLDER = "/path/to/suspension-fabric"  # the checkout's path in the docs' snippet


def documented_snakefile() -> str:
    """The importing Snakefile of docs/workflow.md, with this repository's path in it."""
    text = (REPO / "docs" / "workflow.md").read_text()
    section = text[text.index("### Using the workflow as a module") :]
    block = re.search(r"\n\n((?:    configfile:.*\n)(?:    .*\n|\n)*)", section).group(1)
    return "\n".join(line[4:] for line in block.rstrip().splitlines()).replace(PLACEHOLDER, str(REPO)) + "\n"


def importing_workflow(workdir, config, snakefile=None):
    """A folder importing this workflow with ``config`` as config/config.yaml (no run)."""
    (workdir / "config").mkdir()
    (workdir / "config" / "config.yaml").write_text(yaml.safe_dump(config, sort_keys=False))
    (workdir / "Snakefile").write_text(snakefile or documented_snakefile())
    return workdir


@pytest.fixture(scope="module")
def importer(tmp_path_factory):
    """The importing workflow's folder after one run of the study (a snakemake run's result too)."""
    workdir = tmp_path_factory.mktemp("importer")
    assert not workdir.resolve().is_relative_to(REPO)
    config = yaml.safe_load((REPO / "config" / "test.yaml").read_text())
    importing_workflow(workdir, {**config, "study": STUDY})
    (workdir / "profiles" / "default").mkdir(parents=True)  # as the docs say: the checkout's profile
    shutil.copy(REPO / "profiles" / "default" / "config.yaml", workdir / "profiles" / "default" / "config.yaml")
    return workdir, snakemake(workdir)


def test_the_docs_snakefile_imports_this_checkout():
    snakefile = documented_snakefile()
    assert f'snakefile:\n        "{REPO}/Snakefile"' in snakefile and "use rule * from study" in snakefile


def test_an_importing_workflow_runs_the_study_with_its_own_config(importer):
    workdir, result = importer
    assert result.returncode == 0, result.stderr[-4000:]
    results = workdir / "results" / STUDY
    for stem in ("fig1_startup", "fig2_rotation", "fig3_stress", "fig5_claims"):
        assert (results / "figures" / f"{stem}.png").stat().st_size > 10_000
    fits = json.loads((results / "fits.json").read_text())
    assert set(fits["models"]) == {"gw", "modified", "separate_rates"} and fits["provenance"]["seeds"] == [1, 2]
    verdicts = pd.read_csv(results / "tables" / "verdicts.csv")
    assert len(verdicts) > 0
    assert (results / "tables" / "fits.html").is_file() and (results / "tables" / "model_errors.csv").is_file()
    # the plugin copied next to the results, nothing written into the checkout
    assert (workdir / "build" / "plugin").is_dir() and not (REPO / "results" / STUDY).exists()
    again = snakemake(workdir)
    assert again.returncode == 0, again.stderr[-4000:]
    assert "Nothing to be done" in again.stdout + again.stderr


def test_the_report_of_the_imported_study(importer):
    """The report takes the module's description (workflow/report, relative to its Snakefile) and captions."""
    workdir, result = importer
    assert result.returncode == 0, result.stderr[-4000:]
    report = snakemake(workdir, "--report", "report.html", timeout=300)
    assert report.returncode == 0, report.stderr[-3000:]
    html = (workdir / "report.html").read_text(errors="replace")
    assert "Shear-rotation fabric study" in html and "fig1_startup.png" in html and "fits.html" in html


def test_a_dataset_study_finds_the_checkouts_dataset_and_model_file(tmp_path):
    """config/reference.yaml names data/reference and data/models/sparse_reference.json, relative
    paths that are not in the importing folder: they are taken from the checkout (dry run)."""
    config = yaml.safe_load((REPO / "config" / "reference.yaml").read_text())
    result = snakemake(importing_workflow(tmp_path, config), "-n")
    assert result.returncode == 0, result.stderr[-4000:]
    counts = job_counts(result.stdout)
    assert counts["study_import_run_tables"] == 1 and "study_shear_segment" not in counts
    assert f"{REPO}/data/reference/dataset.json" in result.stdout


@pytest.mark.parametrize(
    "change, message",
    [
        ({"particles": {"n": "many"}}, "the module's config: config key 'particles.n': 'many' is not of type"),
        (None, "the module's config: this workflow imported as a module needs its study's config"),
    ],
)
def test_a_bad_or_missing_module_config_is_refused_naming_it(tmp_path, change, message):
    config = yaml.safe_load((REPO / "config" / "test.yaml").read_text())
    snakefile = documented_snakefile()
    if change is None:  # no `config:` in the module statement
        snakefile = snakefile.replace("    config:\n        config\n", "")
        assert "config:" not in snakefile.split("module study:")[1]
    else:
        config.update(change)
    result = snakemake(importing_workflow(tmp_path, config, snakefile), "-n")
    assert result.returncode != 0 and message in result.stdout + result.stderr


def test_the_imported_study_fits_as_the_direct_run(importer, study):
    """Same config but the name, same engine: the same fits as `snakemake --configfile config/test.yaml`."""
    workdir, result = importer
    assert result.returncode == 0, result.stderr[-4000:]
    imported = json.loads((workdir / "results" / STUDY / "fits.json").read_text())
    direct = json.loads((study / RESULTS / "fits.json").read_text())
    assert imported["models"] == direct["models"] and imported["targets"] == direct["targets"]

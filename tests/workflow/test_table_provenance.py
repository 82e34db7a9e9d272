"""Checked provenance of the derived tables (suspension_fabric.io.table_provenance), on the real
test study: every analysis job records, beside each table it writes, the table's SHA-256 and those
of the tables it read; a table edited after its rule wrote it is refused by the next job that reads
it, naming the file and the rule, until the edit is accepted."""

import json

import pytest

from suspension_fabric.io.table_provenance import ProvenanceError, check_inputs, main, record_path
from workflow_helpers import RESULTS, TEST_CONFIG, snakemake

pytestmark = pytest.mark.workflow


def test_every_derived_table_has_its_record(study):
    tables = study / RESULTS / "tables"
    record = json.loads(record_path(tables / "startup_runs.csv").read_text())
    assert record["rule"] == "aggregate_startup" and len(record["sha256"]) == 64
    assert any(path.endswith("/startup/fabric.csv") for path in record["inputs"])
    fits = json.loads(record_path(study / RESULTS / "fits.json").read_text())
    assert fits["inputs"][f"{RESULTS}/tables/startup_runs.csv"] == record["sha256"]
    check_inputs([tables / "startup_runs.csv", study / RESULTS / "fits.json"])  # unchanged: accepted


def test_an_edited_table_is_refused_downstream_until_the_edit_is_accepted(finished_study, monkeypatch):
    table = finished_study / RESULTS / "tables/startup_runs.csv"
    lines = table.read_text().splitlines(keepends=True)
    lines[1] = lines[1].replace(",", ",9", 1)  # a digit typed into the first row
    table.write_text("".join(lines))
    result = snakemake(finished_study, f"{RESULTS}/fits.json", *TEST_CONFIG)
    assert result.returncode != 0
    log = (finished_study / RESULTS / "logs/fit_models.log").read_text()
    assert f"{RESULTS}/tables/startup_runs.csv: changed since rule aggregate_startup wrote it" in log
    assert "suspension_fabric.io.table_provenance accept" in log
    monkeypatch.chdir(finished_study)
    with pytest.raises(ProvenanceError, match="changed since rule aggregate_startup"):
        check_inputs([table.relative_to(finished_study)])
    main(["accept", str(table.relative_to(finished_study))])
    check_inputs([table.relative_to(finished_study)])
    assert "accepted_utc" in json.loads(record_path(table).read_text())

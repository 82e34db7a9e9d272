"""Checked provenance of every derived table: what a rule wrote, and what it read.

Each job of the workflow's analysis rules records, beside every table it writes, a small record
``.<name>.provenance.json`` in the same folder: the rule, the table's SHA-256 and the SHA-256 of
every table it read. A job that reads a table with such a record first checks the table against
it, and refuses a table changed since its rule wrote it, naming the file, the rule and both
hashes: without this, an edited intermediate table would flow silently into every figure
downstream (Snakemake reruns the jobs that read it, with the edit). Every analysis script runs
inside [`checked_tables`][suspension_fabric.io.table_provenance.checked_tables]; the simulations' own outputs
are not recorded here: their run records (run_complete.json) and checks guard them.

To keep a deliberate edit, accept it (the record then holds the edited table's hash and says
when it was accepted)::

    python -m suspension_fabric.io.table_provenance accept results/<study>/tables/<table>.csv

or delete the table to have the workflow make it again.
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import time
from collections.abc import Iterable
from pathlib import Path

__all__ = [
    "TRACKED_SUFFIXES",
    "ProvenanceError",
    "record_path",
    "check_inputs",
    "record_outputs",
    "checked_tables",
    "accept",
    "main",
]

#: Files that are tables (or table-like records) and get a provenance record; trajectories,
#: checkpoints and figures do not.
TRACKED_SUFFIXES = (".csv", ".json", ".md", ".txt", ".gz")


class ProvenanceError(ValueError):
    """A table that differs from what its rule wrote; the message names the file and the rule."""


def record_path(path: str | Path) -> Path:
    """The provenance record of a table: ``.<name>.provenance.json`` beside it."""
    path = Path(path)
    return path.with_name(f".{path.name}.provenance.json")


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _tables(paths: Iterable) -> list[Path]:
    """The tracked regular files among ``paths`` (nested lists of Snakemake's input or output)."""
    found = []
    for item in paths:
        if isinstance(item, (list, tuple)):
            found += _tables(item)
            continue
        path = Path(str(item))
        if path.suffix in TRACKED_SUFFIXES and not path.name.endswith(".provenance.json") and path.is_file():
            found.append(path)
    return found


def check_inputs(inputs: Iterable) -> dict[str, str]:
    """Every input table with a provenance record must be the table its rule wrote; returns the
    SHA-256 of every input table, for the records of the job's outputs."""
    read = {}
    for path in _tables(inputs):
        now = read[str(path)] = _sha256(path)
        record_file = record_path(path)
        if not record_file.is_file():
            continue
        record = json.loads(record_file.read_text())
        if now != record["sha256"]:
            raise ProvenanceError(
                f"{path}: changed since rule {record['rule']} wrote it (SHA-256 {record['sha256'][:12]}... "
                f"recorded, {now[:12]}... now); keep a deliberate edit with `python -m "
                f"suspension_fabric.io.table_provenance accept {path}`, or delete it to have the workflow make it again"
            )
    return read


def record_outputs(rule: str, read: dict[str, str], outputs: Iterable) -> None:
    """Record, beside every output table, the rule, its SHA-256 and those of the input tables it
    read (``read``, from `check_inputs`)."""
    for path in _tables(outputs):
        record = {"rule": rule, "sha256": _sha256(path), "inputs": read}
        record_path(path).write_text(json.dumps(record, indent=1) + "\n")


@contextlib.contextmanager
def checked_tables(job):
    """Around a workflow script (``job`` its Snakemake object): its input tables checked against
    their records before the block, its output tables recorded after it."""
    read = check_inputs(job.input)
    yield
    record_outputs(job.rule, read, job.output)


def accept(path: str | Path) -> Path:
    """Make a deliberately edited table's record hold its current hash (``accepted_utc`` says when)."""
    path = Path(path)
    record_file = record_path(path)
    if not record_file.is_file():
        raise FileNotFoundError(f"{path} has no provenance record ({record_file.name}): nothing to accept")
    record = json.loads(record_file.read_text())
    record.update(sha256=_sha256(path), accepted_utc=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()))
    record_file.write_text(json.dumps(record, indent=1) + "\n")
    return record_file


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="python -m suspension_fabric.io.table_provenance", description=__doc__.split("\n\n")[0]
    )
    commands = parser.add_subparsers(dest="command", required=True)
    keep = commands.add_parser("accept", help="keep a deliberately edited table: record its current SHA-256")
    keep.add_argument("tables", nargs="+")
    args = parser.parse_args(argv)
    for table in args.tables:
        print(f"accepted: {table} ({accept(table)})")


if __name__ == "__main__":
    main()

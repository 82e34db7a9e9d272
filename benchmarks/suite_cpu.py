"""Where the test suite's CPU goes: every Python process it starts, by script and by test.

    .venv/bin/python benchmarks/suite_cpu.py run --record benchmarks/data/suite_cpu/<commit>.tsv [pytest arguments]
    .venv/bin/python benchmarks/suite_cpu.py report benchmarks/data/suite_cpu/<commit>.tsv [--top 25]

`run` runs the test suite (``python -m pytest -q`` with the project's options and the given
arguments) with a ``sitecustomize`` module first on PYTHONPATH. Every Python process that starts
from it (the pytest workers, each Snakemake run, each Snakemake job's script, each simulation
runner) records at exit one line: its pid, its script (Snakemake's copies of the workflow's scripts
by their name), its own CPU seconds, those of the children it waited for (LAMMPS under a runner),
its wall seconds and the test that started it (pytest's ``PYTEST_CURRENT_TEST``, which the
subprocesses inherit). Processes killed by a signal record nothing; nor do programs that are not
Python (``lmp``, ``mpirun``) except through the children's CPU of the process that waited for them.
`run` prints the suite's wall time and the CPU of its process tree.

`report` prints, from a record, the CPU of the scripts (summed over their processes, with the
count), of the tests (every process a test started, Snakemake's own process counted apart) and of
the processes started outside any test: those of the study on SLURM, which conftest.py starts when
the tests are collected (its Snakemake job steps run as ``python -m snakemake``, recorded as
``__main__.py``). pytest and its workers, which live as long as the suite, are left out of that
count.

The suite is CPU-bound on two cores (both busy from the first test to the last), so its wall time
is about half its CPU: these tables say where a cut pays.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

REPO = Path(__file__).resolve().parents[1]
COLUMNS = ["pid", "script", "cpu_s", "children_cpu_s", "wall_s", "test"]

RECORDER = """
import atexit, os, resource, sys, time

_START = time.time()


def _record():
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    script = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else "-c"
    fields = (
        os.getpid(),
        script,
        f"{own.ru_utime + own.ru_stime:.2f}",
        f"{children.ru_utime + children.ru_stime:.2f}",
        f"{time.time() - _START:.2f}",
        os.environ.get("PYTEST_CURRENT_TEST", ""),
    )
    try:
        with open(os.environ["SUITE_CPU_RECORD"], "a") as out:
            out.write("\\t".join(str(f).replace("\\t", " ") for f in fields) + "\\n")
    except (KeyError, OSError):
        pass


atexit.register(_record)
"""


def run(record: Path, pytest_args: list[str]) -> None:
    record.parent.mkdir(parents=True, exist_ok=True)
    if record.exists():
        raise SystemExit(f"{record} exists: give a new file (a record is appended to by every process)")
    with tempfile.TemporaryDirectory() as folder:
        Path(folder, "sitecustomize.py").write_text(RECORDER)
        path = os.pathsep.join(p for p in (folder, os.environ.get("PYTHONPATH", "")) if p)
        env = dict(os.environ, PYTHONPATH=path, SUITE_CPU_RECORD=str(record.resolve()))
        start = time.time()
        result = subprocess.run([sys.executable, "-m", "pytest", "-q", *pytest_args], cwd=REPO, env=env)
        wall = time.time() - start
    tree = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = tree.ru_utime + tree.ru_stime
    print(f"pytest exit {result.returncode}; wall {wall:.0f} s; CPU of its process tree {cpu:.0f} s")


def read_record(record: Path) -> pd.DataFrame:
    table = pd.read_csv(record, sep="\t", names=COLUMNS, keep_default_na=False)
    # Snakemake runs a job's script as .snakemake/scripts/tmpXXXXXXXX.<name>.py
    table["script"] = table["script"].str.replace(r"^tmp[a-z0-9_]{8}\.", "", regex=True)
    table["test"] = table["test"].str.replace(r" \((setup|call|teardown)\)$", "", regex=True)
    return table


def outside_tests(table: pd.DataFrame) -> pd.DataFrame:
    """The processes no test started, but for pytest and its workers (those that lived through more
    than half of the longest life in the record)."""
    session = table["wall_s"] > 0.5 * table["wall_s"].max()
    return table[(table["test"] == "") & ~session]


def outside_summary(table: pd.DataFrame) -> dict[str, float]:
    """The processes outside any test (`outside_tests`) and the Snakemake job steps among them (run as
    ``python -m snakemake``, recorded as ``__main__.py``): their counts and CPU seconds."""
    outside = outside_tests(table)
    steps = outside[outside["script"] == "__main__.py"]
    return {
        "processes": len(outside),
        "cpu_s": float(outside["cpu_s"].sum()),
        "job_steps": len(steps),
        "job_steps_cpu_s": float(steps["cpu_s"].sum()),
    }


def report(record: Path, top: int) -> None:
    table = read_record(record)
    print(f"{len(table)} Python processes, {table['cpu_s'].sum():.0f} CPU s of their own\n")
    scripts = table.groupby("script").agg(processes=("pid", "size"), cpu_s=("cpu_s", "sum"))
    scripts["cpu_s_each"] = scripts["cpu_s"] / scripts["processes"]
    print(scripts.sort_values("cpu_s", ascending=False).head(top).round(2).to_markdown())
    tests = table[table["test"] != ""].copy()
    tests["snakemake_cpu_s"] = tests["cpu_s"].where(tests["script"] == "snakemake", 0.0)
    tests["test"] = tests["test"].map(lambda t: re.sub(r"^tests/", "", t))
    per_test = tests.groupby("test").agg(
        processes=("pid", "size"), cpu_s=("cpu_s", "sum"), snakemake_cpu_s=("snakemake_cpu_s", "sum")
    )
    print()
    print(per_test.sort_values("cpu_s", ascending=False).head(top).round(1).to_markdown())
    outside = outside_summary(table)
    print(
        f"\noutside any test: {outside['processes']} processes, {outside['cpu_s']:.0f} CPU s "
        f"(Snakemake job steps: {outside['job_steps']}, {outside['job_steps_cpu_s']:.0f} CPU s)"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    run_parser = commands.add_parser("run", help="run the suite, recording every Python process's CPU")
    run_parser.add_argument("--record", type=Path, required=True)
    report_parser = commands.add_parser("report", help="the CPU by script and by test of a record")
    report_parser.add_argument("record", type=Path)
    report_parser.add_argument("--top", type=int, default=25)
    args, rest = parser.parse_known_args(argv)
    if args.command == "run":
        run(args.record, rest)
    else:
        if rest:
            parser.error(f"unrecognized arguments: {' '.join(rest)}")
        report(args.record, args.top)


if __name__ == "__main__":
    main()

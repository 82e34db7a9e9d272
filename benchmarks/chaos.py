"""The study under random kills at full size (tests/chaos_helpers.py): the test study made once
without interruption, then again from scratch in another folder while SIGKILLs land at random
moments, and the two results/ trees compared file by file.

    .venv/bin/python benchmarks/chaos.py --kills 20 --seed 20261207    # Markdown for BENCHMARKS.md

Prints the schedule (round, kind, delay drawn, victim, Snakemake's exit status), the counts by
kind, whether the final run succeeded, the folders left behind and the number of files that differ
from the uninterrupted run's. Writes the schedule to benchmarks/data/chaos_rounds.csv.
"""

from __future__ import annotations

import argparse
import collections
import csv
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from chaos_helpers import KINDS, chaos_run, comparable_digests, leftovers, resumed_runs, rounds_table  # noqa: E402
from workflow_helpers import TEST_CONFIG, copy_workflow, snakemake  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--seed", type=int, default=20261207)
    parser.add_argument("--max-delay", type=float, default=6.0, help="largest wait before a kill (s)")
    parser.add_argument("--keep", type=Path, help="make both studies in this folder and keep them")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        scratch = args.keep or scratch
        reference = copy_workflow(Path(scratch) / "reference")
        started = time.monotonic()
        made = snakemake(reference, *TEST_CONFIG)
        if made.returncode != 0:
            raise SystemExit(f"the uninterrupted study failed:\n{made.stderr[-3000:]}")
        uninterrupted = time.monotonic() - started
        workdir = copy_workflow(Path(scratch) / "chaos")
        started = time.monotonic()
        rounds, final = chaos_run(workdir, TEST_CONFIG, args.kills, args.seed, args.max_delay)
        elapsed = time.monotonic() - started
        left = leftovers(workdir)
        mine, theirs = comparable_digests(workdir), comparable_digests(reference)
        differing = sorted(name for name in mine.keys() | theirs.keys() if mine.get(name) != theirs.get(name))
        resumed = resumed_runs(workdir)
    table = rounds_table(rounds)
    with open(ROOT / "benchmarks" / "data" / "chaos_rounds.csv", "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=list(table[0]))
        writer.writeheader()
        writer.writerows(table)
    landed = collections.Counter(r.kind for r in rounds if r.victim != "nothing")
    print(f"seed {args.seed}, {args.kills} kills asked, max delay {args.max_delay:g} s")
    print("| round | kind | delay (s) | victim | Snakemake exit |\n|---|---|---|---|---|")
    for r in rounds:
        print(f"| {r.round} | {r.kind} | {r.delay:.2f} | {r.victim} | {r.snakemake_exit} |")
    print()
    print("kills landed: " + ", ".join(f"{kind} {landed[kind]}" for kind in KINDS) + f" (all {sum(landed.values())})")
    print(f"final run exit status {final}; uninterrupted study {uninterrupted:.0f} s, under kills {elapsed:.0f} s")
    print(f"left behind: {left or 'nothing'}")
    print(f"runs resumed part-way (run: steps): {resumed or 'none'}")
    print(f"files differing from the uninterrupted run: {len(differing)} of {len(theirs)} {differing[:10]}")


if __name__ == "__main__":
    main()

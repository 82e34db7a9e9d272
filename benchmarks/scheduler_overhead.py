"""The CPU that Snakemake's own process spends scheduling, against the settings of its scheduler.

    .venv/bin/python benchmarks/scheduler_overhead.py [--rounds 1] [--save benchmarks/data/scheduler_overhead.csv]

The map's rebuild from the committed datasets (data/campaign, config/campaign.yaml with
config/map.yaml: 121 analysis jobs, no simulation) in a fresh copy of the workflow, once per
setting and round, the settings interleaved: Snakemake's defaults (the ILP scheduler, at most 100
jobs started per second), the greedy scheduler (profiles/default/config.yaml), and the greedy
scheduler with a rate limit of 1000 jobs per minute (less scheduling, but Snakemake then waits for
its pending wake-up, up to a minute, before it exits). The copy has no profiles/ folder, so each run has
only the settings given. Prints per run the wall time, the CPU of Snakemake's own process and that
of everything it ran (the jobs).

Why the rate limit's span matters: after every pass over the ready jobs, Snakemake's scheduler starts a
timer that wakes it once the limit's timespan has passed, whatever woke it; a pass woken by a
finished job starts one more such chain, so with a 1 s span a run of n jobs ends up passing over
its ready jobs about n times a second, each pass checking the size of every input of every ready
job.
"""

from __future__ import annotations

import argparse
import csv
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = Path(sys.executable).with_name("snakemake")
TARGET = ["results/map/tables/map_summary.md", "--configfile", "config/campaign.yaml", "config/map.yaml"]
SETTINGS = {
    "defaults (ilp, 100/1s)": [],
    "greedy": ["--scheduler", "greedy"],
    "greedy, 1000/1m": ["--scheduler", "greedy", "--max-jobs-per-timespan", "1000/1m"],
}
#: Runs Snakemake's command line in this process and writes the process's own CPU seconds (not
#: its children's) to the file named by the first argument when it exits.
MAIN_CPU = """
import atexit, resource, runpy, sys
out = sys.argv.pop(1)
def record():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    open(out, "w").write(str(usage.ru_utime + usage.ru_stime))
atexit.register(record)
sys.argv[0] = sys.argv.pop(1)
runpy.run_path(sys.argv[0], run_name="__main__")
"""


def copy_study(target: Path) -> Path:
    for name in ("config", "workflow", "envs"):
        shutil.copytree(REPO / name, target / name, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(REPO / "Snakefile", target / "Snakefile")
    shutil.copytree(REPO / "data" / "campaign", target / "data" / "campaign")
    return target


def run(workdir: Path, options: list[str]) -> dict[str, float]:
    shutil.rmtree(workdir / "results", ignore_errors=True)
    shutil.rmtree(workdir / ".snakemake", ignore_errors=True)
    main_cpu = workdir / "main_cpu.txt"
    command = [sys.executable, "-c", MAIN_CPU, str(main_cpu), str(SNAKEMAKE), "--cores", "2", *options, *TARGET]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(command, cwd=workdir, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        raise SystemExit(f"snakemake {' '.join(options)} failed:\n{result.stderr[-3000:]}")
    total = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    main = float(main_cpu.read_text())
    return {"wall": wall, "main": main, "jobs": total - main}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--save", type=Path, help="also write the rows to this CSV file")
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        workdir = copy_study(Path(folder))
        print("| setting | round | wall s | Snakemake's process, CPU s | its jobs, CPU s |")
        print("|---|--:|--:|--:|--:|")
        for round_ in range(1, args.rounds + 1):
            for name, options in SETTINGS.items():
                row = run(workdir, options)
                rows.append({"setting": name, "round": round_, **row})
                print(f"| {name} | {round_} | {row['wall']:.0f} | {row['main']:.1f} | {row['jobs']:.0f} |", flush=True)

    if args.save:
        with open(args.save, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()

"""The rebuilds from committed data under two floating-point configurations: which printed digits move.

    .venv/bin/python benchmarks/float_configs.py [--studies reference protocols ...]

Each study is rebuilt twice without simulating, in two copies of the workflow: with the machine's
own BLAS kernels and NumPy loops, and with the second configuration of the test suite
(tests/workflow_helpers.py: OpenBLAS's Prescott kernels, NumPy's dispatched SIMD loops off). For
every generated Markdown fragment it counts the printed numbers and those that differ between the
two (and by more than one unit of their last digit); for every CSV table the largest difference of
a number in units of its column's largest value. Prints Markdown tables for BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from quoted_numbers import fragment_problems  # noqa: E402
from workflow_helpers import copy_workflow, second_float_config  # noqa: E402

#: study -> (config files, data folders it needs, its results folder)
STUDIES = {
    "reference": (["config/reference.yaml"], ["data"], "results/reference"),
    "protocols": (
        ["config/protocols_reference.yaml"],
        ["data/protocols", "data/models"],
        "results/protocols_reference",
    ),
    "map": (["config/campaign.yaml", "config/map.yaml"], ["data/campaign"], "results/map"),
    "default": (["config/default_reference.yaml"], ["data/default"], "results/default_reference"),
}
_NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def rebuild(study: str, env: dict | None, where: Path) -> tuple[Path, float]:
    configs, data, results = STUDIES[study]
    workdir = copy_workflow(where)
    for folder in data:
        shutil.copytree(REPO / folder, workdir / folder)
    start = time.perf_counter()
    command = [str(Path(sys.executable).with_name("snakemake")), "--cores", "2", "--configfile", *configs]
    done = subprocess.run(command, cwd=workdir, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{study}: rebuild failed\n{done.stderr[-3000:]}")
    return workdir / results, time.perf_counter() - start


def compare(first: Path, second: Path) -> tuple[list[str], list[str]]:
    fragments, tables = [], []
    for path in sorted(first.rglob("*.md")):
        other = second / path.relative_to(first)
        a, b = path.read_text(), other.read_text()
        numbers = _NUMBER.findall(a)
        moved = sum(x != y for x, y in zip(numbers, _NUMBER.findall(b)))
        beyond = len(fragment_problems(a, b))
        fragments.append(f"| {path.relative_to(first)} | {len(numbers)} | {moved} | {beyond} |")
    for path in sorted(first.rglob("*.csv")):
        if path.stat().st_size == 0:  # a table a rule leaves empty (no sparse model on a small study)
            continue
        a, b = pd.read_csv(path), pd.read_csv(second / path.relative_to(first))
        x, y = a.select_dtypes("number").to_numpy(dtype=float), b.select_dtypes("number").to_numpy(dtype=float)
        if x.size == 0 or x.shape != y.shape:
            continue
        # each difference in units of its column's largest value: a number at round-off next to
        # the column's scale (a component kept at 0 by symmetry) is not a relative change of 1
        scale = np.nanmax(np.abs(np.where(np.isfinite(x), x, np.nan)), axis=0, initial=0.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            relative = np.where(scale > 0, np.abs(x - y) / scale, 0.0)
        worst = float(np.nanmax(relative)) if np.isfinite(relative).any() else 0.0
        if worst > 0:
            tables.append(f"| {path.relative_to(first)} | {worst:.1e} |")
    return fragments, tables


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--studies", nargs="+", default=list(STUDIES), choices=list(STUDIES))
    args = parser.parse_args(argv)
    for study in args.studies:
        with tempfile.TemporaryDirectory() as scratch:
            native, native_s = rebuild(study, None, Path(scratch) / "native")
            second, second_s = rebuild(study, second_float_config(), Path(scratch) / "second")
            fragments, tables = compare(native, second)
        print(f"\n{study}: rebuilt in {native_s:.0f} s (native) and {second_s:.0f} s (second configuration)\n")
        print("| fragment | printed numbers | differ | differ by more than a unit of the last digit |")
        print("|---|---|---|---|")
        print("\n".join(fragments))
        print("\n| table whose numbers differ | largest difference / column's largest value |\n|---|---|")
        print("\n".join(tables) or "| (none) | 0 |")


if __name__ == "__main__":
    main()

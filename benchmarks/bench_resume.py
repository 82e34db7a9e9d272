"""What resuming a killed simulation saves, at the default study's size and settings.

One N = 500 packing (seed 1), startup shear to strain 5 with the default settings (implicit
integrator, dt = 2e-5, restart files every 0.5 strain):
  1. uninterrupted: its LAMMPS wall time is the cost of a rerun from strain 0;
  2. the same run in a subprocess, SIGKILLed (lmp's process group) once its stress table
     passes --kill-strain; then run_startup again, which continues from the newest restart.
Prints the wall time of the resumed part and of the whole second call (restart probe,
stitching and output checks included) against the uninterrupted run, and checks that the
stitched table has the uninterrupted run's steps and its rows up to the restart step.

    python benchmarks/bench_resume.py [--root results/bench_resume] [--kill-strain 4.2]

Run it on an idle machine (it times LAMMPS).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, pack, read_stress_table, run_startup
from suspension_fabric.simulation.lammps.plugin import plugin_path
from suspension_fabric.simulation.lammps.process import lammps_processes_in

STRAIN = 5.0
KILLED_RUN = f"""
import sys
from suspension_fabric.simulation.lammps import ForceModel, run_startup
run_startup(sys.argv[1], sys.argv[2], {STRAIN}, force_model=ForceModel(plugin=sys.argv[3]), progress=None)
"""


def last_strain(table: Path) -> float:
    try:
        lines = table.read_text().splitlines()
    except FileNotFoundError:
        return 0.0
    rows = [line for line in lines[1:] if line.strip()]
    return float(rows[-2].split()[1]) if len(rows) > 1 else 0.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=Path, default=Path("results/bench_resume"))
    parser.add_argument("--kill-strain", type=float, default=4.2)
    parser.add_argument("-n", type=int, default=500)
    args = parser.parse_args()
    root = args.root.resolve()
    if root.exists():
        shutil.rmtree(root)
    packing = pack(root / "packing", args.n, seed=1)
    model = ForceModel(plugin=plugin_path())

    whole = run_startup(root / "whole", packing.data_file, STRAIN, force_model=model, progress=None)
    print(f"uninterrupted: {whole.wall_time:.1f} s for strain {STRAIN}", flush=True)

    output = root / "killed"
    process = subprocess.Popen(
        [sys.executable, "-c", KILLED_RUN, str(output), str(packing.data_file), str(plugin_path())],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    table = root / ".killed.partial" / "segment-01" / "stress.txt"
    while last_strain(table) < args.kill_strain:
        if process.poll() is not None:
            raise SystemExit("the run ended before it was killed")
        time.sleep(0.2)
    for pid in lammps_processes_in(root / ".killed.partial"):
        os.killpg(pid, signal.SIGKILL)
    process.wait()
    killed_at = last_strain(table)
    print(f"killed at strain {killed_at:.3f}", flush=True)

    start = time.monotonic()
    resumed = run_startup(output, packing.data_file, STRAIN, force_model=model, progress=None)
    call = time.monotonic() - start
    marker = json.loads((output / "run_complete.json").read_text())
    segment = marker["segments"][-1]
    resumed_from = segment["start_step"] * ShearSettings().dt
    a, b = read_stress_table(whole.table_file), read_stress_table(resumed.table_file)
    continuous = np.array_equal(a["step"], b["step"])
    before = a["step"] <= segment["start_step"]
    identical = all(np.array_equal(a[c][before], b[c][before]) for c in a)
    print(
        f"resumed from strain {resumed_from:.3f}: LAMMPS {segment['wall_time_s']:.1f} s, whole call "
        f"{call:.1f} s (probe, stitching, checks: {call - segment['wall_time_s']:.1f} s)"
    )
    print(
        f"rerun from strain 0 would take {whole.wall_time:.1f} s: the resume costs "
        f"{call / whole.wall_time:.3f} of it (saving {100 * (1 - call / whole.wall_time):.0f}%); "
        f"work lost to the kill: strain {killed_at - resumed_from:.3f}"
    )
    print(f"stitched table has the uninterrupted steps: {continuous}; identical rows up to the restart: {identical}")


if __name__ == "__main__":
    main()

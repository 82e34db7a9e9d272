"""One simulation across MPI ranks: the default engine (fix hydro/implicit/sf) on 1 and 2 ranks
of the same steady state (BENCHMARKS.md, "One simulation across MPI ranks").

    .venv/bin/python benchmarks/mpi_scaling.py prepare [--n 16000]   # steady state (any load)
    .venv/bin/python benchmarks/mpi_scaling.py measure [--n 16000]   # timings: idle machine
    .venv/bin/python benchmarks/mpi_scaling.py iterations [--n 16000] [--ranks 1 2 4 8 16]
    .venv/bin/python benchmarks/mpi_scaling.py model [--n 16000]      # efficiency model, 8-64 ranks

`prepare`: the paper's point (phi = 0.45, packing seed 1, the default forces and engine) at
N = n, a startup to strain PREPARE_STRAIN on 2 ranks, into results/mpi_scaling/n<N>/.

`measure`: from that checkpoint, the same shear continued for MEASURE_STRAIN on 1 rank and on
2 ranks, alternating, REPEATS times each; per run LAMMPS's loop time, the time of its Comm and
Modify (the fix) sections averaged over the ranks, the mean CG iterations per step and the
ghost atoms per rank. Prints a Markdown table and the speed-up of 2 ranks over 1 (median of
the pairs). Written to results/mpi_scaling/n<N>/measure.csv.

`iterations`: the same continuation, ITERATION_STRAIN long, on 1, 2, 4, ... ranks; on this
2-core machine more than 2 ranks share cores, so only the iteration counts and ghost counts
are kept (results/mpi_scaling/n<N>/iterations.csv), not the times.

`model`: the parallel efficiency on P = 8-64 ranks of one node of dedicated cores, from the
measured figures: a step's work per atom (the 1-rank run's Modify time less nothing: no ghost is
used on 1 rank) splits into a part per CG iteration and a fixed part (fitted from the
iterations); on P ranks each rank does N/P atoms' work times I(P)/I(1) for the iterations, plus
the communication: per step (2 + 2 I) ghost exchanges of 6 doubles per ghost atom and 3 I + 4
global sums, priced with the 2-rank run's measured Comm time per exchanged double and the
measured latency of a global sum; the ghosts per rank are measured up to 16 ranks and, beyond,
scaled as the surface of a rank's cube of atoms, (N/P)^(2/3).
"""

from __future__ import annotations

import argparse
import csv
import platform
import re
import statistics
from pathlib import Path

from suspension_fabric.simulation.lammps import (
    PACK_FILES,
    RUN_FILES,
    ForceModel,
    ShearSettings,
    is_complete,
    pack,
    run_rotation,
    run_startup,
)

ROOT = Path("results/mpi_scaling")
PREPARE_STRAIN = 1.0
MEASURE_STRAIN = 0.1
ITERATION_STRAIN = 0.02
REPEATS = 3
LOOP_TIME = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
SECTION = re.compile(r"^(Comm|Modify)\s*\|\s*[0-9.eE+-]+\s*\|\s*([0-9.eE+-]+)\s*\|", re.MULTILINE)
GHOSTS = re.compile(r"^Nghost:\s+([0-9.eE+-]+) ave", re.MULTILINE)


def folder(n: int) -> Path:
    return ROOT / f"n{n}"


def checkpoint(n: int) -> Path:
    return folder(n) / "startup" / RUN_FILES["checkpoint"]


def prepare(n: int) -> None:
    packing = folder(n) / "packing"
    if not is_complete(packing):
        pack(packing, n, phi=0.45, seed=1, ranks=2)
    startup = folder(n) / "startup"
    if not is_complete(startup):
        run_startup(
            startup,
            packing / PACK_FILES["data"],
            PREPARE_STRAIN,
            force_model=ForceModel(),
            settings=ShearSettings(dump_strain=0.1, ranks=2),
            progress_interval=300,
        )


def continuation(n: int, ranks: int, strain: float, name: str) -> dict:
    """The prepared shear continued for `strain` on `ranks` ranks; LAMMPS's figures of the run."""
    settings = ShearSettings(
        dump_strain=strain,
        table_strain=strain / 10,
        thermo_strain=strain / 20,
        restart_strain=strain,
        max_stress_jitter=None,
        ranks=ranks,
    )
    run = run_rotation(
        folder(n) / name, checkpoint(n), 0.0, strain, settings=settings, overwrite=True, resume=False, progress=None
    )
    log = run.log_file.read_text()
    seconds, procs, steps, atoms = LOOP_TIME.findall(log)[-1]
    sections = dict(SECTION.findall(log))
    return {
        "n": int(atoms),
        "ranks": int(procs),
        "steps": int(steps),
        "loop_s": float(seconds),
        "comm_s": float(sections["Comm"]),
        "modify_s": float(sections["Modify"]),
        "iterations": mean_iterations(log),
        "ghosts_per_rank": float(GHOSTS.findall(log)[-1]),
    }


def mean_iterations(log: str) -> float:
    """Mean of the thermo column v_solver_iterations (the last step's CG iterations) after step 0."""
    values, columns = [], None
    for line in log.splitlines():
        fields = line.split()
        if fields[:1] == ["Step"]:
            columns = fields
        elif columns and len(fields) == len(columns) and fields[0].isdigit():
            values.append(float(fields[columns.index("v_solver_iterations")]))
        elif fields[:2] == ["Loop", "time"]:
            columns = None
    return statistics.fmean(values[1:])


def write_rows(rows: list[dict], path: Path) -> None:
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def measure(n: int) -> None:
    print(
        f"# {platform.machine()}, {platform.python_version()}; N = {n}, the paper's point, default engine; "
        f"{MEASURE_STRAIN:g} strain continued from strain {PREPARE_STRAIN:g}, 1 and 2 ranks alternating\n"
    )
    print("| run | ranks | steps | loop s | Modify s (fix) | Comm s | mean CG iterations | ghosts per rank |")
    print("|---|--:|--:|--:|--:|--:|--:|--:|")
    rows = []
    for repeat in range(1, REPEATS + 1):
        for ranks in (1, 2):
            row = {"repeat": repeat, **continuation(n, ranks, MEASURE_STRAIN, f"measure_ranks{ranks}")}
            rows.append(row)
            print(
                f"| {repeat} | {ranks} | {row['steps']} | {row['loop_s']:.1f} | {row['modify_s']:.1f} | "
                f"{row['comm_s']:.2f} | {row['iterations']:.2f} | {row['ghosts_per_rank']:.0f} |",
                flush=True,
            )
    write_rows(rows, folder(n) / "measure.csv")
    speedups = [one["loop_s"] / two["loop_s"] for one, two in zip(rows[0::2], rows[1::2], strict=True)]
    print(
        f"\nspeed-up of 2 ranks over 1 (loop time), per pair: {', '.join(f'{s:.2f}' for s in speedups)}; "
        f"median {statistics.median(speedups):.2f} (target >= 1.7)"
    )


def iterations(n: int, ranks_list: list[int]) -> None:
    print("| ranks | steps | mean CG iterations | ghosts per rank |\n|--:|--:|--:|--:|")
    rows = []
    for ranks in ranks_list:
        row = continuation(n, ranks, ITERATION_STRAIN, f"iterations_ranks{ranks}")
        rows.append({key: row[key] for key in ("n", "ranks", "steps", "iterations", "ghosts_per_rank")})
        print(f"| {ranks} | {row['steps']} | {row['iterations']:.2f} | {row['ghosts_per_rank']:.0f} |", flush=True)
    write_rows(rows, folder(n) / "iterations.csv")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("command", choices=("prepare", "measure", "iterations", "model"))
    parser.add_argument("--n", type=int, default=16000)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    args = parser.parse_args()
    if args.command == "prepare":
        prepare(args.n)
    elif args.command == "measure":
        measure(args.n)
    elif args.command == "iterations":
        iterations(args.n, args.ranks)


if __name__ == "__main__":
    main()

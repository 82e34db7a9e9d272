"""One simulation across MPI ranks: the default engine (fix hydro/implicit/sf) on 1 and 2 ranks
of the same steady state, and a model of its parallel efficiency on more (BENCHMARKS.md, "One
simulation across MPI ranks").

    .venv/bin/python benchmarks/mpi_scaling.py prepare [--n 16000]   # steady state (any load)
    .venv/bin/python benchmarks/mpi_scaling.py startup [--n 16000]   # the prepared startup's figures
    .venv/bin/python benchmarks/mpi_scaling.py measure [--n 16000] [--local-solve-fraction 0.02] [--label L]   # idle
    .venv/bin/python benchmarks/mpi_scaling.py measure [--n 16000] --preconditioner jacobi        # idle
    .venv/bin/python benchmarks/mpi_scaling.py split [--n 16000]     # price of an iteration: idle
    .venv/bin/python benchmarks/mpi_scaling.py iterations [--n 16000] [--ranks 1 2 4 8] [--preconditioner jacobi]
    .venv/bin/python benchmarks/mpi_scaling.py latency [--n 16000]   # MPI's prices: idle machine
    .venv/bin/python benchmarks/mpi_scaling.py model [--n 16000]     # efficiency, 1-64 ranks
    .venv/bin/python benchmarks/mpi_scaling.py sizes --n 500 4000 16000   # cost per atom against N
    .venv/bin/python benchmarks/mpi_scaling.py local --n 500 4000 16000   # local solves: idle

The commands `contention`, `jitter` and `preconditioners`, whose tables are in
benchmarks/data/mpi_scaling/n16000/, are in commit 7b1031c (docs/physics.md).

`prepare`: the paper's point (phi = 0.45, packing seed 1, the default forces and engine) at
N = n, a startup to strain PREPARE_STRAIN on 2 ranks, into results/mpi_scaling/n<N>/.

`startup`: that startup's loop time and its CG iterations per step over each half of its strain.

`measure`: from that checkpoint, the same shear continued for MEASURE_STRAIN on 1 rank and on
2 ranks, alternating, REPEATS times each; per run LAMMPS's loop time, its Comm and Modify (the
fix) sections averaged over the ranks, the mean CG iterations per step and the ghost atoms per
rank, and the share of the CPUs' time the host of a virtual machine took for others while it ran
(steal, from /proc/stat). Prints a Markdown table and the speed-up of 2 ranks over 1 (per pair and
the median); writes measure.csv (with --label L, measure_L.csv: a later measurement beside the
committed one). With --local-solve-fraction f > 0 both run local solves
(run.local_solve_fraction = f), into measure_local<f>.csv; with --preconditioner jacobi both use
block Jacobi within the ranks too (run.preconditioner), into measure_jacobi.csv.

`split`: the 1-rank continuation (MEASURE_STRAIN at N = 16000, longer for smaller N, at most
1 strain) at the default solver_tol and at SPLIT_TOL, alternating, REPEATS times each: more CG iterations
for the same other work, so the difference prices one iteration per atom (split.csv).

`iterations`: the continuation, ITERATION_STRAIN long, on each rank count given; on this 2-core
machine more than 2 ranks share cores, so only the iteration and ghost counts are kept, not the
times (iterations.csv; with --preconditioner jacobi, iterations_jacobi.csv).

`sizes`: from each N's split.csv, the 1-rank cost per atom per step split into the part outside
the CG iterations and the iterations' part: what the growth of the cost with N comes from.

`local`: for each N, the 1-rank continuation (split's strain) with global iterations only and
with local solves (run.local_solve_fraction = LOCAL_FRACTION), alternating, REPEATS times each:
the cost per atom per step, the global CG iterations, and the cost per atom against the
smallest N (local_solves_n<N>_..., one table per command).

`model`: the time per step on P ranks of dedicated cores of one node,
    t(P) = N/P (a + b I(P)) + (5 + 2 I(P)) 6 g(P) c + (5 + 3 I(P)) s log2 P,
with a and b the 1-rank costs per atom outside and per CG iteration (measure and split), I(P)
the iterations per step (measured up to the largest P of `iterations`, then growing by their
mean growth per rank doubling), g(P) the ghosts per rank, from the shell of one subdomain of
LAMMPS's grid (checked against the measured counts), c the price of one exchanged double (the
2-rank run's time less its modelled compute, divided by its ghost traffic: waiting for the
slower rank included), s the latency of a global sum on 2 ranks (`latency`: benchmarks/
mpi_latency.c), growing as log2 P; the counts of ghost exchanges (5 + 2 I) and global sums
(5 + 3 I) per step are those of fix_hydro_implicit_sf.cpp. Prints t(P), the speed-up
t(1)/t(P) and the efficiency t(1)/(P t(P)).
"""

from __future__ import annotations

import argparse
import csv
import math
import platform
import re
import statistics
import subprocess
import sys
from pathlib import Path

from suspension_fabric.io.schema import load_schema, schema_default
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
from suspension_fabric.simulation.lammps.plugin import mpi_include_dir
from suspension_fabric.simulation.lammps.process import lammps_environment, mpi_launcher, thermo_rows

ROOT = Path("results/mpi_scaling")
PRECONDITIONERS = tuple(load_schema()["properties"]["run"]["properties"]["preconditioner"]["enum"])
DEFAULT_PRECONDITIONER = schema_default("run", "preconditioner")
TABLES = Path("benchmarks/data/mpi_scaling")
PREPARE_STRAIN = 1.0
MEASURE_STRAIN = 0.1
ITERATION_STRAIN = 0.02
REPEATS = 3
SPLIT_TOL = 1.0e-5
LOCAL_FRACTION = 0.02
MODEL_RANKS = (8, 16, 32, 64)
# per step, with I CG iterations (all passes): ghost exchanges (forward or reverse, 6 doubles per
# ghost) and global sums, as fix_hydro_implicit_sf.cpp makes them with one pass: exchanges for
# the relative velocities, the right-hand side, the first residual's product (2) and the end of
# the solve, and 2 per iteration (the product: the direction to the ghosts, the ghosts' sums
# back; the preconditioner is local); sums: 2 for the first residual, 3 per iteration, 3 per step
EXCHANGES_FIXED = 5
EXCHANGES_PER_ITERATION = 2
SUMS_FIXED = 5
SUMS_PER_ITERATION = 3
LATENCY_SOURCE = Path(__file__).with_name("mpi_latency.c")
LOOP_TIME = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
SECTION = re.compile(r"^(Comm|Modify)\s*\|\s*[0-9.eE+-]+\s*\|\s*([0-9.eE+-]+)\s*\|", re.MULTILINE)
GHOSTS = re.compile(r"^Nghost:\s+([0-9.eE+-]+) ave", re.MULTILINE)
BOX = re.compile(r"triclinic box = \(([^)]*)\) to \(([^)]*)\)")
CUTOFF = re.compile(r"ghost atom cutoff = ([0-9.eE+-]+)")


def folder(n: int) -> Path:
    return ROOT / f"n{n}"


def tables(n: int) -> Path:
    """The committed tables of the measurements (the run folders stay in results/)."""
    return TABLES / f"n{n}"


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


def continuation_settings(strain: float, ranks: int = 1) -> ShearSettings:
    """The outputs of a benchmark's continuation of `strain`: one frame and checkpoint at its end, the
    stress table 10 times and thermo 20 times over it, no jitter check."""
    return ShearSettings(
        dump_strain=strain,
        table_strain=strain / 10,
        thermo_strain=strain / 20,
        restart_strain=strain,
        max_stress_jitter=None,
        ranks=ranks,
    )


def continuation(n: int, ranks: int, strain: float, name: str, force_model: ForceModel | None = None) -> dict:
    """The prepared shear continued for `strain` on `ranks` ranks (the default engine unless
    `force_model` is given); LAMMPS's figures of the run."""
    settings = continuation_settings(strain, ranks)
    before = cpu_times()
    run = run_rotation(
        folder(n) / name,
        checkpoint(n),
        0.0,
        strain,
        force_model=force_model or ForceModel(),
        settings=settings,
        overwrite=True,
        resume=False,
        progress=None,
    )
    return {**figures(run.log_file.read_text()), "steal": stolen_share(before, cpu_times())}


def cpu_times() -> list[int] | None:
    """The machine's CPU time counters summed over its CPUs (the first line of /proc/stat: user,
    nice, system, idle, iowait, irq, softirq, steal, ...), or None where there is no /proc/stat."""
    stat = Path("/proc/stat")
    if not stat.exists():
        return None
    return [int(field) for field in stat.read_text().split("\n", 1)[0].split()[1:9]]


def stolen_share(before: list[int] | None, after: list[int] | None) -> float:
    """The share of the CPUs' time between two readings that the host of this virtual machine
    gave to others (steal): on a 2-core machine a step on 2 ranks waits whenever either core is
    taken, so steal slows a 2-rank run more than a 1-rank one. NaN without /proc/stat."""
    if before is None or after is None:
        return math.nan
    spent = [b - a for a, b in zip(before, after, strict=True)]
    return spent[7] / sum(spent) if sum(spent) else math.nan


def figures(log: str) -> dict:
    """A run's figures from its LAMMPS log: size, ranks, loop and section times, mean CG
    iterations, ghosts per rank, box lengths and ghost cutoff."""
    seconds, procs, steps, atoms = LOOP_TIME.findall(log)[-1]
    sections = dict(SECTION.findall(log))
    low, high = (tuple(float(v) for v in corner.split()) for corner in BOX.findall(log)[-1])
    return {
        "n": int(atoms),
        "ranks": int(procs),
        "steps": int(steps),
        "loop_s": float(seconds),
        "comm_s": float(sections["Comm"]),
        "modify_s": float(sections["Modify"]),
        "iterations": mean_iterations(log),
        "ghosts_per_rank": float(GHOSTS.findall(log)[-1]),
        **{f"box_{axis}": h - lo for axis, h, lo in zip("xyz", high, low, strict=True)},
        "ghost_cutoff": float(CUTOFF.findall(log)[-1]),
    }


def mean_iterations(log: str) -> float:
    """Mean of the thermo column v_solver_iterations (the last step's CG iterations) after step 0."""
    return statistics.fmean(row["v_solver_iterations"] for row in thermo_rows(log)[1:])


def labelled(label: str) -> str:
    """A table name's suffix for a labelled measurement ("" without a label)."""
    return f"_{label}" if label else ""


def write_rows(rows: list[dict], path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def measure(n: int, local_fraction: float = 0.0, preconditioner: str = DEFAULT_PRECONDITIONER, label: str = "") -> None:
    """1 and 2 ranks alternating; with local solves (run.local_solve_fraction = local_fraction > 0)
    or another preconditioner, into their own run folders and table (measure_local<f>.csv,
    measure_<preconditioner>.csv); a label names a table of its own (measure_<label>.csv), so that
    a later measurement of the same runs does not replace the committed one."""
    engine = "default engine" + (f", local solves {local_fraction:g}" if local_fraction else "")
    suffix = f"_local{local_fraction:g}" if local_fraction else ""
    if preconditioner != DEFAULT_PRECONDITIONER:
        engine += f", preconditioner {preconditioner}"
        suffix += f"_{preconditioner}"
    print(
        f"# {platform.machine()}, {platform.python_version()}; N = {n}, the paper's point, {engine}; "
        f"{MEASURE_STRAIN:g} strain continued from strain {PREPARE_STRAIN:g}, 1 and 2 ranks alternating\n"
    )
    print(
        "| run | ranks | steps | loop s | Modify s (fix) | Comm s | mean CG iterations | ghosts per rank "
        "| host steal % |"
    )
    print("|---|--:|--:|--:|--:|--:|--:|--:|--:|")
    rows = []
    model = ForceModel(local_solve_fraction=local_fraction, preconditioner=preconditioner)
    for repeat in range(1, REPEATS + 1):
        for ranks in (1, 2):
            row = {"repeat": repeat, **continuation(n, ranks, MEASURE_STRAIN, f"measure{suffix}_ranks{ranks}", model)}
            rows.append(row)
            print(
                f"| {repeat} | {ranks} | {row['steps']} | {row['loop_s']:.1f} | {row['modify_s']:.1f} | "
                f"{row['comm_s']:.2f} | {row['iterations']:.2f} | {row['ghosts_per_rank']:.0f} | "
                f"{100 * row['steal']:.1f} |",
                flush=True,
            )
    write_rows(rows, tables(n) / f"measure{suffix}{labelled(label)}.csv")
    speedups = [one["loop_s"] / two["loop_s"] for one, two in zip(rows[0::2], rows[1::2], strict=True)]
    print(
        f"\nspeed-up of 2 ranks over 1 (loop time), per pair: {', '.join(f'{s:.2f}' for s in speedups)}; "
        f"median {statistics.median(speedups):.2f} (target >= 1.7)"
    )


def rotating_rounds(n: int, runs: list[tuple[int, str, ForceModel, dict]]) -> list[dict]:
    """Each run (ranks, run folder, engine, the columns naming it in the table) continued MEASURE_STRAIN from
    the prepared state, the runs of a round in an order that rotates from round to round, REPEATS rounds, so
    that a drift of the machine's speed falls on every run alike. Prints a Markdown row per run: round,
    ranks, the naming columns, loop s, mean CG iterations, host steal %."""
    rows = []
    for repeat in range(1, REPEATS + 1):
        shift = (repeat - 1) % len(runs)
        for ranks, name, model, columns in runs[shift:] + runs[:shift]:
            row = {"repeat": repeat, **columns, **continuation(n, ranks, MEASURE_STRAIN, name, model)}
            rows.append(row)
            cells = "".join(
                f" {value:g} |" if isinstance(value, float) else f" {value} |" for value in columns.values()
            )
            print(
                f"| {repeat} | {ranks} |{cells} {row['loop_s']:.1f} | {row['iterations']:.2f} | "
                f"{100 * row['steal']:.1f} |",
                flush=True,
            )
    return rows


def iterations(n: int, ranks_list: list[int], preconditioner: str = DEFAULT_PRECONDITIONER) -> None:
    """The CG iterations and ghosts on each rank count (iterations.csv; another preconditioner than
    the default into iterations_<preconditioner>.csv)."""
    suffix = "" if preconditioner == DEFAULT_PRECONDITIONER else f"_{preconditioner}"
    model = ForceModel(preconditioner=preconditioner)
    print("| ranks | steps | mean CG iterations | ghosts per rank |\n|--:|--:|--:|--:|")
    rows = []
    for ranks in ranks_list:
        row = continuation(n, ranks, ITERATION_STRAIN, f"iterations{suffix}_ranks{ranks}", model)
        keep = ("n", "ranks", "steps", "iterations", "ghosts_per_rank", "box_x", "box_y", "box_z", "ghost_cutoff")
        rows.append({key: row[key] for key in keep})
        print(f"| {ranks} | {row['steps']} | {row['iterations']:.2f} | {row['ghosts_per_rank']:.0f} |", flush=True)
    write_rows(rows, tables(n) / f"iterations{suffix}.csv")


def split_strain(n: int) -> float:
    """MEASURE_STRAIN at N = 16000; smaller systems run longer, for comparable loop times: the
    first of 0.1, 0.2, 0.5 and 1 strain (steps that divide the checkpoint's, so that the outputs
    stay on LAMMPS's grid) at least MEASURE_STRAIN x 16000 / n."""
    wanted = MEASURE_STRAIN * 16000 / n
    return next((strain for strain in (0.1, 0.2, 0.5) if strain >= wanted - 1e-12), 1.0)


def split(n: int) -> None:
    """The 1-rank continuation at the default solver_tol and at SPLIT_TOL, alternating, REPEATS
    times each: more CG iterations for the same other work, so the difference prices one
    iteration per atom."""
    rows = []
    for repeat in range(1, REPEATS + 1):
        for tol in (ForceModel().solver_tol, SPLIT_TOL):
            run = continuation(n, 1, split_strain(n), f"split_tol{tol:g}", ForceModel(solver_tol=tol))
            rows.append({"repeat": repeat, "solver_tol": tol, **run})
            print(f"solver_tol {tol:g}: {run['loop_s']:.1f} s, {run['iterations']:.2f} iterations per step", flush=True)
    write_rows(rows, tables(n) / "split.csv")


def local_solves(ns: list[int]) -> None:
    rows = []
    for n in ns:
        for repeat in range(1, REPEATS + 1):
            for fraction in (0.0, LOCAL_FRACTION):
                model = ForceModel(local_solve_fraction=fraction)
                run = continuation(n, 1, split_strain(n), f"local{fraction:g}", model)
                rows.append({"repeat": repeat, "local_solve_fraction": fraction, **run})
                print(
                    f"N {n}, local {fraction:g}: {run['loop_s']:.2f} s, {run['iterations']:.2f} iterations", flush=True
                )
    write_rows(rows, TABLES / f"local_solves_{'_'.join(f'n{n}' for n in ns)}.csv")
    print_local_solves(rows)


def print_local_solves(rows: list[dict]) -> None:
    """Medians over the repeats: us per atom per step, global CG iterations per step, and the
    cost per atom against the smallest N of the same setting."""
    ns = sorted({int(row["n"]) for row in rows})
    fractions = sorted({row["local_solve_fraction"] for row in rows})

    def median(n, fraction, key):
        return statistics.median(
            row[key] / (row["steps"] * n) if key == "loop_s" else row[key]
            for row in rows
            if int(row["n"]) == n and row["local_solve_fraction"] == fraction
        )

    print(
        "| N | local_solve_fraction | us per atom per step | global CG iterations | cost per atom / N = "
        f"{ns[0]} | local against global |"
    )
    print("|--:|--:|--:|--:|--:|--:|")
    for n in ns:
        for fraction in fractions:
            cost = median(n, fraction, "loop_s")
            print(
                f"| {n} | {fraction:g} | {cost * 1e6:.3f} | {median(n, fraction, 'iterations'):.2f} | "
                f"{cost / median(ns[0], fraction, 'loop_s'):.2f} | {cost / median(n, fractions[0], 'loop_s'):.2f} |"
            )


def startup_report(n: int) -> None:
    """The prepared startup's own figures (its LAMMPS log): loop time, ranks, steps, and the mean
    CG iterations per step over each half of its strain (thermo rows, one step each)."""
    log = (folder(n) / "startup" / "log.lammps").read_text()
    run = figures(log)
    rows = thermo_rows(log)[1:]
    halves = [
        statistics.fmean(r["v_solver_iterations"] for r in rows if low < r["v_strain"] <= high + 1e-9)
        for low, high in ((0.0, PREPARE_STRAIN / 2), (PREPARE_STRAIN / 2, PREPARE_STRAIN))
    ]
    print(
        f"N = {run['n']}: startup to strain {PREPARE_STRAIN:g} on {run['ranks']} ranks, {run['steps']} steps in "
        f"{run['loop_s']:.0f} s ({run['loop_s'] / run['steps'] * 1e3:.1f} ms per step, "
        f"{run['loop_s'] * run['ranks'] / (run['steps'] * run['n']) * 1e6:.2f} core-us per atom per step); "
        f"CG iterations per step {halves[0]:.2f} over strain 0-{PREPARE_STRAIN / 2:g}, "
        f"{halves[1]:.2f} over {PREPARE_STRAIN / 2:g}-{PREPARE_STRAIN:g}; ghosts per rank {run['ghosts_per_rank']:.0f}"
    )


def read_rows(path: Path) -> list[dict]:
    with path.open() as handle:
        return [{key: float(value) for key, value in row.items()} for row in csv.DictReader(handle)]


def compile_mpi_program(source: Path) -> Path:
    """A C benchmark of this folder compiled against the venv's mpich, into results/mpi_scaling/."""
    binary = ROOT / source.stem
    binary.parent.mkdir(parents=True, exist_ok=True)
    command = ["gcc", "-O2", f"-I{mpi_include_dir()}", str(source), "-o", str(binary)]
    subprocess.run([*command, f"-L{Path(sys.prefix) / 'lib'}", "-lmpi"], check=True)
    return binary


def latency(n: int) -> None:
    """Compiles benchmarks/mpi_latency.c against the venv's mpich and runs it on 2 ranks, with
    messages of the size of one ghost exchange of the measured 2-rank run (6 doubles per ghost)."""
    two = [row for row in read_rows(tables(n) / "measure.csv") if row["ranks"] == 2]
    doubles = round(6 * statistics.median(row["ghosts_per_rank"] for row in two))
    binary = compile_mpi_program(LATENCY_SOURCE)
    command = [str(mpi_launcher()), "-np", "2", str(binary), str(doubles)]
    output = subprocess.run(command, env=lammps_environment(), capture_output=True, text=True, check=True).stdout
    allreduce_us, message_ns = (float(value) for value in output.split())
    write_rows(
        [{"doubles": doubles, "allreduce_us": allreduce_us, "ns_per_double": message_ns}], tables(n) / "latency.csv"
    )
    print(
        f"2 ranks: MPI_Allreduce of one double {allreduce_us:.3f} us; a message of {doubles} doubles "
        f"{message_ns:.3f} ns per double one way"
    )


def processor_grid(ranks: int, lengths: tuple[float, float, float]) -> tuple[int, int, int]:
    """LAMMPS's default grid: the factorisation px py pz = ranks whose subdomains have the least surface."""
    best = None
    for px in range(1, ranks + 1):
        for py in range(1, ranks // px + 1):
            if ranks % (px * py):
                continue
            pz = ranks // (px * py)
            a = (lengths[0] / px, lengths[1] / py, lengths[2] / pz)
            surface = a[0] * a[1] + a[1] * a[2] + a[0] * a[2]
            if best is None or surface < best[0] - 1e-12:
                best = (surface, (px, py, pz))
    return best[1]


def modelled_ghosts(n: int, lengths, cutoff: float, grid) -> float:
    """Atoms in the shell of thickness `cutoff` around one subdomain, at the mean number density."""
    sub = [length / p for length, p in zip(lengths, grid, strict=True)]
    density = n / math.prod(lengths)
    return density * (math.prod(a + 2 * cutoff for a in sub) - math.prod(sub))


def model_inputs(n: int) -> dict:
    """What `model` takes from the committed tables: the 1-rank step and its CG iterations (medians of
    measure.csv), the costs per atom outside the iterations (a, "fixed") and per iteration (b), the
    iterations' share of the step from split.csv, the counts of iterations.csv, the box, the ghost
    cutoff, MPI's prices (latency.csv) and the measured 2-rank step."""
    measured = read_rows(tables(n) / "measure.csv")
    split_row = split_costs(n)
    counts = {int(row["ranks"]): row for row in read_rows(tables(n) / "iterations.csv")}

    def median_of(ranks: int, key: str) -> float:
        return statistics.median(
            row[key] / (row["steps"] if key == "loop_s" else 1.0) for row in measured if row["ranks"] == ranks
        )

    step_one, iterations_one = median_of(1, "loop_s"), median_of(1, "iterations")
    # the iteration's share of the 1-rank step from the split (its runs need not see the machine
    # at measure's speed: the share, not the seconds, is carried over)
    share = split_row["iterations"] * split_row["per_iteration"] * n / split_row["step"]
    return {
        "step_one": step_one,
        "iterations_one": iterations_one,
        "share": share,
        "per_iteration": share * step_one / (n * iterations_one),  # s per atom per CG iteration
        "fixed": (1.0 - share) * step_one / n,  # s per atom per step outside the iterations
        "split_repeats": split_row["repeats"],
        "counts": {ranks: row["iterations"] for ranks, row in counts.items()},
        "ghosts": {ranks: row["ghosts_per_rank"] for ranks, row in counts.items()},
        "lengths": tuple(counts[1][f"box_{axis}"] for axis in "xyz"),
        "cutoff": counts[1]["ghost_cutoff"],
        "prices": read_rows(tables(n) / "latency.csv")[0],
        "step_two": median_of(2, "loop_s"),
    }


def iteration_growth(counts: dict[int, float]) -> float:
    """The mean growth of the CG iterations per doubling of the ranks, from 2 ranks to the most counted."""
    largest = max(counts)
    return (counts[largest] - counts[2]) / math.log2(largest / 2)


def iterations_on(counts: dict[int, float], ranks: int) -> float:
    """The CG iterations on `ranks` ranks from counts {ranks: iterations} of one window: the count where
    measured, beyond the most ranks counted growing by iteration_growth per doubling."""
    largest = max(counts)
    return counts.get(ranks, counts[largest] + iteration_growth(counts) * math.log2(ranks / largest))


def communication(n: int, ranks: int, iterations_p: float, inputs: dict) -> tuple[float, float]:
    """The modelled ghosts per rank and the seconds per step of the ghost exchanges and global sums on
    `ranks` ranks with `iterations_p` CG iterations per step."""
    lengths = inputs["lengths"]
    ghosts = modelled_ghosts(n, lengths, inputs["cutoff"], processor_grid(ranks, lengths))
    if ranks == 1:
        return ghosts, 0.0
    prices = inputs["prices"]
    exchanges = EXCHANGES_FIXED + EXCHANGES_PER_ITERATION * iterations_p
    sums = SUMS_FIXED + SUMS_PER_ITERATION * iterations_p
    seconds = exchanges * 6 * ghosts * prices["ns_per_double"] * 1e-9
    return ghosts, seconds + sums * prices["allreduce_us"] * 1e-6 * math.log2(ranks)


def model_row(ranks: int, lengths, iterations: float, step: float, seconds: float, step_one: float) -> dict:
    """A rank count's row of a model's table: its grid, CG iterations, step (s), the communication's share of
    it (`seconds` of it), and the speed-up over `step_one` and the efficiency."""
    return {
        "ranks": ranks,
        "grid": "x".join(map(str, processor_grid(ranks, lengths))),
        "iterations": iterations,
        "step": step,
        "communication": seconds / step,
        "speedup": step_one / step,
        "efficiency": step_one / step / ranks,
    }


def same_tol_model(n: int) -> dict:
    """The model (the module's docstring) at the default solver_tol on every rank count: {"inputs", "growth",
    "check_ms": (modelled, measured) 2-rank step, "rows": per P its grid, iterations, ghosts (model), step,
    communication share, speed-up and efficiency}."""
    inputs = model_inputs(n)
    counts, step_one, iterations_one = inputs["counts"], inputs["step_one"], inputs["iterations_one"]

    def step_at(ranks: int) -> dict:
        # the iterations windows are shorter than measure's: their ratios to 1 rank carry over
        iterations = iterations_one * iterations_on(counts, ranks) / counts[1]
        ghosts, seconds = communication(n, ranks, iterations, inputs)
        step = n / ranks * (inputs["fixed"] + inputs["per_iteration"] * iterations) + seconds
        return {**model_row(ranks, inputs["lengths"], iterations, step, seconds, step_one), "ghosts": ghosts}

    return {
        "inputs": inputs,
        "growth": iteration_growth(counts),
        "check_ms": (1e3 * step_at(2)["step"], 1e3 * inputs["step_two"]),
        "rows": [step_at(ranks) for ranks in sorted(set(counts) | set(MODEL_RANKS))],
    }


def model(n: int) -> None:
    """Prints same_tol_model: its inputs, the check at 2 ranks, and a Markdown row per P."""
    found = same_tol_model(n)
    inputs, counts = found["inputs"], found["inputs"]["counts"]
    prices = inputs["prices"]
    print(
        f"# N = {n}, box {' x '.join(f'{x:.2f}' for x in inputs['lengths'])}, ghost cutoff {inputs['cutoff']:g}. "
        f"1 rank (measure): {inputs['step_one'] * 1e3:.1f} ms per step at {inputs['iterations_one']:.2f} CG "
        f"iterations; the iterations' share {inputs['share']:.2f} (split: solver_tol {ForceModel().solver_tol:g} "
        f"against {SPLIT_TOL:g}, medians of {inputs['split_repeats']}), so a = {inputs['fixed'] * 1e6:.3f} us per "
        f"atom per step and b = {inputs['per_iteration'] * 1e6:.3f} us per atom per iteration. Prices on 2 ranks "
        f"(latency): a global sum {prices['allreduce_us']:.3f} us, {prices['ns_per_double']:.3f} ns per exchanged "
        f"double. Beyond P = {max(counts)}, I(P) grows by {found['growth']:.2f} per doubling (its mean from 2 to "
        f"{max(counts)} ranks). Check at P = 2: modelled {found['check_ms'][0]:.1f} ms per step, measured "
        f"{found['check_ms'][1]:.1f}\n"
    )
    print(
        "| ranks P | grid | atoms per rank | CG iterations I(P) | ghosts per rank (measured) "
        "| ghosts per rank (model) | ms per step | of it communication | speed-up | efficiency |"
    )
    print("|--:|:-:|--:|--:|--:|--:|--:|--:|--:|--:|")
    for row in found["rows"]:
        ranks = row["ranks"]
        measured_ghosts = f"{inputs['ghosts'][ranks]:.0f}" if ranks in counts else ""
        print(
            f"| {ranks} | {row['grid']} | {n // ranks} | {row['iterations']:.2f} | {measured_ghosts} | "
            f"{row['ghosts']:.0f} | {row['step'] * 1e3:.2f} | {row['communication']:.2f} | {row['speedup']:.2f} | "
            f"{row['efficiency']:.2f} |"
        )


def split_costs(n: int) -> dict:
    """From split.csv (medians per solver_tol): the 1-rank step at the default tolerance, its
    iterations, and its cost per atom outside the CG iterations (a) and per iteration (b)."""
    tols = read_rows(tables(n) / "split.csv")
    loose, tight = (
        {key: statistics.median(row[key] for row in tols if row["solver_tol"] == tol) for key in tols[0]}
        for tol in sorted({row["solver_tol"] for row in tols}, reverse=True)
    )
    step = loose["loop_s"] / loose["steps"]
    per_iteration = (tight["loop_s"] - loose["loop_s"]) / (tight["iterations"] - loose["iterations"])
    per_iteration /= loose["steps"] * n
    return {
        "step": step,
        "iterations": loose["iterations"],
        "fixed": step / n - per_iteration * loose["iterations"],
        "per_iteration": per_iteration,
        "repeats": len(tols) // 2,
    }


def sizes(ns: list[int]) -> None:
    """The 1-rank cost per atom split into its part outside the CG iterations and its iterations,
    for each N with a split.csv: what the growth of the cost with N comes from."""
    rows = {n: split_costs(n) for n in ns}
    base = rows[min(ns)]
    print(
        "| N | ms per step | CG iterations | us per atom per step | outside the iterations (a) "
        f"| per iteration (b) | iterations x b | cost per atom / N = {min(ns)} |"
    )
    print("|--:|--:|--:|--:|--:|--:|--:|--:|")
    for n, row in rows.items():
        per_atom = row["step"] / n
        print(
            f"| {n} | {row['step'] * 1e3:.2f} | {row['iterations']:.2f} | {per_atom * 1e6:.3f} | "
            f"{row['fixed'] * 1e6:.3f} | {row['per_iteration'] * 1e6:.3f} | "
            f"{row['iterations'] * row['per_iteration'] * 1e6:.3f} | {per_atom / (base['step'] / min(ns)):.2f} |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument(
        "command",
        choices=(
            "prepare",
            "startup",
            "measure",
            "split",
            "iterations",
            "latency",
            "model",
            "sizes",
            "local",
        ),
    )
    parser.add_argument("--n", type=int, nargs="+", default=[16000])
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    parser.add_argument(
        "--local-solve-fraction", type=float, default=0.0, help="measure: run.local_solve_fraction (0: off)"
    )
    parser.add_argument(
        "--preconditioner",
        choices=PRECONDITIONERS,
        default=DEFAULT_PRECONDITIONER,
        help="measure, iterations: run.preconditioner",
    )
    parser.add_argument(
        "--label",
        default="",
        help="measure: write the table as <name>_<label>.csv beside the committed one",
    )
    args = parser.parse_args()
    if args.command == "sizes":
        sizes(args.n)
        return
    if args.command == "local":
        local_solves(args.n)
        return
    if len(args.n) != 1:
        parser.error(f"{args.command} takes one --n")
    args.n = args.n[0]
    if args.command == "prepare":
        prepare(args.n)
    elif args.command == "startup":
        startup_report(args.n)
    elif args.command == "measure":
        measure(args.n, args.local_solve_fraction, args.preconditioner, args.label)
    elif args.command == "iterations":
        iterations(args.n, args.ranks, args.preconditioner)
    elif args.command == "split":
        split(args.n)
    elif args.command == "latency":
        latency(args.n)
    else:
        model(args.n)


if __name__ == "__main__":
    main()

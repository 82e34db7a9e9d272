"""What run.solver_tol means on several ranks: one step of the default engine from a steady state,
solved on each rank count with each preconditioner at each tolerance, against the same step solved
on 1 rank with the default preconditioner at REFERENCE_TOL (BENCHMARKS.md, "One simulation across
MPI ranks").

The solve stops when |z|_max <= solver_tol, z = M^-1 r (M the preconditioner, r the residual).
With dilu, z is close to the error A^-1 r on one rank, but on several ranks M drops the couplings
of the pairs that cross a rank boundary, so the same tol may be a looser solve there. Block Jacobi
(each particle's own 6x6 block) is the same preconditioner on any number of ranks. Needs the states
of `mpi_scaling.py prepare --n N`:

    .venv/bin/python benchmarks/mpi_scaling.py prepare --n 16000
    .venv/bin/python benchmarks/mpi_accuracy.py errors --n 16000 [--ranks 1 2 4 8]   # errors, iterations
    .venv/bin/python benchmarks/mpi_accuracy.py report --n 16000 [--label L]   # print the tables again
    .venv/bin/python benchmarks/mpi_accuracy.py timing --n 16000 [--label L]   # idle machine
    .venv/bin/python benchmarks/mpi_accuracy.py counts --n 16000 --ranks 4 8   # iterations at the matched tols
    .venv/bin/python benchmarks/mpi_accuracy.py model --n 16000 --labels L1 L2   # 1-64 ranks, equal accuracy

States: the prepared state (strain PREPARE_STRAIN) and STATE_COUNT - 1 more, each STATE_SPACING strain
after the one before on 1 rank (made once, into results/mpi_scaling/n<N>/accuracy_states/). From each
state benchmarks/one_step_velocities.lmp runs one step with each setting; the largest and the rms
difference of the solved velocities (translational and angular, units gammadot d and gammadot) from
the reference. Where the solve stops between two iterations moves a single step's error by a factor
of about two, so a setting is judged by its error over the default engine's (1 rank, the default
preconditioner and solver_tol) on the same state: the geometric mean of that ratio over the states,
with its 95% t-interval (the states the units). The matched tol of a (ranks, preconditioner) is the
loosest of TOLERANCES whose mean ratios, largest and rms, are both at most 1. Then for each setting
on at most as many ranks as the machine has cores, the mean CG iterations per step over ITERATION_STRAIN
from the prepared state (counts only: they do not depend on the host's load; on more ranks than cores
the waiting ranks spin on the shared cores and 200 steps take many minutes). Writes
benchmarks/data/mpi_scaling/n<N>/accuracy.csv and accuracy_iterations.csv; `report` prints them again.

`timing`: the default engine on 1 rank, each other preconditioner on 1 rank and each preconditioner on 2 ranks
at its matched tol, MEASURE_STRAIN from the prepared state, the runs of a round in an order that rotates,
REPEATS rounds: the speed-up of 2 ranks at the 1-rank default's accuracy, each preconditioner's loop time over
the default's on 2 ranks, and another preconditioner's 1-rank loop time over the default's (what `model`
needs of it) and its own 2-rank speed-up (accuracy_timing.csv, or accuracy_timing_<label>.csv beside it).

`counts`: each preconditioner's mean CG iterations at its matched tol on the given rank counts, added to
accuracy_iterations.csv (the runs may share the cores: only the counts are kept).

`model`: mpi_scaling.py's model of the step on P ranks (1-64), with each preconditioner at its matched tol,
against the 1-rank default engine: the parallel efficiency at equal accuracy (the function's docstring).
"""

from __future__ import annotations

import argparse
import csv
import os
import statistics
import subprocess
from pathlib import Path

import numpy as np
from mpi_scaling import (
    DEFAULT_PRECONDITIONER,
    ITERATION_STRAIN,
    MODEL_RANKS,
    PRECONDITIONERS,
    PREPARE_STRAIN,
    checkpoint,
    communication,
    continuation,
    continuation_settings,
    folder,
    iteration_growth,
    iterations_on,
    labelled,
    model_inputs,
    model_row,
    rotating_rounds,
    tables,
    write_rows,
)
from scipy import stats

from suspension_fabric.io.schema import schema_default
from suspension_fabric.simulation.lammps import RUN_FILES, ForceModel, ShearSettings, is_complete, run_rotation
from suspension_fabric.simulation.lammps.process import lammps_command, lammps_environment, thermo_rows
from suspension_fabric.simulation.lammps.runner import shear_run_variables

SCRIPT = Path(__file__).with_name("one_step_velocities.lmp")
STATE_COUNT = 8
STATE_SPACING = 0.02
RANKS = (1, 2)
TOLERANCES = (1e-3, 5e-4, 3e-4, 1e-4)
REFERENCE_TOL = 1e-8
DEFAULT_TOL = schema_default("run", "solver_tol")
VELOCITY_FILE = "velocities.dump"
DUMP_HEADER_LINES = 9


def states(n: int) -> dict[str, Path]:
    """The prepared checkpoint and STATE_COUNT - 1 more, each STATE_SPACING strain after the one before on 1
    rank (made here once, into results/mpi_scaling/n<N>/accuracy_states/)."""
    if not is_complete(folder(n) / "startup"):
        raise SystemExit(f"no prepared state for N = {n}: run benchmarks/mpi_scaling.py prepare --n {n} first")
    found = {f"{PREPARE_STRAIN:g}": checkpoint(n)}
    settings = continuation_settings(STATE_SPACING)
    for k in range(1, STATE_COUNT):
        strain = f"{PREPARE_STRAIN + k * STATE_SPACING:g}"
        run = folder(n) / "accuracy_states" / f"strain{strain}"
        if not is_complete(run):
            run_rotation(
                run, list(found.values())[-1], 0.0, STATE_SPACING, settings=settings, overwrite=True, progress=None
            )
        found[strain] = run / RUN_FILES["checkpoint"]
    return found


def one_step(state: Path, ranks: int, preconditioner: str, tol: float, run_dir: Path) -> tuple[np.ndarray, float]:
    """The velocities after one step from `state` (rows by atom ID: id, v, omega) and its CG iterations."""
    defaults = ShearSettings()
    step = defaults.dt * defaults.rate
    settings = ShearSettings(dump_strain=step, table_strain=step, thermo_strain=step, restart_strain=step, ranks=ranks)
    source = {
        "start_from": "checkpoint",
        "start_file": str(state.resolve()),
        "segment_index": "1",
        "flow_angle_deg": "0.0",
        "turning_deg_per_strain": "0.0",
        **ForceModel(preconditioner=preconditioner, solver_tol=tol).variables(),
    }
    variables = {**shear_run_variables(source, settings, step), "velocity_file": VELOCITY_FILE}
    run_dir.mkdir(parents=True, exist_ok=True)
    command = lammps_command(SCRIPT, variables, ranks)
    done = subprocess.run(command, cwd=run_dir, env=lammps_environment(), capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed in {run_dir}:\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    iterations = thermo_rows((run_dir / "log.lammps").read_text())[-1]["v_solver_iterations"]
    return np.loadtxt(run_dir / VELOCITY_FILE, skiprows=DUMP_HEADER_LINES), iterations


def settings_grid(ranks_list: tuple[int, ...]) -> list[tuple[int, str, float]]:
    return [(ranks, p, tol) for ranks in ranks_list for p in PRECONDITIONERS for tol in TOLERANCES]


def measure(n: int, ranks_list: tuple[int, ...] = RANKS) -> None:
    """The one-step errors of every setting on every state (accuracy.csv), then the settings' mean CG
    iterations (accuracy_iterations.csv)."""
    rows = []
    for name, state in states(n).items():
        scratch = folder(n) / "accuracy" / f"strain{name}"
        reference, _ = one_step(state, 1, DEFAULT_PRECONDITIONER, REFERENCE_TOL, scratch / "reference")
        for ranks, preconditioner, tol in settings_grid(ranks_list):
            velocities, iterations = one_step(
                state, ranks, preconditioner, tol, scratch / f"ranks{ranks}_{preconditioner}_{tol:g}"
            )
            if not np.array_equal(velocities[:, 0], reference[:, 0]):
                raise SystemExit(f"{state}: the dumps of {ranks} ranks and of the reference list other atoms")
            difference = velocities[:, 1:] - reference[:, 1:]
            rows.append(
                {
                    "state": name,
                    "ranks": ranks,
                    "preconditioner": preconditioner,
                    "tol": tol,
                    "step_iterations": iterations,
                    "largest": float(np.abs(difference).max()),
                    "rms": float(np.sqrt(np.mean(difference**2))),
                }
            )
            print(rows[-1], flush=True)
    write_rows(rows, tables(n) / "accuracy.csv")
    # more ranks than cores: the waiting ranks spin on the shared cores and 200 steps take many minutes
    counted = settings_grid(tuple(r for r in ranks_list if r <= os.cpu_count()))
    write_rows([iteration_count(n, *setting) for setting in counted], tables(n) / "accuracy_iterations.csv")


def iteration_count(n: int, ranks: int, preconditioner: str, tol: float) -> dict:
    """The mean CG iterations per step of a setting over ITERATION_STRAIN from the prepared state."""
    model = ForceModel(preconditioner=preconditioner, solver_tol=tol)
    run = continuation(n, ranks, ITERATION_STRAIN, f"accuracy_iterations_ranks{ranks}_{preconditioner}_{tol:g}", model)
    row = {"ranks": ranks, "preconditioner": preconditioner, "tol": tol, "iterations": run["iterations"]}
    print(row, flush=True)
    return row


def matched_counts(n: int, ranks_list: tuple[int, ...]) -> None:
    """Each preconditioner's mean CG iterations at its matched tol on each of `ranks_list`, added to
    accuracy_iterations.csv (a row of the same setting replaced): the counts `model` needs on more ranks
    than the machine has cores, where the runs take minutes but the counts do not mind."""
    path = tables(n) / "accuracy_iterations.csv"
    matched = matched_tolerances(error_ratios(read_table(tables(n) / "accuracy.csv")))
    missing = [(ranks, name) for ranks in ranks_list for name in PRECONDITIONERS if matched.get((ranks, name)) is None]
    if missing:
        raise SystemExit(f"{tables(n) / 'accuracy.csv'} has no matched tol for (ranks, preconditioner) {missing}")
    rows = {(int(r["ranks"]), r["preconditioner"], r["tol"]): r for r in read_table(path)}
    for ranks in ranks_list:
        for name in PRECONDITIONERS:
            row = iteration_count(n, ranks, name, matched[(ranks, name)])
            rows[(ranks, name, row["tol"])] = row
    write_rows([{**row, "ranks": int(row["ranks"])} for row in rows.values()], path)


def read_table(path: Path) -> list[dict]:
    """A committed table's rows, numbers as floats and names as strings."""
    with path.open() as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        for key in ("ranks", "tol", "step_iterations", "largest", "rms", "iterations", "repeat", "loop_s"):
            if key in row:
                row[key] = float(row[key])
    return rows


def is_default(row: dict) -> bool:
    return (int(row["ranks"]), row["preconditioner"], float(row["tol"])) == (1, DEFAULT_PRECONDITIONER, DEFAULT_TOL)


def error_ratios(errors: list[dict]) -> dict[tuple[int, str, float], dict[str, tuple[float, float, float]]]:
    """Per setting, the geometric mean over the states of its largest and rms difference over the default
    engine's on the same state, with the 95% t-interval: {setting: {"largest": (mean, low, high), "rms": ...}}."""
    default = {row["state"]: row for row in errors if is_default(row)}
    grouped: dict[tuple[int, str, float], list[dict]] = {}
    for row in errors:
        grouped.setdefault((int(row["ranks"]), row["preconditioner"], row["tol"]), []).append(row)
    ratios = {}
    for setting, rows in grouped.items():
        ratios[setting] = {}
        for key in ("largest", "rms"):
            logs = np.log([row[key] / default[row["state"]][key] for row in rows])
            half = stats.t.ppf(0.975, len(logs) - 1) * logs.std(ddof=1) / np.sqrt(len(logs))
            ratios[setting][key] = tuple(
                float(np.exp(v)) for v in (logs.mean(), logs.mean() - half, logs.mean() + half)
            )
    return ratios


def matched_tolerances(ratios: dict) -> dict[tuple[int, str], float | None]:
    """Per (ranks, preconditioner), the loosest tol whose mean ratios, largest and rms, are both at most 1
    (None: no tol of the grid)."""
    matched = {}
    for ranks, preconditioner in sorted({(ranks, p) for ranks, p, _ in ratios}):
        within = [
            tol
            for (r, p, tol), ratio in sorted(ratios.items(), key=lambda item: -item[0][2])
            if (r, p) == (ranks, preconditioner) and ratio["largest"][0] <= 1 and ratio["rms"][0] <= 1
        ]
        matched[(ranks, preconditioner)] = within[0] if within else None
    return matched


def report(n: int) -> None:
    errors = read_table(tables(n) / "accuracy.csv")
    counts = read_table(tables(n) / "accuracy_iterations.csv")
    iterations = {(int(r["ranks"]), r["preconditioner"], r["tol"]): r["iterations"] for r in counts}
    ratios = error_ratios(errors)

    def counted(ranks: int, preconditioner: str, tol: float) -> str:
        found = iterations.get((ranks, preconditioner, tol))
        return "-" if found is None else f"{found:.2f}"

    states_count = len({row["state"] for row in errors})
    print(
        f"N = {n}: one step from each of {states_count} states; difference from 1 rank, {DEFAULT_PRECONDITIONER} "
        f"at tol {REFERENCE_TOL:g}, over that of 1 rank, {DEFAULT_PRECONDITIONER} at tol {DEFAULT_TOL:g} on the "
        f"same state: geometric mean [95% t-interval over the states]; mean CG iterations per step over "
        f"{ITERATION_STRAIN:g} strain\n"
    )
    print("| ranks | preconditioner | tol | largest / default's | rms / default's | CG iterations per step |")
    print("|--:|---|--:|--:|--:|--:|")
    for (ranks, preconditioner, tol), ratio in sorted(
        ratios.items(), key=lambda item: (item[0][0], item[0][1], -item[0][2])
    ):
        cells = [f"{m:.2f} [{lo:.2f}, {hi:.2f}]" for m, lo, hi in (ratio["largest"], ratio["rms"])]
        print(
            f"| {ranks} | {preconditioner} | {tol:g} | {cells[0]} | {cells[1]} | "
            f"{counted(ranks, preconditioner, tol)} |"
        )
    print("\nmatched tol (the loosest whose mean ratios are both <= 1) and its iterations per step:")
    for (ranks, preconditioner), tol in matched_tolerances(ratios).items():
        found = f"{tol:g}, {counted(ranks, preconditioner, tol)} iterations" if tol else "none of the grid"
        print(f"- {ranks} rank(s), {preconditioner}: {found}")


def timing(n: int, label: str = "") -> None:
    """The default engine on 1 rank, each other preconditioner on 1 rank and each preconditioner on 2 ranks at
    its matched tol (accuracy.csv), the runs of a round in an order that rotates from round to round, REPEATS
    rounds of MEASURE_STRAIN from the prepared state: the speed-up of 2 ranks at the 1-rank default's accuracy
    (accuracy_timing.csv, or accuracy_timing_<label>.csv)."""
    matched = matched_tolerances(error_ratios(read_table(tables(n) / "accuracy.csv")))
    runs = [(1, DEFAULT_PRECONDITIONER, DEFAULT_TOL)]
    others = [name for name in PRECONDITIONERS if name != DEFAULT_PRECONDITIONER]
    runs += [(1, name, matched[(1, name)]) for name in others if matched[(1, name)] is not None]
    runs += [(2, name, matched[(2, name)]) for name in PRECONDITIONERS if matched[(2, name)] is not None]
    print("| round | ranks | preconditioner | tol | loop s | mean CG iterations | host steal % |")
    print("|--:|--:|---|--:|--:|--:|--:|")
    rows = rotating_rounds(
        n,
        [
            (
                ranks,
                f"accuracy_timing_ranks{ranks}_{name}",
                ForceModel(preconditioner=name, solver_tol=tol),
                {"preconditioner": name, "tol": tol},
            )
            for ranks, name, tol in runs
        ],
    )
    write_rows(rows, tables(n) / f"accuracy_timing{labelled(label)}.csv")
    print()
    print_timing(rows)


def print_timing(rows: list[dict]) -> None:
    """Per 2-rank setting, the 1-rank default's loop time over its own in each round, and the median; where
    another preconditioner also ran on 1 rank at its matched tol (the tables since `timing` runs it), its 1-rank loop
    time over the default's and its own 2-rank speed-up."""
    one_rank = {row["repeat"]: row["loop_s"] for row in rows if int(row["ranks"]) == 1 and is_default(row)}
    for name in dict.fromkeys(row["preconditioner"] for row in rows if int(row["ranks"]) == 2):
        mine = [row for row in rows if int(row["ranks"]) == 2 and row["preconditioner"] == name]
        speedups = [one_rank[row["repeat"]] / row["loop_s"] for row in mine]
        print(
            f"2 ranks, {name} at tol {float(mine[0]['tol']):g}: speed-up over 1 rank, {DEFAULT_PRECONDITIONER} at "
            f"{DEFAULT_TOL:g}, per round {', '.join(f'{x:.2f}' for x in speedups)}; "
            f"median {statistics.median(speedups):.2f}"
        )
    two_ranks = {(row["repeat"], row["preconditioner"]): row["loop_s"] for row in rows if int(row["ranks"]) == 2}
    for name in (name for name in PRECONDITIONERS if name != DEFAULT_PRECONDITIONER):
        if (1.0, name) in two_ranks and (1.0, DEFAULT_PRECONDITIONER) in two_ranks:
            ratios = [two_ranks[(r, name)] / two_ranks[(r, DEFAULT_PRECONDITIONER)] for r, p in two_ranks if p == name]
            print(
                f"2 ranks: {name}'s loop time over {DEFAULT_PRECONDITIONER}'s per round "
                f"{', '.join(f'{x:.2f}' for x in ratios)}; median {statistics.median(ratios):.2f}"
            )
    for name in (name for name in PRECONDITIONERS if name != DEFAULT_PRECONDITIONER):
        alone = {row["repeat"]: row for row in rows if int(row["ranks"]) == 1 and row["preconditioner"] == name}
        if not alone:
            continue
        tol = float(next(iter(alone.values()))["tol"])
        over_default = [alone[r]["loop_s"] / one_rank[r] for r in alone]
        split = [alone[r]["loop_s"] / two_ranks[(r, name)] for r in alone if (r, name) in two_ranks]
        print(
            f"1 rank, {name} at tol {tol:g}: loop time over 1 rank, {DEFAULT_PRECONDITIONER} at {DEFAULT_TOL:g}, "
            "per round "
            f"{', '.join(f'{x:.2f}' for x in over_default)}; median {statistics.median(over_default):.2f}"
        )
        if split:
            print(
                f"{name} at tol {tol:g}: speed-up of 2 ranks over its 1 rank, per round "
                f"{', '.join(f'{x:.2f}' for x in split)}; "
                f"median {statistics.median(split):.2f}"
            )


def equal_accuracy_model(n: int, labels: list[str]) -> dict:
    """mpi_scaling.py's model of the step on P ranks (its docstring), at the 1-rank default's accuracy: each
    preconditioner at its matched tol on each P (beyond the most ranks counted, at theirs and with the
    iterations growing as from 2 ranks to them), against the 1-rank default. dilu's compute is a + b I(P) per
    atom with the default's a and b (only the tol differs). A preconditioner whose iterations are the same on
    every rank count (block Jacobi) has its compute on P ranks as its 1-rank step over P; that step is its
    loop time over the default's in the same round of the timing tables (`labels`, their rounds pooled; median),
    times the default's 1-rank step there (median). The 2-rank speed-ups are checked against the tables' medians.
    Returns {"inputs", "matched", "steps_one", "most", "growth", "check": {name: (modelled, measured)}, "rows"}."""
    inputs = model_inputs(n)
    matched = matched_tolerances(error_ratios(read_table(tables(n) / "accuracy.csv")))
    counted = {
        (int(r["ranks"]), r["preconditioner"], r["tol"]): r["iterations"]
        for r in read_table(tables(n) / "accuracy_iterations.csv")
    }
    rounds = []
    for label in labels:
        table = read_table(tables(n) / f"accuracy_timing{labelled(label)}.csv")
        rounds += [[row for row in table if row["repeat"] == repeat] for repeat in sorted({r["repeat"] for r in table})]

    # the seconds from the timing rounds themselves (the host's speed drifts between sessions), the
    # iterations' share of the 1-rank step from split.csv
    defaults = [row for runs in rounds for row in runs if is_default(row)]
    step_one = statistics.median(row["loop_s"] / float(row["steps"]) for row in defaults)
    iterations_one = statistics.median(row["iterations"] for row in defaults)
    fixed = (1.0 - inputs["share"]) * step_one / n
    per_iteration = inputs["share"] * step_one / (n * iterations_one)

    def per_round(ranks: int, name: str) -> list[float]:
        """The default's 1-rank loop time over the setting's, per round that ran it."""
        found = []
        for runs in rounds:
            default = next(row["loop_s"] for row in runs if is_default(row))
            found += [default / r["loop_s"] for r in runs if int(r["ranks"]) == ranks and r["preconditioner"] == name]
        return found

    def counts_at_matched_tol(name: str) -> dict[int, float]:
        """{P: iterations at the matched tol on P ranks}."""
        settings = [(ranks, p, tol) for (ranks, p), tol in matched.items() if p == name]
        counts = {setting[0]: counted[setting] for setting in settings if setting in counted}
        if name != DEFAULT_PRECONDITIONER and len(set(counts.values())) > 1:
            raise SystemExit(f"{name}'s iterations at its matched tols differ with the ranks ({counts}): no model")
        return counts

    counts = {name: counts_at_matched_tol(name) for name in PRECONDITIONERS}
    steps_one = {DEFAULT_PRECONDITIONER: step_one}
    for name in PRECONDITIONERS:
        if name != DEFAULT_PRECONDITIONER:
            alone = per_round(1, name)
            if not alone:
                raise SystemExit(f"the timing tables {labels} have no 1-rank {name} run: run `timing` again")
            steps_one[name] = step_one / statistics.median(alone)

    # the counts' window is shorter than the timing runs': their ratios to the 1-rank default carry over
    window = iterations_one / counts[DEFAULT_PRECONDITIONER][1]

    def step_at(name: str, ranks: int) -> tuple[float, float, float]:
        iterations = window * iterations_on(counts[name], ranks)
        seconds = communication(n, ranks, iterations, inputs)[1]
        if name == DEFAULT_PRECONDITIONER:
            compute = n / ranks * (fixed + per_iteration * iterations)
        else:
            compute = steps_one[name] / ranks
        return iterations, compute + seconds, seconds

    most = {name: max(counts[name]) for name in PRECONDITIONERS}
    rows = []
    for ranks in sorted({r for c in counts.values() for r in c} | set(MODEL_RANKS)):
        for name in PRECONDITIONERS:
            iterations, step, seconds = step_at(name, ranks)
            rows.append(
                {
                    **model_row(ranks, inputs["lengths"], iterations, step, seconds, step_one),
                    "preconditioner": name,
                    "tol": matched.get((ranks, name), matched[(most[name], name)]),
                }
            )
    return {
        "inputs": {**inputs, "step_one": step_one, "fixed": fixed, "per_iteration": per_iteration},
        "matched": matched,
        "steps_one": steps_one,
        "most": most,
        "growth": {name: iteration_growth(counts[name]) for name in PRECONDITIONERS},
        "check": {name: (step_one / step_at(name, 2)[1], statistics.median(per_round(2, name))) for name in counts},
        "rounds": len(rounds),
        "rows": rows,
    }


def model(n: int, labels: list[str]) -> None:
    """Prints equal_accuracy_model: its inputs, the check at 2 ranks, and a Markdown row per (P, preconditioner)."""
    found = equal_accuracy_model(n, labels)
    inputs, matched, most = found["inputs"], found["matched"], found["most"]
    print(
        f"N = {n}, at the accuracy of 1 rank, {DEFAULT_PRECONDITIONER} at {DEFAULT_TOL:g}. 1 rank (timing): "
        f"{inputs['step_one'] * 1e3:.1f} ms per step, a = {inputs['fixed'] * 1e6:.3f} and "
        f"b = {inputs['per_iteration'] * 1e6:.3f} us per atom; "
        + "; ".join(
            f"{name}: 1-rank step {found['steps_one'][name] * 1e3:.1f} ms at tol {matched[(1, name)]:g}, beyond "
            f"{most[name]} ranks tol {matched[(most[name], name)]:g} and I(P) growing by "
            f"{found['growth'][name]:.2f} per doubling"
            for name in PRECONDITIONERS
        )
        + f". Check at P = 2, speed-up modelled against measured (timing {', '.join(labels)}, median of "
        f"{found['rounds']} rounds): "
        + ", ".join(
            f"{name} {modelled:.2f} against {measured:.2f}" for name, (modelled, measured) in found["check"].items()
        )
        + "\n"
    )
    print(
        "| ranks P | grid | preconditioner | tol | CG iterations I(P) | ms per step | of it communication "
        "| speed-up | efficiency |"
    )
    print("|--:|:-:|---|--:|--:|--:|--:|--:|--:|")
    for row in found["rows"]:
        print(
            f"| {row['ranks']} | {row['grid']} | {row['preconditioner']} | {row['tol']:g} | {row['iterations']:.2f} | "
            f"{row['step'] * 1e3:.2f} | {row['communication']:.2f} | {row['speedup']:.2f} | {row['efficiency']:.2f} |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("command", choices=("errors", "report", "timing", "counts", "model"))
    parser.add_argument("--n", type=int, default=16000)
    parser.add_argument(
        "--ranks",
        type=int,
        nargs="+",
        default=list(RANKS),
        help="errors: the rank counts (1 first), counts: the rank counts to add (more than 2 share this "
        "machine's cores, which the counts and errors do not mind)",
    )
    parser.add_argument(
        "--label",
        default="",
        help="timing: write the table as accuracy_timing_<label>.csv; report: read that table",
    )
    parser.add_argument(
        "--labels", nargs="+", default=[""], help="model: the timing tables (accuracy_timing_<label>.csv) to pool"
    )
    args = parser.parse_args()
    if args.command == "errors" and 1 not in args.ranks:
        parser.error("--ranks must include 1: the errors are compared with the 1-rank default engine's")
    if args.command == "errors":
        measure(args.n, tuple(args.ranks))
    if args.command in ("errors", "report"):
        report(args.n)
        timings = tables(args.n) / f"accuracy_timing{labelled(args.label)}.csv"
        if args.command == "report" and timings.exists():
            print()
            print_timing(read_table(timings))
    if args.command == "timing":
        timing(args.n, args.label)
    if args.command == "counts":
        matched_counts(args.n, tuple(args.ranks))
    if args.command == "model":
        model(args.n, args.labels)


if __name__ == "__main__":
    main()

"""The step error of the two contact solves, paired on the same sheared states (BENCHMARKS.md,
"Engine III").

Each state is the end of a steady startup (a run's ``checkpoint.rst``, one per seed). From it,
every rung continues the shear for ``--strain`` at one (solve, dt as a fraction of tau) and
records the mean contact shear stress and pressure (units eta_f gammadot), the contact number
per particle, the sliding fraction, the contact-state passes and CG iterations per step and the
LAMMPS wall time per unit strain. Over so short a horizon the trajectories from one state stay
close, so a rung's difference from the reference rung on the same state is its step error, not
sampling noise; the seeds' states are the independent units (mean and 95% t-interval over them).

    .venv/bin/python benchmarks/contact_solve.py run --point phi0.53_mu0.5 \
        --states 'results/engine_newton_phi0.53_mu0.5/seed*/startup/checkpoint.rst'
    .venv/bin/python benchmarks/contact_solve.py report

    .venv/bin/python benchmarks/contact_solve.py local --point phi0.55_mu1 \
        --states 'results/corner_probe/seed*/startup/checkpoint.rst' --strain 0.05 \
        --config benchmarks/configs/campaign_corner_point.yaml
    .venv/bin/python benchmarks/contact_solve.py guess --point phi0.55_mu1 \
        --states 'results/corner_probe/seed*/startup/checkpoint.rst' --strain 0.05 \
        --config benchmarks/configs/campaign_corner_point.yaml
    .venv/bin/python benchmarks/contact_solve.py precond --point phi0.55_mu1 \
        --states 'results/corner_probe/seed*/startup/checkpoint.rst' --strain 0.05 \
        --config benchmarks/configs/campaign_corner_point.yaml
    .venv/bin/python benchmarks/contact_solve.py tol --point phi0.55_mu1 \
        --states 'results/corner_probe/seed*/startup/checkpoint.rst' --strain 0.05 \
        --config benchmarks/configs/campaign_corner_point.yaml

`local`: from each state, the point's own engine (its solve and dt) with each
run.local_solve_fraction of LOCAL_FRACTIONS in turn (the old velocities as the solve's first
iterate), LOCAL_REPEATS rounds (the same solve to the tolerance, so the wall times compare the
local solves' cost; time it on an idle machine); `local-report` prints its table again.
`guess`: the same with each (run.initial_guess, run.local_solve_fraction) of GUESS_RUNGS;
`guess-report` prints its table again. `precond`: the same with each (run.preconditioner,
run.initial_guess, run.local_solve_fraction) of PRECOND_RUNGS; `precond-report`. `tol`: the same
with each (run.preconditioner, run.initial_guess, run.local_solve_fraction, run.solver_tol) of
TOL_RUNGS; `tol-report`. The tables were measured with the corner point's first engine (kn =
1.5625e10, dt = 8e-6, dilu, the old velocities as the first iterate, solver_tol 1e-3), which
benchmarks/configs/campaign_corner_point.yaml keeps.

The reference rung is the lagged solve at 0.024 tau (the campaign's engine; tau = X(delta)/kn of
two small spheres, suspension_fabric.simulation.scales.contact_relaxation_time). The wall times
are of one LAMMPS process; time it on an idle machine.
"""

from __future__ import annotations

import argparse
import glob
import time
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

from suspension_fabric.simulation.lammps import ForceModel
from suspension_fabric.simulation.lammps.plugin import new_lammps
from suspension_fabric.simulation.scales import contact_relaxation_time
from suspension_fabric.study.campaign import campaign_points
from suspension_fabric.study.config import load_config

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
TABLE = HERE / "data" / "contact_solve.csv"
#: (solve, dt as a fraction of tau); the first is the reference
RUNGS = (("lagged", 0.024), ("lagged", 0.24), ("newton", 0.12), ("newton", 0.24), ("newton", 0.6))
QUANTITIES = ("contact_12", "contact_pressure", "contact_number", "sliding_fraction")
LOCAL_TABLE = HERE / "data" / "contact_solve_local.csv"
#: run.local_solve_fraction of the `local` command; the first (global iterations only) is the reference
LOCAL_FRACTIONS = (0.0, 0.02, 0.05)
LOCAL_REPEATS = 3
GUESS_TABLE = HERE / "data" / "contact_solve_guess.csv"
#: (run.initial_guess, run.local_solve_fraction) of the `guess` command; the first is the reference
GUESS_RUNGS = (("previous", 0.0), ("linear", 0.0), ("quadratic", 0.0), ("quadratic", 0.02))
PRECOND_TABLE = HERE / "data" / "contact_solve_precond.csv"
#: (run.preconditioner, run.initial_guess, run.local_solve_fraction) of the `precond` command; the
#: first (the engine the map's first datasets of (0.53, 1) and (0.55, 1) were made with) is the reference
PRECOND_RUNGS = (
    ("dilu", "previous", 0.0),
    ("jacobi", "previous", 0.0),
    ("dilu", "quadratic", 0.02),
    ("jacobi", "quadratic", 0.02),
)
TOL_TABLE = HERE / "data" / "contact_solve_tol.csv"
#: (run.preconditioner, run.initial_guess, run.local_solve_fraction, run.solver_tol) of the `tol`
#: command; the first (the map's engine) is the reference
TOL_RUNGS = (
    ("dilu", "previous", 0.0, 1e-3),
    ("dilu", "quadratic", 0.02, 1e-3),
    ("dilu", "quadratic", 0.02, 3e-4),
    ("jacobi", "quadratic", 0.02, 3e-4),
    ("jacobi", "quadratic", 0.02, 1e-4),
)
#: the run settings a rung of the `local`, `guess`, `precond` or `tol` command sets, by its length
RUNG_KEYS = {
    1: ("local_solve_fraction",),
    2: ("initial_guess", "local_solve_fraction"),
    3: ("preconditioner", "initial_guess", "local_solve_fraction"),
    4: ("preconditioner", "initial_guess", "local_solve_fraction", "solver_tol"),
}


def point_study(name: str, config: Path) -> dict:
    """The validated study of one point of a campaign config (the two points the Newton solve freed:
    benchmarks/configs/campaign_newton_points.yaml)."""
    points = campaign_points(load_config(config))
    if name not in points:
        raise SystemExit(f"{config}: no point {name!r} to run (points: {', '.join(points)})")
    return points[name]


def rung_dt(fraction: float, tau: float) -> float:
    """fraction x tau rounded down to 1, 2, 4 or 5 x 10^k (whole steps per output stride)."""
    target = fraction * tau
    decade = 10.0 ** np.floor(np.log10(target))
    return float(max(m * decade for m in (1, 2, 4, 5) if m * decade <= target * (1 + 1e-9)))


def engine_from_checkpoint(checkpoint: Path, study: dict, dt: float):
    """A LAMMPS instance holding ``checkpoint`` under the shear, with the study's engine (its forces and
    run settings) and step ``dt``, set up by a zero-step run."""
    v = ForceModel.from_config(study).variables()
    lmp = new_lammps(load_plugin=False)
    lmp.commands_string(
        f"""
units lj
atom_style sphere
atom_modify map array
dimension 3
boundary p p p
plugin load {v["plugin"]}
read_restart {checkpoint}
newton on on
pair_style lubricate/sf {v["eta_f"]} {v["delta"]} {v["h_out"]} implicit
pair_coeff * *
fix integrate all hydro/implicit/sf tol {v["solver_tol"]} precond {v["preconditioner"]} &
    contacts {v["kn"]} {v["kt"]} {v["mu"]} solve {study["run"]["contact_solve"]} local {v["local_solve_fraction"]} &
    guess {v["initial_guess"]}
neighbor 0.1 bin
neigh_modify delay 0 every 1 check yes
comm_modify mode single vel yes
fix shear all deform 1 xz erate 1.0 remap v flip yes
timestep {dt!r}
thermo_style custom step
run 0 post no
"""
    )
    return lmp


def continue_shear(
    checkpoint: Path,
    study: dict,
    solve: str,
    dt: float,
    strain: float,
    local_fraction: float = 0.0,
    initial_guess: str = "previous",
    preconditioner: str | None = None,
    solver_tol: float | None = None,
) -> dict:
    """Means over ``strain`` of shear continued from ``checkpoint``, and the wall time per strain."""
    run = {
        **study["run"],
        "contact_solve": solve,
        "local_solve_fraction": local_fraction,
        "initial_guess": initial_guess,
        "preconditioner": preconditioner or study["run"]["preconditioner"],
        "solver_tol": solver_tol or study["run"]["solver_tol"],
    }
    lmp = engine_from_checkpoint(checkpoint, {**study, "run": run}, dt)
    scale = 1.0 / study["forces"]["eta_f"]
    samples, chunks = [], 20
    steps = max(1, round(strain / chunks / dt))
    start = time.perf_counter()
    for _ in range(chunks):
        lmp.command(f"run {steps} post no")
        f = [lmp.extract_fix("integrate", 0, 1, k) for k in range(30)]
        volume, atoms = lmp.get_thermo("vol"), lmp.get_natoms()
        samples.append(
            {
                "contact_12": -f[7] / volume * scale,
                "contact_pressure": (f[3] + f[4] + f[5]) / (3.0 * volume) * scale,
                "contact_number": 2.0 * f[19] / atoms,
                "sliding_fraction": f[20] / f[19] if f[19] else np.nan,
                "passes_per_step": f[18],
                "iterations_per_step": f[1],
                "local_work_per_step": f[29],
            }
        )
    wall = time.perf_counter() - start
    lmp.close()
    means = pd.DataFrame(samples)
    row = {q: means[q].mean() for q in QUANTITIES}
    # the fix's counters are means since it was defined: the last sample covers the whole run
    row.update(means.iloc[-1][["passes_per_step", "iterations_per_step", "local_work_per_step"]].to_dict())
    return {**row, "n": atoms, "wall_per_strain": wall / (chunks * steps * dt)}


def measure(point: str, states: list[Path], config: Path, strain: float) -> pd.DataFrame:
    study = point_study(point, config)
    forces = study["forces"]
    tau = contact_relaxation_time(1.0, 1.0, forces["eta_f"], forces["delta"], forces["kn"])
    rows = []
    for state in states:
        for solve, fraction in RUNGS:
            dt = rung_dt(fraction, tau)
            row = continue_shear(state, study, solve, dt, strain)
            rows.append(
                {
                    "point": point,
                    "state": str(state),
                    "kn": forces["kn"],
                    "tau": tau,
                    "solve": solve,
                    "dt": dt,
                    "strain": strain,
                    **row,
                }
            )
            print(
                pd.DataFrame(rows[-1:]).drop(columns="state").to_string(index=False, header=len(rows) == 1), flush=True
            )
    return pd.DataFrame(rows)


def measure_starts(
    point: str, states: list[Path], config: Path, strain: float, rungs: tuple[tuple, ...]
) -> pd.DataFrame:
    """The point's own engine (its solve and dt) from each state, with each rung of ``rungs`` (run
    settings named by RUNG_KEYS; the point's own for the others) in turn, LOCAL_REPEATS rounds: the
    same trajectory to the solver's tolerance, so the wall times compare the solves."""
    study = point_study(point, config)
    rows = []
    for repeat in range(1, LOCAL_REPEATS + 1):
        for state in states:
            for rung in rungs:
                settings = {key: study["run"][key] for key in RUNG_KEYS[4]} | dict(
                    zip(RUNG_KEYS[len(rung)], rung, strict=True)
                )
                row = continue_shear(
                    state,
                    study,
                    study["run"]["contact_solve"],
                    study["run"]["dt"],
                    strain,
                    settings["local_solve_fraction"],
                    settings["initial_guess"],
                    settings["preconditioner"],
                    settings["solver_tol"],
                )
                rows.append(
                    {"point": point, "state": str(state), "repeat": repeat}
                    | settings
                    | {"dt": study["run"]["dt"], "strain": strain, **row}
                )
                print(
                    pd.DataFrame(rows[-1:]).drop(columns="state").to_string(index=False, header=len(rows) == 1),
                    flush=True,
                )
    return pd.DataFrame(rows)


def _cell(value) -> str:
    return value if isinstance(value, str) else f"{value:g}"


def report_starts(table: pd.DataFrame, rungs: tuple, level: float = 0.95) -> str:
    """Per point and rung (``rungs``: local_solve_fraction values or tuples of the run settings
    RUNG_KEYS names by their length): CG
    iterations and local work per step, the wall time per strain (each state's median over the
    repeats) and its ratio to the first rung on the same state, mean and t-interval over the
    states; the contact quantities' largest relative difference from the first rung's run on the
    same state (the solves agree to the tolerance)."""
    keys = list(RUNG_KEYS[len(rungs[0]) if isinstance(rungs[0], tuple) else 1])
    reference = rungs[0] if len(keys) > 1 else (rungs[0],)
    lines = []
    sizes = "n" in table and table["n"].nunique() > 1  # one table per point and size
    for group, rows in table.groupby(["point", "n"] if sizes else "point", sort=False):
        per_state = rows.groupby([*keys, "state"]).median(numeric_only=True)
        base = per_state.xs(reference, level=keys)
        states = len(base)
        name = f"{group[0]}, N = {group[1]:g}" if sizes else group
        lines.append(
            f"{name}: dt {rows['dt'].iloc[0]:g}, {states} states, {rows['strain'].iloc[0]:g} strain from each, "
            f"{rows['repeat'].nunique()} rounds (median per state); ratio to "
            + ", ".join(f"{key} {_cell(value)}" for key, value in zip(keys, reference, strict=True))
            + f" on the same state, mean [{level:.0%} t-interval over states]\n"
        )
        first = "wall / global only" if len(keys) == 1 else "wall / first row"
        header = [*keys, "CG iterations/step", "local work/step (sweeps)", "wall s/strain"]
        header += [first, "contact quantities: largest relative change"]
        lines.append("| " + " | ".join(header) + " |")
        lines.append("|" + "--:|" * len(header))
        t = stats.t.ppf(0.5 + level / 2, states - 1) if states > 1 else np.nan
        for rung_key in rungs:
            values = rung_key if isinstance(rung_key, tuple) else (rung_key,)
            rung = per_state.xs(values, level=keys).loc[base.index]
            ratio = rung["wall_per_strain"] / base["wall_per_strain"]
            half = t * ratio.std(ddof=1) / np.sqrt(states)
            drift = max(float((rung[q] / base[q] - 1.0).abs().max()) for q in QUANTITIES)
            cells = [_cell(value) for value in values]
            cells += [f"{rung['iterations_per_step'].mean():.2f}"]
            cells += [f"{rung['local_work_per_step'].mean():.3f}", f"{rung['wall_per_strain'].mean():.1f}"]
            cells += [f"{ratio.mean():.3f} [{ratio.mean() - half:.3f}, {ratio.mean() + half:.3f}]", f"{drift:.2e}"]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def report(table: pd.DataFrame, level: float = 0.95) -> str:
    """Per point and rung: the mean over states of each quantity's relative difference from the
    reference rung on the same state, with its t-interval over the states, and the cost."""
    lines = []
    for point, rows in table.groupby("point", sort=False):
        reference = rows[(rows["solve"] == RUNGS[0][0]) & np.isclose(rows["dt"] / rows["tau"], RUNGS[0][1], rtol=0.2)]
        reference = reference.set_index("state")
        states = len(reference)
        lines.append(
            f"{point}: kn = {rows['kn'].iloc[0]:.4g}, tau = {rows['tau'].iloc[0]:.3g}, {states} states, "
            f"{rows['strain'].iloc[0]:g} strain from each; relative difference from the reference rung "
            f"(lagged, dt {reference['dt'].iloc[0]:g}) on the same state, mean [{level:.0%} t-interval over states]\n"
        )
        header = [
            "solve",
            "dt",
            "dt/tau",
            *QUANTITIES,
            "passes/step",
            "CG iterations/step",
            "wall s/strain",
            "speed-up",
        ]
        lines.append("| " + " | ".join(header) + " |")
        lines.append("|" + "---|" * len(header))
        t = stats.t.ppf(0.5 + level / 2, states - 1) if states > 1 else np.nan
        for (solve, dt), rung in rows.groupby(["solve", "dt"], sort=False):
            rung = rung.set_index("state").loc[reference.index]
            cells = [solve, f"{dt:g}", f"{dt / rung['tau'].iloc[0]:.3g}"]
            for quantity in QUANTITIES:
                change = rung[quantity] / reference[quantity] - 1.0
                half = t * change.std(ddof=1) / np.sqrt(states)
                cells.append(f"{change.mean():+.4f} [{change.mean() - half:+.4f}, {change.mean() + half:+.4f}]")
            speed = reference["wall_per_strain"].mean() / rung["wall_per_strain"].mean()
            cells += [
                f"{rung['passes_per_step'].mean():.2f}",
                f"{rung['iterations_per_step'].mean():.1f}",
                f"{rung['wall_per_strain'].mean():.1f}",
                f"{speed:.2f}",
            ]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "command",
        choices=("run", "report", "local", "local-report", "guess", "guess-report", "precond", "precond-report")
        + ("tol", "tol-report"),
    )
    parser.add_argument("--point", help="the campaign point whose engine the states were made with (run)")
    parser.add_argument("--states", help="glob of the checkpoints to continue, one per seed (run)")
    parser.add_argument("--config", type=Path, default=REPO / "config" / "campaign.yaml")
    parser.add_argument("--strain", type=float, default=0.1)
    args = parser.parse_args(argv)
    tables = {"run": TABLE, "local": LOCAL_TABLE, "guess": GUESS_TABLE, "precond": PRECOND_TABLE, "tol": TOL_TABLE}
    start_rungs = {
        "local": tuple(("previous", f) for f in LOCAL_FRACTIONS),
        "guess": GUESS_RUNGS,
        "precond": PRECOND_RUNGS,
        "tol": TOL_RUNGS,
    }
    if args.command in tables:
        states = [Path(p) for p in sorted(glob.glob(args.states or ""))]
        if not args.point or not states:
            parser.error(f"{args.command} needs --point and --states matching at least one checkpoint")
        path = tables[args.command]
        if args.command == "run":
            table = measure(args.point, states, args.config, args.strain)
        else:
            table = measure_starts(args.point, states, args.config, args.strain, start_rungs[args.command])
        if path.is_file():  # keep the other points' rows
            old = pd.read_csv(path)
            table = pd.concat([old[old["point"] != args.point], table], ignore_index=True)
        path.parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(path, index=False, float_format="%.6g")
    if args.command in ("local", "local-report"):
        print(report_starts(pd.read_csv(LOCAL_TABLE), LOCAL_FRACTIONS))
    elif args.command in ("guess", "guess-report"):
        print(report_starts(pd.read_csv(GUESS_TABLE), GUESS_RUNGS))
    elif args.command in ("precond", "precond-report"):
        print(report_starts(pd.read_csv(PRECOND_TABLE), PRECOND_RUNGS))
    elif args.command in ("tol", "tol-report"):
        print(report_starts(pd.read_csv(TOL_TABLE), TOL_RUNGS))
    else:
        print(report(pd.read_csv(TABLE)))


if __name__ == "__main__":
    main()

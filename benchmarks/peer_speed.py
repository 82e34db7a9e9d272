"""Speed of the project's engine against the peer code LF_DEM on the same packing, one core each,
at the same time: per code the wall time per unit strain over a window at steady state, the steps
per unit strain and the wall time per step.

A point is a study of config/campaign.yaml (``phi0.45_mu0.5`` is the paper's point): its packing
(seed 1, the pack rule's settings) is sheared from rest to the window's end by

- the project, with the engine that study runs (its kn, dt, contact solve and outputs:
  ForceModel.from_config, ShearSettings.from_config), and
- LF_DEM with the same physics (lfdem_comparison.py: lubrication resistances and cutoffs, contact
  dashpot at the resistance of xi = 0, Coulomb friction, kt = 2/7 kn, the spring matched on
  small-small pairs), overdamped with Heun steps of at most 1e-3 radii.

Both start together, so they share the machine alike. The project's progress reports (every thermo
line, its elapsed wall time) and LF_DEM's data table (polled every POLL_S, its last complete row's
strain) give each code's wall clock against strain; the time per unit strain is the slope of a
straight line through the (strain, wall) pairs inside the window. LF_DEM's steps per unit strain
are the mean of 1 / dt over its rows in the window (its data table's ``dt`` column is the mean
step of each output interval; time = strain at rate 1); the project's are 1 / dt.

    .venv/bin/python benchmarks/peer_speed.py run --lfdem /path/to/LF_DEM/LF_DEM --point phi0.45_mu0.5
    .venv/bin/python benchmarks/peer_speed.py run --lfdem ... --point phi0.50_mu0.5 --contact-solve newton
    .venv/bin/python benchmarks/peer_speed.py run --lfdem ... --point phi0.45_mu0.5 --n 1000 \\
        --contact-solve lagged newton --newton-gain 5
    .venv/bin/python benchmarks/peer_speed.py report

`run` appends one row per point and project engine to benchmarks/data/peer_speed.csv (several
engines are timed one after the other while one LF_DEM run goes on); `report` prints the table.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import threading
import time
from datetime import date
from pathlib import Path

import numpy as np
import pandas as pd
from lfdem_comparison import BUILD_HELP, data_columns, reached_strain, start_lfdem, write_lfdem_inputs

from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, pack, run_startup
from suspension_fabric.study.campaign import campaign_points
from suspension_fabric.study.config import load_config, validate_config

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
TABLE = HERE / "data" / "peer_speed.csv"
CAMPAIGN = REPO / "config" / "campaign.yaml"
WINDOW = (1.5, 2.5)
SEED = 1
POLL_S = 0.5
NEWTON_GAIN = 10.0


def point_study(name: str, contact_solve: str | None = None, newton_gain: float = NEWTON_GAIN) -> dict:
    """The study config/campaign.yaml runs at point ``name``; with ``contact_solve`` "newton" at a
    point the campaign runs with the lagged solve, the Newton solve at ``newton_gain`` times its step
    (10: 0.24 of the contact relaxation time instead of 0.024, docs/physics.md, "The contact law
    solved by Newton passes"; 5 at the paper's point, the step validated against data/reference)."""
    points = campaign_points(load_config(CAMPAIGN))
    if name not in points:
        raise SystemExit(f"{CAMPAIGN}: no point {name!r} (points: {', '.join(points)})")
    study = points[name]
    if contact_solve is None or contact_solve == study["run"]["contact_solve"]:
        return study
    if contact_solve != "newton":
        raise SystemExit(f"--contact-solve: {name} runs the Newton solve; only 'newton' changes a lagged point")
    run = {**study["run"], "engine": "as_given", "contact_solve": "newton", "dt": newton_gain * study["run"]["dt"]}
    run["max_dt_per_relaxation"] = 0.25
    return validate_config({**study, "study": "peer_speed", "run": run})


def lfdem_engine(force_model: ForceModel) -> dict:
    """The physics LF_DEM is given (lfdem_comparison.lfdem_parameters): the project's force model
    as its LAMMPS variables have it (kt defaulted there), at shear rate 1."""
    variables = force_model.variables()
    return {name: float(variables[name]) for name in ("kn", "kt", "mu", "h_out", "delta", "eta_f")} | {"rate": 1.0}


def window_slope(strain, wall, window) -> float:
    """Wall seconds per unit strain: the least-squares slope of wall against strain in ``window``."""
    strain, wall = np.asarray(strain, dtype=float), np.asarray(wall, dtype=float)
    inside = (strain >= window[0]) & (strain <= window[1])
    if inside.sum() < 3:
        raise RuntimeError(f"fewer than 3 progress points in the strain window {window}")
    return float(np.polyfit(strain[inside], wall[inside], 1)[0])


def run_peer(binary: Path, packing: Path, force_model: ForceModel, folder: Path, strain: float, clock: list) -> Path:
    """LF_DEM on ``packing`` to ``strain``; appends (strain, elapsed wall s) to ``clock`` as it runs."""
    write_lfdem_inputs(packing, folder, strain, lfdem_engine(force_model))
    start = time.monotonic()
    with open(folder / "lfdem.out", "w") as out:
        process = start_lfdem(binary, folder, out)
        while process.poll() is None:
            time.sleep(POLL_S)
            reached = reached_strain(folder)
            if reached > (clock[-1][0] if clock else 0.0):
                clock.append((reached, time.monotonic() - start))
    if process.returncode != 0:
        raise RuntimeError(f"LF_DEM failed ({process.returncode}); see {folder}/lfdem.out")
    return next(folder.glob("data_*.dat"))


def lfdem_steps_per_strain(data: Path, window) -> float:
    table = np.loadtxt(data, ndmin=2)
    columns = data_columns(data)
    strain, dt = table[:, columns["cumulated shear strain"]], table[:, columns["dt"]]
    inside = (strain >= window[0]) & (strain <= window[1])
    return float(np.mean(1.0 / dt[inside]))


def measure(
    binary: Path,
    point: str,
    window,
    keep: Path | None,
    contact_solve: str | None = None,
    n: int | None = None,
    newton_gain: float = NEWTON_GAIN,
) -> dict:
    """Both codes timed at ``point`` (with ``n`` particles instead of the point's N if given): the table's row."""
    return measure_engines(binary, point, window, keep, [contact_solve], n, newton_gain)[0]


def measure_engines(
    binary: Path,
    point: str,
    window,
    keep: Path | None,
    contact_solves: list[str | None],
    n: int | None = None,
    newton_gain: float = NEWTON_GAIN,
) -> list[dict]:
    """One LF_DEM run at ``point`` and, while it runs, the project's run with each of ``contact_solves``
    one after the other on the other core: a row per project engine, each against the same LF_DEM run."""
    studies = [point_study(point, solve, newton_gain) for solve in contact_solves]
    study = studies[0]
    folder = Path(tempfile.mkdtemp(prefix="peer_speed_", dir=keep))
    particles = {**study["particles"], "n": n or study["particles"]["n"]}
    shape = {key: particles[key] for key in ("split", "fraction_large", "d_small", "d_large")}
    packing = pack(folder / "packing", particles["n"], particles["phi"], SEED, **shape).data_file
    strain = window[1] + 0.01
    force_model = ForceModel.from_config(study)
    peer_clock, peer_outcome = [], {}
    (folder / "peer").mkdir()

    def peer():
        try:
            peer_outcome["data"] = run_peer(binary, packing, force_model, folder / "peer", strain, peer_clock)
        except Exception as err:  # raised after the project's run
            peer_outcome["error"] = err

    worker = threading.Thread(target=peer)
    worker.start()
    timed = []
    for index, engine_study in enumerate(studies):
        project_clock = []
        settings = ShearSettings.from_config(engine_study)
        run_startup(
            folder / ("project" if index == 0 else f"project{index + 1}"),
            packing,
            strain,
            force_model=ForceModel.from_config(engine_study),
            settings=settings,
            progress=lambda label, reached, total, elapsed, clock=project_clock: clock.append((reached, elapsed)),
            progress_interval=0.0,
        )
        timed.append((engine_study, settings, window_slope(*zip(*project_clock), window)))
    worker.join()
    if "error" in peer_outcome:
        raise peer_outcome["error"]
    peer_per_strain = window_slope(*zip(*peer_clock), window)
    peer_steps = lfdem_steps_per_strain(peer_outcome["data"], window)
    return [
        row(point, particles["n"], engine_study, settings, window, project_per_strain, peer_per_strain, peer_steps)
        for engine_study, settings, project_per_strain in timed
    ]


def row(point, n, study, settings, window, project_per_strain, peer_per_strain, peer_steps) -> dict:
    """The table's row of one project engine against the LF_DEM run."""
    project_steps = 1.0 / (settings.dt * settings.rate)
    return {
        "date": date.today().isoformat(),
        "machine": f"{platform.machine()} {os.cpu_count()} cores",
        "point": point,
        "n": n,
        "kn": study["forces"]["kn"],
        "engine": f"{study['run']['contact_solve']} dt {settings.dt:g}",
        "window": f"{window[0]:g}-{window[1]:g}",
        "project_s_per_strain": project_per_strain,
        "peer_s_per_strain": peer_per_strain,
        "ratio": peer_per_strain / project_per_strain,
        "project_steps_per_strain": project_steps,
        "peer_steps_per_strain": peer_steps,
        "project_ms_per_step": 1e3 * project_per_strain / project_steps,
        "peer_ms_per_step": 1e3 * peer_per_strain / peer_steps,
        "step_cost_ratio": (peer_per_strain / peer_steps) / (project_per_strain / project_steps),
    }


def report(table: pd.DataFrame) -> str:
    lines = [
        "| point | N | kn | project engine | window | project s/strain | LF_DEM s/strain | LF_DEM / project "
        "| steps/strain project | steps/strain LF_DEM | ms/step project | ms/step LF_DEM | per-step ratio |",
        "|:--|--:|--:|:--|:--|--:|--:|--:|--:|--:|--:|--:|--:|",
    ]
    for row in table.itertuples():
        lines.append(
            f"| {row.point} | {row.n} | {row.kn:.3g} | {row.engine} | {row.window} | {row.project_s_per_strain:.1f} "
            f"| {row.peer_s_per_strain:.0f} | {row.ratio:.0f} | {row.project_steps_per_strain:.0f} "
            f"| {row.peer_steps_per_strain:.0f} | {row.project_ms_per_step:.3g} | {row.peer_ms_per_step:.3g} "
            f"| {row.step_cost_ratio:.0f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="time both codes at one point and append the row")
    run.add_argument("--point", required=True, help="a point of config/campaign.yaml, e.g. phi0.45_mu0.5")
    run.add_argument(
        "--lfdem",
        type=Path,
        default=os.environ.get("LF_DEM"),
        help="the LF_DEM binary (default: $LF_DEM)",
    )
    run.add_argument("--window", type=float, nargs=2, default=WINDOW, help="strain window (default 1.5 2.5)")
    run.add_argument("--keep", type=Path, help="keep the runs' files under this folder")
    run.add_argument(
        "--contact-solve",
        choices=("lagged", "newton"),
        nargs="+",
        help="newton: the Newton solve at --newton-gain times the lagged step at a lagged point (default: the "
        "point's own); several: each timed in turn against one LF_DEM run",
    )
    run.add_argument("--newton-gain", type=float, default=NEWTON_GAIN, help="the Newton step over the lagged one")
    run.add_argument("--n", type=int, help="particles (default: the point's N)")
    sub.add_parser("report", help="print benchmarks/data/peer_speed.csv as a table")
    args = parser.parse_args(argv)
    if args.command == "report":
        print(report(pd.read_csv(TABLE)))
        return
    if args.lfdem is None or not args.lfdem.is_file():
        print(BUILD_HELP)
        sys.exit(1)
    if args.window[0] < 1.5:
        raise SystemExit(f"--window: starts at strain {args.window[0]:g}; steady state needs 1.5 or later")
    rows = measure_engines(
        args.lfdem.resolve(),
        args.point,
        tuple(args.window),
        args.keep,
        args.contact_solve or [None],
        args.n,
        args.newton_gain,
    )
    table = pd.concat([pd.read_csv(TABLE), pd.DataFrame(rows)]) if TABLE.is_file() else pd.DataFrame(rows)
    TABLE.parent.mkdir(parents=True, exist_ok=True)
    table.to_csv(TABLE, index=False)
    print(report(pd.DataFrame(rows)))


if __name__ == "__main__":
    main()

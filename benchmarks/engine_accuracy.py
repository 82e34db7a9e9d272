"""Accuracy of the implicit hydrodynamics against the explicit reference (BENCHMARKS.md, "Engine accuracy").

    .venv/bin/python benchmarks/engine_accuracy.py run --seed 2024 --integrator explicit --dt 2e-7
    .venv/bin/python benchmarks/engine_accuracy.py run --seed 2024 --integrator implicit --dt 1e-5
    .venv/bin/python benchmarks/engine_accuracy.py run --seed 2024 --integrator implicit --dt 2e-5 \
        --from-explicit-checkpoint
    .venv/bin/python benchmarks/engine_accuracy.py save      # analysed tables -> benchmarks/data/engine_accuracy
    .venv/bin/python benchmarks/engine_accuracy.py report [--seeds 2024 2025] [--root benchmarks/data/engine_accuracy]

`run`: one packing (N = 500, phi = 0.45, the given seed), a startup to strain 5 with its
checkpoint, then shear rotations by 90 and 180 degrees from that checkpoint for 1 strain each,
all at the project's default forces with the given integrator and time step, into
`results/engine_accuracy/seed<seed>/<integrator>_dt<dt>/`. Finished runs are reused. The LAMMPS
scripts and the plugin library are copied into the output folder before the first run and
used from there, so later edits of the sources cannot change a run that is under way.
Writes each run's fabric table (`fabric.csv`) next to its dump. With
`--from-explicit-checkpoint` only the two rotations run, from the explicit dt = 2e-7 startup's
checkpoint, into `<integrator>_dt<dt>_from_explicit/`: both integrators then start each
transient from the same state, a sharper comparison than across independent startups.

`save`: copies every finished run's fabric table and completion record (no trajectories) to
`benchmarks/data/engine_accuracy/`, so the report can be regenerated without simulating.

`report`: for every (integrator, dt) found, the steady fabric over strain 2-5 per packing
(correlation-aware standard errors, tables.steady_state) and its difference from the
explicit dt = 2e-7 run in units of the combined standard error; after each rotation,
<nn>'_12 and <nn>'_23 in strain bins against the explicit runs, with the seed-to-seed
spread of the explicit runs (per bin, and pooled: the rms over the bins, as two packings give
a poor per-bin estimate); and the wall time of every run in core-s per particle per unit strain
(on a shared machine: see benchmarks/bench_engine.py for the speed).
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.analysis.tables import run_fabric_table, steady_state
from suspension_fabric.io.resources import LAMMPS_SCRIPTS_DIR
from suspension_fabric.simulation.lammps import (
    ForceModel,
    ShearSettings,
    is_complete,
    pack,
    plugin,
    run_rotation,
    run_startup,
    runner,
)

N_PARTICLES = 500
PHI = 0.45
STARTUP_STRAIN = 5.0
ROTATION_STRAIN = 1.0
ANGLES = (90.0, 180.0)
STEADY_WINDOW = (2.0, 5.0)
ROOT = Path("results/engine_accuracy")
COLUMNS = ("n11", "n22", "n33", "n12", "n13", "n23", "Z")
REFERENCE = ("explicit", 2e-7)
ROTATION_BINS = [(0.0, 0.05), (0.05, 0.1), (0.1, 0.2), (0.2, 0.3), (0.3, 0.5), (0.5, 0.75), (0.75, 1.0)]


def run_label(integrator: str, dt: float, from_explicit: bool = False) -> str:
    return f"{integrator}_dt{dt:g}" + ("_from_explicit" if from_explicit else "")


def frozen_inputs(out: Path) -> tuple[Path, Path]:
    """Copies of the LAMMPS scripts and the plugin library in ``out`` (made once)."""
    scripts, library = out / "inputs" / "lammps", out / "inputs" / "libsuspension_fabric_lammps.so"
    if not library.is_file():
        scripts.parent.mkdir(parents=True, exist_ok=True)
        shutil.copytree(LAMMPS_SCRIPTS_DIR, scripts, dirs_exist_ok=True)
        shutil.copy2(plugin.plugin_path(), library)
    missing = sorted(s.name for s in LAMMPS_SCRIPTS_DIR.glob("*.lmp") if not (scripts / s.name).is_file())
    if missing:  # frozen for an older runner, which did not use these
        raise SystemExit(
            f"{scripts} lacks {', '.join(missing)} that the current runner uses; "
            f"remove {scripts.parent} to freeze the current scripts and plugin"
        )
    return scripts, library


def use_frozen_inputs(scripts: Path) -> None:
    """Make the runner use the frozen copies: its scripts folder (the runner reads
    LAMMPS_SCRIPTS_DIR at each run), and the frozen library as it is: the staleness check
    against the current plugin sources is off, since ignoring later edits is the point."""
    runner.LAMMPS_SCRIPTS_DIR = scripts.resolve()
    plugin.check_not_stale = lambda library: None


def write_fabric(run_dir: Path, seed: int) -> None:
    """The run's fabric table (time step, first step and angle from its completion marker)."""
    target = run_dir / "fabric.csv"
    if not target.is_file():
        run_fabric_table(run_dir / runner.DUMP_FILE, run_dir / runner.COMPLETION_MARKER, seed=seed).to_csv(
            target, index=False
        )


def run(seed: int, integrator: str, dt: float, from_explicit: bool) -> None:
    out = ROOT / f"seed{seed}" / run_label(integrator, dt, from_explicit)
    settings = ShearSettings(dt=dt, dump_strain=0.01)  # a frame every 0.01 strain, as in benchmarks/data

    def frozen_model() -> ForceModel:
        """The force model on the frozen inputs, set up only when a simulation is due (so
        re-analysing finished runs works whatever runner the frozen copy was made for)."""
        scripts, library = frozen_inputs(out)
        use_frozen_inputs(scripts)
        return ForceModel(plugin=library.resolve(), integrator=integrator)

    if from_explicit:
        startup = ROOT / f"seed{seed}" / run_label(*REFERENCE) / "startup"
    else:
        packing = ROOT / f"seed{seed}" / "packing"
        if not is_complete(packing):
            frozen_model()
            pack(packing, N_PARTICLES, phi=PHI, seed=seed)
        startup = out / "startup"
        if not is_complete(startup):
            run_startup(
                startup,
                packing / runner.PACK_DATA,
                STARTUP_STRAIN,
                force_model=frozen_model(),
                settings=settings,
                progress_interval=120,
            )
        write_fabric(startup, seed)
    for theta in ANGLES:
        rotation = out / f"rotate_{theta:g}"
        if not is_complete(rotation):
            run_rotation(
                rotation,
                startup / runner.CHECKPOINT_FILE,
                theta,
                ROTATION_STRAIN,
                force_model=frozen_model(),
                settings=settings,
                progress_interval=120,
            )
        write_fabric(rotation, seed)


def save(destination: Path = Path("benchmarks/data/engine_accuracy")) -> None:
    for table in sorted(ROOT.glob("seed*/*/*/fabric.csv")):
        target = destination / table.parent.relative_to(ROOT)
        target.mkdir(parents=True, exist_ok=True)
        shutil.copy2(table, target / "fabric.csv")
        shutil.copy2(table.parent / runner.COMPLETION_MARKER, target / runner.COMPLETION_MARKER)
        print(target)


def cost(run_dir: Path) -> float:
    marker = json.loads((run_dir / runner.COMPLETION_MARKER).read_text())
    return marker["wall_time_s"] / (N_PARTICLES * marker["results"]["strain"])


def report(seeds: list[int], root: Path) -> None:
    runs = sorted(
        {
            p.name
            for seed in seeds
            for p in (root / f"seed{seed}").glob("*_dt*")
            if (p / "startup" / "fabric.csv").is_file()
        }
    )
    rotation_runs = sorted(
        {
            p.name
            for seed in seeds
            for p in (root / f"seed{seed}").glob("*_dt*")
            if (p / f"rotate_{ANGLES[0]:g}" / "fabric.csv").is_file()
        }
    )
    reference = run_label(*REFERENCE)
    print(
        f"N = {N_PARTICLES}, phi = {PHI}, default forces; steady window strain "
        f"{STEADY_WINDOW[0]:g}-{STEADY_WINDOW[1]:g}; packings {', '.join(map(str, seeds))}\n"
    )
    print("Steady fabric (mean +- correlation-aware standard error); z = (run - explicit) / combined sem\n")
    print("| packing | run | " + " | ".join(COLUMNS) + " | max abs z | wall core-s/particle/strain |")
    print("|" + "---|" * (len(COLUMNS) + 4))
    steady = {}
    for seed in seeds:
        for label in runs:
            path = root / f"seed{seed}" / label / "startup" / "fabric.csv"
            if path.is_file():
                steady[seed, label] = steady_state(pd.read_csv(path), *STEADY_WINDOW).set_index("quantity")
        for label in runs:
            if (seed, label) not in steady:
                continue
            table = steady[seed, label]
            cells, worst = [], 0.0
            for name in COLUMNS:
                mean, sem = table.loc[name, "mean"], table.loc[name, "sem"]
                text = f"{mean:.4f} +- {sem:.4f}"
                if label != reference and (seed, reference) in steady:
                    ref = steady[seed, reference].loc[name]
                    z = (mean - ref["mean"]) / np.hypot(sem, ref["sem"])
                    worst = max(worst, abs(z))
                    text += f" (z {z:+.1f})"
                cells.append(text)
            z_text = "-" if label == reference else f"{worst:.1f}"
            print(
                f"| {seed} | {label} | "
                + " | ".join(cells)
                + f" | {z_text} | {cost(root / f'seed{seed}' / label / 'startup'):.3f} |"
            )

    for theta in ANGLES:
        for component in ("n12", "n23"):
            print(
                f"\nAfter the {theta:g} degree rotation: <nn>'_{component[1:]} (rotated frame) per strain bin; "
                "spread = standard deviation of the explicit runs over packings\n"
            )
            header = " | ".join(f"{lo:g}-{hi:g}" for lo, hi in ROTATION_BINS)
            print(f"| packing | run | {header} |")
            print("|" + "---|" * (len(ROTATION_BINS) + 2))
            bins = {}
            for seed in seeds:
                for label in rotation_runs:
                    path = root / f"seed{seed}" / label / f"rotate_{theta:g}" / "fabric.csv"
                    if not path.is_file():
                        continue
                    table = pd.read_csv(path)
                    means = [
                        table.loc[(table.strain >= lo) & (table.strain < hi + 1e-9), component].mean()
                        for lo, hi in ROTATION_BINS
                    ]
                    bins.setdefault(label, []).append(means)
                    print(f"| {seed} | {label} | " + " | ".join(f"{m:.4f}" for m in means) + " |")
            reference_bins = np.array(bins.get(reference, []))
            if len(reference_bins) < 2:
                continue
            spread = np.std(reference_bins, axis=0, ddof=1)
            # two packings give a poor per-bin standard deviation (it can vanish by chance):
            # judge against the pooled one, the rms over the bins
            pooled = float(np.sqrt(np.mean(spread**2)))
            print("| spread | explicit | " + " | ".join(f"{v:.4f}" for v in spread) + " |")
            ratios = []
            for label, values in bins.items():
                if label == reference or len(values) != len(reference_bins):
                    continue
                difference = np.mean(values, axis=0) - reference_bins.mean(axis=0)
                print(f"| mean - explicit | {label} | " + " | ".join(f"{v:+.4f}" for v in difference) + " |")
                ratios.append(f"{label} {np.max(np.abs(difference)) / pooled:.2f}")
            print(
                f"\npooled seed-to-seed spread of the explicit runs (rms over bins): {pooled:.4f}; "
                "largest |seed mean - explicit seed mean| over the bins / pooled spread: " + ", ".join(ratios)
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run_parser = sub.add_parser("run")
    run_parser.add_argument("--seed", type=int, required=True)
    run_parser.add_argument("--integrator", choices=("explicit", "implicit"), required=True)
    run_parser.add_argument("--dt", type=float, required=True)
    run_parser.add_argument("--from-explicit-checkpoint", action="store_true")
    sub.add_parser("save")
    report_parser = sub.add_parser("report")
    report_parser.add_argument("--seeds", type=int, nargs="+", default=[2024, 2025])
    report_parser.add_argument("--root", type=Path, default=ROOT)
    args = parser.parse_args()
    if args.command == "run":
        run(args.seed, args.integrator, args.dt, args.from_explicit_checkpoint)
    elif args.command == "save":
        save()
    else:
        report(args.seeds, args.root)


if __name__ == "__main__":
    main()

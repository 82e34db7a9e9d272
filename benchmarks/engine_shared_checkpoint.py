"""The default engine's step and tolerance against a finer integration from shared checkpoints
(BENCHMARKS.md, "Engine speed II: transients from a shared checkpoint").

    .venv/bin/python benchmarks/engine_shared_checkpoint.py run results/default      # ~5 min on 2 idle cores
    .venv/bin/python benchmarks/engine_shared_checkpoint.py report results/default

`run`: from each seed's startup checkpoint of a finished study run with the default engine
(kn = 1.25e8, springs implicit, dt = 1e-4, solver_tol 1e-3), the 90 and 180 degree rotations
again for ROTATION_STRAIN with the same contact model at dt = FINE_DT (5x smaller) and
solver_tol FINE_TOL (100x tighter), into <study>/fine/seed<s>/rotation_theta<a>/, with their
fabric and stress tables made by the workflow's own functions (tables.run_fabric_table,
stress.run_stress_table). Two seed processes run side by side.

`report`: per angle and quantity (<nn>'_12, <nn>'_23, sigma'_12, sigma'_23 in the rotated
frame), the strain-binned seed means of the study's own rotation and of the fine one, and the
paired statistic that decides: per seed, the difference (default - fine) of the quantity's
integral over the strain of the fine run, with its 95% t-interval over the seeds (the seeds
are the independent units; the shared checkpoint makes the pair's startup noise cancel).
"""

from __future__ import annotations

import argparse
import json
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd
from engine_ladder import bin_means  # same directory: the ladder's strain binning
from scipy import stats

from suspension_fabric.analysis import tables
from suspension_fabric.analysis.stress import STRESS_FLOAT_FORMAT, run_stress_table
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, run_rotation

ANGLES = (90, 180)
ROTATION_STRAIN = 1.0
FINE_DT = 2.0e-5  # divides the default startup's 50000 steps at dt = 1e-4 on every output grid
FINE_TOL = 1.0e-5
BINS = [(0.0, 0.05), (0.05, 0.1), (0.1, 0.2), (0.2, 0.3), (0.3, 0.5), (0.5, 1.0)]
QUANTITIES = (
    ("fabric", "n12", "<nn>'_12"),
    ("fabric", "n23", "<nn>'_23"),
    ("stress", "total_12", "sigma'_12"),
    ("stress", "total_23", "sigma'_23"),
)


def fine_rotation(study: Path, seed_folder: str, angle: int) -> Path:
    config = json.loads((study / seed_folder / "startup" / "run_complete.json").read_text())["variables"]
    out = study / "fine" / seed_folder / f"rotation_theta{angle}"
    model = ForceModel(kn=float(config["kn"]), solver_tol=FINE_TOL)
    settings = ShearSettings(
        dt=FINE_DT,
        dump_strain=float(config["dump_strain"]),
        table_strain=float(config["table_strain"]),
        restart_strain=ROTATION_STRAIN,
    )
    run = run_rotation(
        out,
        study / seed_folder / "startup" / "checkpoint.rst",
        float(angle),
        ROTATION_STRAIN,
        force_model=model,
        settings=settings,
        progress=None,
    )
    seed = int(seed_folder.removeprefix("seed"))
    fabric = tables.run_fabric_table(run.dump_file, out / "run_complete.json", seed=seed)
    tables.write_fabric_table(fabric, out / "fabric.csv")
    stress = run_stress_table(run.table_file, out / "run_complete.json", out / "fabric.csv")
    stress.to_csv(out / "stress.csv", index=False, float_format=STRESS_FLOAT_FORMAT)
    return out


def run(study: Path) -> None:
    seeds = sorted(p.name for p in study.glob("seed*") if (p / "startup" / "checkpoint.rst").is_file())
    if not seeds:
        raise FileNotFoundError(f"{study}: no seed*/startup/checkpoint.rst (run the study first)")
    with ProcessPoolExecutor(max_workers=2) as pool:
        for out in pool.map(
            fine_rotation,
            [study] * len(seeds) * len(ANGLES),
            [s for s in seeds for _ in ANGLES],
            [a for _ in seeds for a in ANGLES],
        ):
            print(out, flush=True)


def per_seed(study: Path, run_name: str, kind: str, column: str, fine: bool) -> dict[int, pd.DataFrame]:
    root = study / "fine" if fine else study
    result = {}
    for folder in sorted(root.glob("seed*")):
        table = pd.read_csv(folder / run_name / f"{kind}.csv")
        result[int(folder.name.removeprefix("seed"))] = table[table["strain"] <= ROTATION_STRAIN + 1e-9][
            ["strain", column]
        ]
    return result


def integral(table: pd.DataFrame, column: str) -> float:
    strain, values = table["strain"].to_numpy(), table[column].to_numpy(dtype=float)
    return float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(strain)))


def report(study: Path) -> None:
    fine_record = json.loads(next((study / "fine").glob("seed*/rotation_theta*/run_complete.json")).read_text())
    own_record = json.loads(next(study.glob("seed*/rotation_theta90/run_complete.json")).read_text())
    own, fine = own_record["variables"], fine_record["variables"]
    print(
        f"default: kn {float(own['kn']):g}, springs {own['contact_springs']}, {own['preconditioner']}, dt {own['dt']}, "
        f"tol {own['solver_tol']}; fine: dt {fine['dt']}, tol {fine['solver_tol']}; same checkpoints, "
        f"strain 0-{ROTATION_STRAIN:g} after the rotation\n"
    )
    bins = " | ".join(f"{lo:g}-{hi:g}" for lo, hi in BINS)
    for angle in ANGLES:
        for kind, column, name in QUANTITIES:
            a = per_seed(study, f"rotation_theta{angle}", kind, column, fine=False)
            b = per_seed(study, f"rotation_theta{angle}", kind, column, fine=True)
            seeds = sorted(set(a) & set(b))
            diffs = np.array([integral(a[s], column) - integral(b[s], column) for s in seeds])
            scale = np.mean([abs(integral(b[s], column)) for s in seeds])
            half = stats.t.ppf(0.975, len(seeds) - 1) * diffs.std(ddof=1) / np.sqrt(len(seeds))
            print(
                f"{angle} degrees, {name}: integral over strain 0-{ROTATION_STRAIN:g}, default - fine, per seed "
                f"{np.array2string(diffs, precision=4)}; mean {diffs.mean():+.4f}, 95% t-interval "
                f"[{diffs.mean() - half:+.4f}, {diffs.mean() + half:+.4f}] "
                f"(fine integral, seed mean of |.|: {scale:.4f})\n"
            )
            print(f"| run | {bins} |")
            print("|---|" + "---|" * len(BINS))
            for label, runs in (("default", a), ("fine", b)):
                means = np.mean(
                    [
                        bin_means(runs[s]["strain"].to_numpy(), runs[s][column].to_numpy(dtype=float), BINS)
                        for s in seeds
                    ],
                    axis=0,
                )
                print(f"| {label} | {' | '.join(f'{v:.4f}' for v in means)} |")
            print()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("phase", choices=("run", "report"))
    parser.add_argument("study", type=Path)
    args = parser.parse_args()
    run(args.study) if args.phase == "run" else report(args.study)


if __name__ == "__main__":
    main()

"""Accuracy of the engine's time-step ladder against the production engine (BENCHMARKS.md,
"Engine speed II: accuracy").

    .venv/bin/snakemake --cores 2 --configfile benchmarks/configs/engine_springs_kn1.25e8_dt1e-4.yaml
    .venv/bin/python benchmarks/engine_ladder.py save results/engine_springs_kn1.25e8_dt1e-4
    .venv/bin/python benchmarks/engine_ladder.py report [--reference data/default] \
        [--explicit benchmarks/data/engine_accuracy] benchmarks/data/engine_ladder/engine_springs_*

`save` copies what the report reads (the startup and the 90 and 180 degree rotations: fabric
and stress tables and the run records, no trajectories) to benchmarks/data/engine_ladder/<study>/.

Each study (a dataset folder, or results/<study>) repeats a committed dataset made with the
explicit-spring engine (contact springs explicit, block Jacobi, kn = 1.25e9, dt = 2e-5) with
another engine setting, from the same packings with independent trajectories: by default the
N = 500 study of data/default (seeds 1-3, rotations every 30 degrees, 2 strain after each),
or with --reference data/reference_v1 the N = 1000 one (seeds 1-4, the explicit-spring engine).

Steady state over strain 2-5 of the startup: per quantity the seed mean with its
correlation-aware standard error (tables.steady_state), and z = (study - reference) /
sqrt(sem_study^2 + sem_reference^2); the fabric also against the explicit dt = 2e-7 runs of
`benchmarks/data/engine_accuracy` (packings 2024, 2025). Quantities: the fabric <nn>_ij and Z;
the relative viscosity eta_r with its contact and lubrication parts, N1, N2 and Pi (units
eta_f gammadot, stress.csv).

After the 90 and 180 degree rotations: the seed means of <nn>'_12, <nn>'_23, sigma'_12 and
sigma'_23 (rotated frame) in strain bins, their difference from the reference, and that
difference over the seed-to-seed standard deviation (the criterion: within the seed-to-seed
spread, |ratio| < 1). Three seeds estimate a per-bin standard deviation poorly (two degrees
of freedom), so the spread is pooled: the rms over the bins of both studies' per-bin
standard deviations.
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

from suspension_fabric.analysis.tables import steady_state

STEADY_WINDOW = (2.0, 5.0)
FABRIC = ("n11", "n22", "n33", "n12", "n13", "n23", "Z")
STRESS = ("eta_r", "contact_12", "lubrication_12", "N1", "N2", "Pi")
ANGLES = (90, 180)
BINS = [(0.0, 0.05), (0.05, 0.1), (0.1, 0.2), (0.2, 0.3), (0.3, 0.5), (0.5, 1.0), (1.0, 2.0)]
TRANSIENTS = (("fabric", "n12"), ("fabric", "n23"), ("stress", "total_12"), ("stress", "total_23"))


def seed_folders(study: Path) -> list[Path]:
    folders = sorted(p for p in study.glob("seed*") if p.is_dir())
    if not folders:
        raise FileNotFoundError(f"{study}: no seed*/ folders")
    return folders


def run_table(study: Path, run: str, kind: str) -> pd.DataFrame:
    """The per-seed tables of one run (startup or rotation_theta<angle>) stacked."""
    tables = []
    for folder in seed_folders(study):
        path = folder / run / f"{kind}.csv"
        if not path.is_file():
            raise FileNotFoundError(f"{path} missing: finish the study (or export it) first")
        tables.append(pd.read_csv(path))
    return pd.concat(tables, ignore_index=True)


def engine_label(study: Path) -> str:
    """The engine settings a study was run with, from its dataset record or a run record."""
    record = study / "dataset.json"
    if record.is_file():
        config = json.loads(record.read_text())["config"]
        run, kn = config["run"], config["forces"]["kn"]
    else:
        startup = seed_folders(study)[0] / "startup"
        marker = startup / ("run.json" if (startup / "run.json").is_file() else "run_complete.json")
        run = json.loads(marker.read_text())["variables"]
        kn = run["kn"]
    springs = run.get("contact_springs", "explicit")
    solve = run.get("contact_solve", "lagged")
    preconditioner = run.get("preconditioner", "jacobi")
    tolerance = float(run.get("solver_tol", 1e-5))
    springs += ", newton solve" if solve == "newton" else ""
    label = f"kn {float(kn):.3g}, springs {springs}, {preconditioner}, dt {float(run['dt']):g}"
    return label + (f", tol {tolerance:g}" if tolerance != 1e-5 else "")


def particle_count(study: Path) -> int:
    """N of a study, from its dataset record or its fabric table."""
    record = study / "dataset.json"
    if record.is_file():
        return int(json.loads(record.read_text())["config"]["particles"]["n"])
    return int(run_table(study, "startup", "fabric")["N"].iloc[0])


def save(study: Path, root: Path = Path("benchmarks/data/engine_ladder")) -> Path:
    """Copies the tables and run records the report reads into root/<study name>."""
    target = root / study.name
    for folder in seed_folders(study):
        for run in ("startup", *(f"rotation_theta{angle}" for angle in ANGLES)):
            destination = target / folder.name / run
            destination.mkdir(parents=True, exist_ok=True)
            for name in ("fabric.csv", "stress.csv"):
                shutil.copyfile(folder / run / name, destination / name)
            shutil.copyfile(folder / run / "run_complete.json", destination / "run.json")
    return target


def steady(study: Path, kind: str, columns) -> pd.DataFrame:
    table = run_table(study, "startup", kind)
    return steady_state(table, *STEADY_WINDOW, value_columns=columns).set_index("quantity")


def steady_rows(name: str, study: pd.DataFrame, reference: pd.DataFrame | None, columns) -> str:
    cells = []
    largest = 0.0
    for quantity in columns:
        mean, sem = study.loc[quantity, "mean"], study.loc[quantity, "sem"]
        cell = f"{mean:.4f} +- {sem:.4f}"
        if reference is not None:
            z = (mean - reference.loc[quantity, "mean"]) / np.hypot(sem, reference.loc[quantity, "sem"])
            largest = max(largest, abs(z))
            cell += f" (z {z:+.1f})"
        cells.append(cell)
    tail = f"{largest:.1f}" if reference is not None else "-"
    return f"| {name} | {' | '.join(cells)} | {tail} |"


def bin_means(strain: np.ndarray, values: np.ndarray, bins=BINS) -> list[float]:
    """Mean of `values` in each strain bin [lo, hi); the last bin includes its upper edge (the
    run's last frame)."""
    last = bins[-1][1]
    return [values[(strain >= lo) & ((strain < hi) | ((hi == last) & (strain <= hi)))].mean() for lo, hi in bins]


def binned_seed_means(study: Path, angle: int, kind: str, column: str) -> np.ndarray:
    """Per seed (rows) and strain bin (columns) the mean of `column` after the rotation."""
    table = run_table(study, f"rotation_theta{angle}", kind)
    return np.array(
        [
            bin_means(series["strain"].to_numpy(), series[column].to_numpy(dtype=float))
            for _, series in table.groupby("seed", sort=True)
        ]
    )


def null_threshold(seeds: int = 3, bins: int = len(BINS), level: float = 0.95, draws: int = 20000) -> float:
    """The `level` quantile of the max-over-bins ratio for two studies of the same engine:
    independent normal bins, `seeds` seeds each, the spread pooled as in the report (Monte
    Carlo, fixed seed). Real bins are correlated along strain, which lowers the quantile."""
    rng = np.random.default_rng(0)
    a = rng.normal(size=(draws, seeds, bins))
    b = rng.normal(size=(draws, seeds, bins))
    spread = np.sqrt(np.mean(np.concatenate([a.std(axis=1, ddof=1), b.std(axis=1, ddof=1)], axis=1) ** 2, axis=1))
    ratio = np.abs(a.mean(axis=1) - b.mean(axis=1)).max(axis=1) / spread
    return float(np.quantile(ratio, level))


def per_bin_t(study: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Two-sample t per strain bin (seeds as the units, the variance pooled per bin): unlike the
    ratio to a spread pooled over the bins, it does not flag a bin whose own seed spread is large."""
    n, m = len(study), len(reference)
    variance = ((n - 1) * study.var(axis=0, ddof=1) + (m - 1) * reference.var(axis=0, ddof=1)) / (n + m - 2)
    return (study.mean(axis=0) - reference.mean(axis=0)) / np.sqrt(variance * (1.0 / n + 1.0 / m))


def per_bin_t_threshold(seeds: int, bins: int = len(BINS), level: float = 0.95) -> float:
    """The `level` quantile of the max over independent bins of |t| with 2 (seeds - 1) degrees
    of freedom (Sidak)."""
    single = 1.0 - level ** (1.0 / bins)
    return float(stats.t.ppf(1.0 - single / 2.0, 2 * (seeds - 1)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("phase", choices=("save", "report"))
    parser.add_argument("studies", nargs="+", type=Path)
    parser.add_argument("--reference", type=Path, default=Path("data/default"))
    parser.add_argument("--explicit", type=Path, default=Path("benchmarks/data/engine_accuracy"))
    args = parser.parse_args()
    if args.phase == "save":
        for study in args.studies:
            print(save(study))
        return

    labels = {args.reference: f"reference: {engine_label(args.reference)}"}
    labels.update({study: engine_label(study) for study in args.studies})
    seeds = len(seed_folders(args.reference))
    print(
        f"N = {particle_count(args.reference)}, phi = 0.45, {seeds} seeds; steady window strain "
        f"{STEADY_WINDOW[0]:g}-{STEADY_WINDOW[1]:g}; z = (study - reference) / combined sem\n"
    )

    print("Steady fabric (seed mean +- correlation-aware sem)\n")
    print(f"| engine | {' | '.join(FABRIC)} | max abs z |")
    print("|---|" + "---|" * (len(FABRIC) + 1))
    reference = steady(args.reference, "fabric", FABRIC)
    explicit = None
    explicit_runs = sorted(args.explicit.glob("seed*/explicit_dt2e-07/startup/fabric.csv"))
    if explicit_runs:
        explicit = steady_state(
            pd.concat([pd.read_csv(p) for p in explicit_runs], ignore_index=True), *STEADY_WINDOW, value_columns=FABRIC
        ).set_index("quantity")
        print(steady_rows(f"explicit dt 2e-7 (packings 2024, 2025; {args.explicit})", explicit, None, FABRIC))
    print(steady_rows(labels[args.reference], reference, None, FABRIC))
    for study in args.studies:
        print(steady_rows(labels[study], steady(study, "fabric", FABRIC), reference, FABRIC))
    if explicit is not None:
        print("\nthe same against the explicit dt = 2e-7 runs:\n")
        print(f"| engine | {' | '.join(FABRIC)} | max abs z |")
        print("|---|" + "---|" * (len(FABRIC) + 1))
        for study in (args.reference, *args.studies):
            print(steady_rows(labels[study], steady(study, "fabric", FABRIC), explicit, FABRIC))

    print("\nSteady stress (units eta_f gammadot; seed mean +- correlation-aware sem)\n")
    print(f"| engine | {' | '.join(STRESS)} | max abs z |")
    print("|---|" + "---|" * (len(STRESS) + 1))
    reference_stress = steady(args.reference, "stress", STRESS)
    print(steady_rows(labels[args.reference], reference_stress, None, STRESS))
    for study in args.studies:
        print(steady_rows(labels[study], steady(study, "stress", STRESS), reference_stress, STRESS))

    print(
        f"\nTransients: for two studies of the same engine ({seeds} seeds each, {len(BINS)} independent bins) "
        f"the max ratio exceeds {null_threshold(seeds):.2f} with 5% probability (engine_ladder.null_threshold), "
        f"the max per-bin |t| {per_bin_t_threshold(seeds):.2f} (engine_ladder.per_bin_t_threshold)."
    )
    bins = " | ".join(f"{lo:g}-{hi:g}" for lo, hi in BINS)
    for angle in ANGLES:
        for kind, column in TRANSIENTS:
            name = {"n12": "<nn>'_12", "n23": "<nn>'_23", "total_12": "sigma'_12", "total_23": "sigma'_23"}[column]
            print(
                f"\nAfter the {angle} degree rotation: {name} (seed mean per strain bin; ratio = "
                "(study - reference) / seed-to-seed sd pooled over the bins and both studies)\n"
            )
            print(f"| engine | {bins} | max abs ratio |")
            print("|---|" + "---|" * (len(BINS) + 1))
            ref = binned_seed_means(args.reference, angle, kind, column)
            spread = ref.std(axis=0, ddof=1)
            print(f"| {labels[args.reference]} | {' | '.join(f'{v:.4f}' for v in ref.mean(axis=0))} | - |")
            print(f"| seed-to-seed sd (reference) | {' | '.join(f'{v:.4f}' for v in spread)} | - |")
            for study in args.studies:
                values = binned_seed_means(study, angle, kind, column)
                pooled = np.sqrt(np.mean(np.concatenate([spread, values.std(axis=0, ddof=1)]) ** 2))
                ratio = (values.mean(axis=0) - ref.mean(axis=0)) / pooled
                print(
                    f"| {labels[study]} | {' | '.join(f'{v:.4f}' for v in values.mean(axis=0))} | "
                    f"{np.abs(ratio).max():.2f} (pooled sd {pooled:.4f}); per-bin t "
                    f"{np.abs(per_bin_t(values, ref)).max():.2f} |"
                )


if __name__ == "__main__":
    main()

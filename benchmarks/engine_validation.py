"""A numerical change against a committed dataset of the same state point (BENCHMARKS.md, "Engine III").

    .venv/bin/python benchmarks/engine_validation.py results/engine_newton_phi0.53_mu0.5 \
        data/campaign/phi0.53_mu0.5 [--save benchmarks/data/engine_validation]

Both studies hold the same seeds' packings, sheared with independent trajectories. Steady state
over strain 2-5 of the startup: per quantity (the fabric <nn>_ij and Z; eta_r with its contact
and lubrication parts, N1, N2, Pi in units of eta_f gammadot) the seed mean with its
correlation-aware standard error (tables.steady_state), and z = (study - dataset) /
sqrt(sem_study^2 + sem_dataset^2). After every rotation of both: <nn>'_12, <nn>'_23, sigma'_12 and
sigma'_23 in the strain bins of engine_ladder.BINS, per bin the seed mean, its standard error
over the seeds (the seeds are the independent units) and z as above. The acceptance criterion,
named before looking: |z| <= 2 (two combined standard errors) for every steady quantity and
every transient bin; with many bins about 5% exceed 2 by chance alone, so the report also gives
how many do and the largest |z| against the Sidak bound for the number of bins compared.
``--save`` copies the tables the report reads (no trajectories) for the record.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import numpy as np
from engine_ladder import BINS, FABRIC, STEADY_WINDOW, STRESS, binned_seed_means, engine_label, seed_folders, steady
from scipy import stats

TRANSIENTS = (("fabric", "n12", "<nn>'_12"), ("fabric", "n23", "<nn>'_23"), ("stress", "total_12", "sigma'_12"))
TRANSIENTS += (("stress", "total_23", "sigma'_23"),)
LEVEL = 2.0


def rotation_angles(study: Path) -> list[int]:
    first = seed_folders(study)[0]
    return sorted(int(p.name.removeprefix("rotation_theta")) for p in first.glob("rotation_theta*") if p.is_dir())


def save(study: Path, root: Path) -> Path:
    """Copies the fabric and stress tables and the run records of every run to root/<study name>."""
    target = root / study.name
    for folder in seed_folders(study):
        for run in sorted(p for p in folder.iterdir() if p.is_dir() and (p / "fabric.csv").is_file()):
            destination = target / folder.name / run.name
            destination.mkdir(parents=True, exist_ok=True)
            for name in ("fabric.csv", "stress.csv"):
                shutil.copyfile(run / name, destination / name)
            marker = run / "run_complete.json"
            shutil.copyfile(marker if marker.is_file() else run / "run.json", destination / "run.json")
    return target


def steady_table(study: Path, dataset: Path) -> tuple[str, list[float]]:
    rows, zs = [], []
    rows.append("| quantity | study | dataset | z |")
    rows.append("|---|---|---|---|")
    for kind, columns in (("fabric", FABRIC), ("stress", STRESS)):
        a, b = steady(study, kind, columns), steady(dataset, kind, columns)
        for quantity in columns:
            z = (a.loc[quantity, "mean"] - b.loc[quantity, "mean"]) / np.hypot(
                a.loc[quantity, "sem"], b.loc[quantity, "sem"]
            )
            zs.append(z)
            rows.append(
                f"| {quantity} | {a.loc[quantity, 'mean']:.4f} +- {a.loc[quantity, 'sem']:.4f} | "
                f"{b.loc[quantity, 'mean']:.4f} +- {b.loc[quantity, 'sem']:.4f} | {z:+.2f} |"
            )
    return "\n".join(rows), zs


def transient_z(study: Path, dataset: Path, angle: int, kind: str, column: str) -> np.ndarray:
    a = binned_seed_means(study, angle, kind, column)
    b = binned_seed_means(dataset, angle, kind, column)
    error = np.sqrt(a.var(axis=0, ddof=1) / len(a) + b.var(axis=0, ddof=1) / len(b))
    return (a.mean(axis=0) - b.mean(axis=0)) / error


def transient_table(study: Path, dataset: Path) -> tuple[str, list[float]]:
    angles = [angle for angle in rotation_angles(study) if angle in rotation_angles(dataset)]
    bins = " | ".join(f"{lo:g}-{hi:g}" for lo, hi in BINS)
    rows = [f"| angle | quantity | {bins} | max abs z |", "|---|---|" + "---|" * (len(BINS) + 1)]
    zs = []
    for angle in angles:
        for kind, column, name in TRANSIENTS:
            z = transient_z(study, dataset, angle, kind, column)
            zs.extend(z)
            rows.append(f"| {angle} | {name} | {' | '.join(f'{v:+.2f}' for v in z)} | {np.abs(z).max():.2f} |")
    return "\n".join(rows), zs


def sidak_bound(count: int, level: float = 0.95) -> float:
    """|z| that the largest of `count` independent standard normals exceeds with 1 - level."""
    return float(stats.norm.ppf(1.0 - (1.0 - level ** (1.0 / count)) / 2.0))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("study", type=Path)
    parser.add_argument("dataset", type=Path)
    parser.add_argument("--save", type=Path, help="copy the study's tables here first")
    args = parser.parse_args()
    study = save(args.study, args.save) if args.save else args.study
    print(f"study: {engine_label(study)} ({len(seed_folders(study))} seeds)")
    print(f"dataset: {engine_label(args.dataset)} ({len(seed_folders(args.dataset))} seeds)")
    print(f"steady window strain {STEADY_WINDOW[0]:g}-{STEADY_WINDOW[1]:g}; z = difference / combined standard error\n")
    text, steady_z = steady_table(study, args.dataset)
    print(text)
    print("\nAfter each rotation: z per strain bin\n")
    text, transient = transient_table(study, args.dataset)
    print(text)
    for name, zs in (("steady quantities", steady_z), ("transient bins", transient)):
        zs = np.abs(np.asarray(zs))
        print(
            f"\n{name}: {len(zs)}, {int((zs > LEVEL).sum())} with |z| > {LEVEL:g} "
            f"({0.0455 * len(zs):.1f} expected by chance), largest {zs.max():.2f} "
            f"(Sidak 95% bound for {len(zs)}: {sidak_bound(len(zs)):.2f})"
        )


if __name__ == "__main__":
    main()

"""A numerical change against a committed dataset of the same state point (BENCHMARKS.md, "Engine III").

    .venv/bin/python benchmarks/engine_validation.py --study results/engine_newton_phi0.53_mu0.5 \
        --dataset data/campaign/phi0.53_mu0.5 [--save benchmarks/data/engine_validation] [--paired]

``--study`` and ``--dataset`` each take one or more folders of seeds (their seeds pooled; a
folder with startups only adds to the steady state). Both hold the same seeds' packings where
they overlap, sheared with independent trajectories, so the seeds are the independent units.
Steady state over strain 2-5 of the startup, per quantity (the fabric <nn>_ij and Z; eta_r with
its contact and lubrication parts, N1, N2, Pi in units of eta_f gammadot): each seed's mean over
the window, the difference of the two seed means, its standard error
sqrt(s_a^2/n_a + s_b^2/n_b) from the seed-to-seed spreads, z = difference / standard error and
Welch's two-sided p. After every rotation both sides have (seeds pooled over the folders
that hold it): <nn>'_12, <nn>'_23, sigma'_12 and sigma'_23
in the strain bins of engine_ladder.BINS, per bin z in the same way. The criterion, named before
looking: |z| <= 2 (two combined standard errors) for every steady quantity and transient bin;
about 5% of the bins exceed 2 by chance alone, so the report also gives how many do and the
largest |z| against the Sidak bound for the number compared. ``--save`` copies the first study
folder's tables (no trajectories) to the given folder for the record. ``--paired`` adds, over the
seeds both sides ran, each seed's difference of the steady means (the same packing on both sides),
their mean and its 95% t-interval.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
from engine_ladder import BINS, FABRIC, STEADY_WINDOW, STRESS, binned_seed_means, engine_label, run_table, seed_folders
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


def seed_means(folders: list[Path], kind: str, columns) -> pd.DataFrame:
    """Each seed's mean of `columns` over the steady window of its startup (rows: seeds)."""
    tables = [run_table(folder, "startup", kind) for folder in folders]
    table = pd.concat(tables, ignore_index=True)
    window = table[(table["strain"] >= STEADY_WINDOW[0]) & (table["strain"] <= STEADY_WINDOW[1])]
    means = window.groupby("seed")[list(columns)].mean()
    if len(means) != sum(t["seed"].nunique() for t in tables):
        raise ValueError(f"{[str(f) for f in folders]}: a seed appears in more than one folder")
    return means


def both_seed_means(study: list[Path], dataset: list[Path]) -> list[tuple[tuple, pd.DataFrame, pd.DataFrame]]:
    """(columns, study's seed means, dataset's seed means) for the fabric and the stress."""
    return [
        (columns, seed_means(study, kind, columns), seed_means(dataset, kind, columns))
        for kind, columns in (("fabric", FABRIC), ("stress", STRESS))
    ]


def steady_table(means) -> tuple[str, list[float]]:
    """Welch's comparison of each quantity's seed means (both_seed_means)."""
    rows = ["| quantity | study | dataset | difference | z | Welch p |", "|---|---|---|---|---|---|"]
    zs = []
    for columns, a, b in means:
        for quantity in columns:
            x, y = a[quantity].to_numpy(), b[quantity].to_numpy()
            error = np.sqrt(x.var(ddof=1) / len(x) + y.var(ddof=1) / len(y))
            z = (x.mean() - y.mean()) / error
            zs.append(z)
            p = stats.ttest_ind(x, y, equal_var=False).pvalue
            difference = x.mean() - y.mean()
            # relative only where the dataset's mean is well resolved (not for components near 0)
            resolved = abs(y.mean()) > 10 * y.std(ddof=1) / np.sqrt(len(y))
            relative = f" ({difference / abs(y.mean()):+.1%})" if resolved else ""
            rows.append(
                f"| {quantity} | {x.mean():.4f} +- {x.std(ddof=1) / np.sqrt(len(x)):.4f} ({len(x)}) | "
                f"{y.mean():.4f} +- {y.std(ddof=1) / np.sqrt(len(y)):.4f} ({len(y)}) | "
                f"{difference:+.4f}{relative} | {z:+.2f} | {p:.3f} |"
            )
    return "\n".join(rows), zs


def paired_table(means, level: float = 0.95) -> str:
    """Per packing: for each seed both sides ran (the same packing, independent trajectories), the
    difference of its steady means (both_seed_means); their mean with a t-interval over those seeds."""
    rows = [f"| quantity | seeds | mean difference | {level:.0%} t-interval | seeds with a lower study value |"]
    rows.append("|---|--:|--:|---|--:|")
    for columns, a, b in means:
        shared = a.index.intersection(b.index)
        if len(shared) < 2:
            raise SystemExit(f"--paired: the study and the dataset share {len(shared)} seeds, at least 2 needed")
        for quantity in columns:
            d = (a.loc[shared, quantity] - b.loc[shared, quantity]).to_numpy()
            half = stats.t.ppf(0.5 + level / 2, len(d) - 1) * d.std(ddof=1) / np.sqrt(len(d))
            rows.append(
                f"| {quantity} | {len(d)} | {d.mean():+.4f} | [{d.mean() - half:+.4f}, {d.mean() + half:+.4f}] | "
                f"{int((d < 0).sum())} of {len(d)} |"
            )
    return "\n".join(rows)


def pooled_bins(folders: list[Path], angle: int, kind: str, column: str) -> np.ndarray:
    """binned_seed_means of every folder that holds the rotation, their seeds stacked."""
    return np.vstack([binned_seed_means(f, angle, kind, column) for f in folders if angle in rotation_angles(f)])


def transient_z(study: list[Path], dataset: list[Path], angle: int, kind: str, column: str) -> np.ndarray:
    a = pooled_bins(study, angle, kind, column)
    b = pooled_bins(dataset, angle, kind, column)
    error = np.sqrt(a.var(axis=0, ddof=1) / len(a) + b.var(axis=0, ddof=1) / len(b))
    return (a.mean(axis=0) - b.mean(axis=0)) / error


def transient_table(study: list[Path], dataset: list[Path]) -> tuple[str, list[float]]:
    """z per strain bin after each rotation that both sides hold (seeds pooled over their folders)."""
    held = [{angle for folder in folders for angle in rotation_angles(folder)} for folders in (study, dataset)]
    angles = sorted(held[0] & held[1])
    bins = " | ".join(f"{lo:g}-{hi:g}" for lo, hi in BINS)
    rows = [f"| angle | quantity | {bins} | max abs z |", "|---|---|" + "---|" * (len(BINS) + 1)]
    zs = []
    for angle in angles:
        for kind, column, name in TRANSIENTS:
            z = transient_z(study, dataset, angle, kind, column)
            zs.extend(z)
            rows.append(f"| {angle} | {name} | {' | '.join(f'{v:+.2f}' for v in z)} | {np.abs(z).max():.2f} |")
    return "\n".join(rows), zs


def rotation_seeds(folders: list[Path]) -> int:
    """The fewest seeds any rotation has, pooled over the folders (0: no rotation)."""
    angles = {angle for folder in folders for angle in rotation_angles(folder)}
    return min((len(pooled_bins(folders, angle, "stress", "total_12")) for angle in angles), default=0)


def welch_null(seeds_a: int, seeds_b: int, count: int, draws: int = 20000, level: float = 0.95) -> tuple[float, float]:
    """Welch's z of `count` independent quantities with seeds_a against seeds_b seeds of one normal
    population (Monte Carlo, fixed seed): how many exceed LEVEL on average, and the |z| that the
    largest exceeds with 1 - level. With few seeds z has heavy tails, so both are above the
    normal-theory count and Sidak bound."""
    rng = np.random.default_rng(0)
    a = rng.normal(size=(draws, seeds_a, count))
    b = rng.normal(size=(draws, seeds_b, count))
    z = (a.mean(axis=1) - b.mean(axis=1)) / np.sqrt(a.var(axis=1, ddof=1) / seeds_a + b.var(axis=1, ddof=1) / seeds_b)
    largest = np.abs(z).max(axis=1)
    return float((np.abs(z) > LEVEL).sum(axis=1).mean()), float(np.quantile(largest, level))


def sidak_bound(count: int, level: float = 0.95) -> float:
    """|z| that the largest of `count` independent standard normals exceeds with 1 - level."""
    return float(stats.norm.ppf(1.0 - (1.0 - level ** (1.0 / count)) / 2.0))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--study", type=Path, nargs="+", required=True)
    parser.add_argument("--dataset", type=Path, nargs="+", required=True)
    parser.add_argument("--save", type=Path, help="copy the first study folder's tables here first")
    parser.add_argument("--paired", action="store_true", help="also the per-packing differences of the steady means")
    args = parser.parse_args()
    study = list(args.study)
    if args.save:
        study[0] = save(study[0], args.save)
    for name, folders in (("study", study), ("dataset", args.dataset)):
        for folder in folders:
            print(f"{name}: {folder}: {engine_label(folder)} ({len(seed_folders(folder))} seeds)")
    window = f"{STEADY_WINDOW[0]:g}-{STEADY_WINDOW[1]:g}"
    print(f"steady window strain {window}; z = difference / its standard error over seeds\n")
    means = both_seed_means(study, args.dataset)
    text, steady_z = steady_table(means)
    print(text)
    if args.paired:
        print("\nPaired by packing (the seeds both sides ran)\n")
        print(paired_table(means))
    print("\nAfter each rotation: z per strain bin\n")
    text, transient = transient_table(study, list(args.dataset))
    print(text)
    seeds = {  # each side's seeds, the fewest any quantity has
        "steady quantities": (min(len(m[1]) for m in means), min(len(m[2]) for m in means)),
        "transient bins": (rotation_seeds(study), rotation_seeds(list(args.dataset))),
    }
    for name, zs in (("steady quantities", steady_z), ("transient bins", transient)):
        zs = np.abs(np.asarray(zs))
        if not len(zs):
            print(f"\n{name}: none (a side holds startups only)")
            continue
        print(
            f"\n{name}: {len(zs)}, {int((zs > LEVEL).sum())} with |z| > {LEVEL:g} "
            f"({0.0455 * len(zs):.1f} expected by chance), largest {zs.max():.2f} "
            f"(Sidak 95% bound for {len(zs)}: {sidak_bound(len(zs)):.2f})"
        )
        expected, bound = welch_null(*seeds[name], len(zs))
        print(
            f"  with Welch's z of {seeds[name][0]} against {seeds[name][1]} seeds (Monte Carlo of normal seeds): "
            f"{expected:.1f} expected beyond {LEVEL:g}, the largest beyond {bound:.2f} in 5% of draws"
        )


if __name__ == "__main__":
    main()

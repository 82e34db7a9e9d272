"""The stress verdicts with the lubrication stress as force dipoles and as pair stresslets, on the same runs.

Reads two finished studies of the same runs that differ only in ``analysis.lubrication_stress``
(config/stresslets.yaml and its dipole twin) and prints, per seed paired (stresslet - dipole,
95% t-interval over the seeds): the steady eta_r, N1, N2, Pi and lubrication sigma_12 (means over
the steady window of each seed's startup); the G-W stress relation fitted on each (a_H, and its
steady N1, N2, Pi against the simulated: the "N1 of the wrong sign, N2 and Pi too large"
verdicts); the integrated viscosity deficit after each rotation (the viscosity-dip verdicts:
does its interval exclude 0?); the stress relations' held-out error of eta_r after rotation.

    .venv/bin/snakemake --cores 2 --configfile config/stresslets.yaml
    .venv/bin/snakemake --cores 2 --configfile config/stresslets.yaml --config study=stresslets_dipole \\
        analysis='{steady_window: [2.0, 5.0], lubrication_stress: dipole}'
    .venv/bin/python benchmarks/lubrication_stress_choice.py results/stresslets_dipole results/stresslets
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import t_interval

QUANTITIES = ("eta_r", "N1", "N2", "Pi", "lubrication_12")


def seed_steady(study: Path) -> pd.DataFrame:
    """Each seed's mean of QUANTITIES over the study's own steady window (its steady-state table's)."""
    steady = pd.read_csv(study / "tables/stress_steady_state.csv")
    window = (steady["strain_min"].iloc[0], steady["strain_max"].iloc[0])
    runs = pd.read_csv(study / "tables/stress_startup_runs.csv")
    inside = runs[(runs["strain"] >= window[0]) & (runs["strain"] <= window[1])]
    return inside.groupby("seed")[list(QUANTITIES)].mean()


def interval(values) -> str:
    found = t_interval(np.asarray(values, dtype=float))
    return f"{found.mean:+.4f} [{found.low:+.4f}, {found.high:+.4f}]"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dipole", type=Path, help="results folder of the study with the dipoles")
    parser.add_argument("stresslet", type=Path, help="results folder of the study with the stresslets")
    args = parser.parse_args()
    dipole, stresslet = seed_steady(args.dipole), seed_steady(args.stresslet)
    print("| steady (seed mean) | dipoles | stresslets | stresslets - dipoles, per seed |\n|---|--:|--:|--:|")
    for name in QUANTITIES:
        print(
            f"| {name} | {dipole[name].mean():.3f} | {stresslet[name].mean():.3f} | "
            f"{interval(stresslet[name] - dipole[name])} |"
        )

    print("\n| G-W relation on the simulated fabric | dipoles | stresslets |\n|---|--:|--:|")
    fits = [
        pd.read_csv(s / "tables/stress_relation_fits.csv").set_index("source").loc["simulation"]
        for s in (args.dipole, args.stresslet)
    ]
    print(f"| a_H | {fits[0]['a_H']:.2f} | {fits[1]['a_H']:.2f} |")
    for name in ("N1", "N2", "Pi"):
        cells = [f"{f[f'{name}_predicted']:.2f} (simulated {f[f'{name}_simulated']:.2f})" for f in fits]
        print(f"| {name} predicted | {cells[0]} | {cells[1]} |")

    print("\n| theta | deficit, dipoles | deficit, stresslets | stresslets - dipoles, per seed |\n|---|--:|--:|--:|")
    deficits = [
        pd.read_csv(s / "tables/stress_viscosity_deficit_per_seed.csv").set_index(["theta", "seed"])["deficit"]
        for s in (args.dipole, args.stresslet)
    ]
    for theta in deficits[0].index.get_level_values("theta").unique():
        a, b = deficits[0].loc[theta], deficits[1].loc[theta].loc[deficits[0].loc[theta].index]
        print(f"| {theta:g} | {interval(a)} | {interval(b)} | {interval(b - a)} |")

    print("\n| relation | held-out mse of eta_r after rotation, dipoles | stresslets |\n|---|--:|--:|")
    boards = [
        pd.read_csv(s / "tables/stress_leaderboard.csv").query("quantity == 'eta_r rotation'").set_index("relation")
        for s in (args.dipole, args.stresslet)
    ]
    for relation, row in boards[0].iterrows():
        other = boards[1].loc[relation]
        print(
            f"| {relation} | {row['held_out_mse']:.4f} [{row['held_out_low']:.4f}, {row['held_out_high']:.4f}] | "
            f"{other['held_out_mse']:.4f} [{other['held_out_low']:.4f}, {other['held_out_high']:.4f}] |"
        )


if __name__ == "__main__":
    main()

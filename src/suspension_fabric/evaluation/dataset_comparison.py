"""A study against other datasets (config key ``verdicts.comparisons``: another system size,
engine or lubrication range), quantity by quantity, with the seeds as the independent units.

Per seed, statistics linear in the data: the mean of each steady quantity over the steady
window of startup shear (fabric <nn>_11, _22, _33, _12 and Z; stress eta_r, N1, N2, Pi where the
runs recorded it) and, at every rotation angle, the integrated viscosity deficit after the
rotation V_s(theta) = integral_0^W (1 - eta_r,s / eta_r^ss,s) dgamma
([`suspension_fabric.evaluation.stress_model.viscosity_deficits`][]). Per dataset: the seed mean with its
t-interval; against the study: the difference of the means with Welch's interval (independent
seeds, unequal spreads), "differs" if it excludes 0, "agrees" otherwise.
"""

from __future__ import annotations

import pandas as pd

from suspension_fabric.analysis.seed_statistics import LEVEL, t_interval, welch_interval
from suspension_fabric.analysis.stress import DERIVED_COLUMNS
from suspension_fabric.evaluation.stress_model import seed_steady_viscosity, viscosity_deficits

__all__ = ["FABRIC_QUANTITIES", "STRESS_QUANTITIES", "per_seed_statistics", "comparison_table"]

FABRIC_QUANTITIES = ("n11", "n22", "n33", "n12", "Z")
STRESS_QUANTITIES = DERIVED_COLUMNS  # eta_r, N1, N2, Pi
DEFICIT = "viscosity_deficit"


def _window_means(runs: pd.DataFrame, quantities, window) -> list[dict]:
    lo, hi = window
    rows = []
    for seed, run in runs.groupby("seed", sort=True):
        inside = run[(run["strain"] >= lo) & (run["strain"] <= hi)]
        if len(inside) < 2:
            raise ValueError(f"seed {seed}: {len(inside)} frame(s) in the steady window {window}, need at least 2")
        rows += [
            {"seed": int(seed), "quantity": q, "theta": float("nan"), "value": float(inside[q].mean())}
            for q in quantities
        ]
    return rows


def per_seed_statistics(
    startup_fabric: pd.DataFrame,
    startup_stress: pd.DataFrame | None,
    rotation_stress: pd.DataFrame | None,
    steady_window,
    window: float,
) -> pd.DataFrame:
    """Long table (seed, quantity, theta, value) of the module's per-seed statistics; the stress
    ones only when the stress tables are given. theta is NaN for the steady quantities."""
    rows = _window_means(startup_fabric, FABRIC_QUANTITIES, steady_window)
    if startup_stress is not None and rotation_stress is not None:
        rows += _window_means(startup_stress, STRESS_QUANTITIES, steady_window)
        deficits = viscosity_deficits(rotation_stress, seed_steady_viscosity(startup_stress, steady_window), window)
        rows += [
            {"seed": int(r.seed), "quantity": DEFICIT, "theta": float(r.theta), "value": float(r.deficit)}
            for r in deficits.itertuples()
        ]
    return pd.DataFrame(rows, columns=["seed", "quantity", "theta", "value"])


def comparison_table(
    per_seed: dict[str, tuple[int, pd.DataFrame]], reference: str, level: float = LEVEL
) -> pd.DataFrame:
    """One row per dataset, quantity and angle: N, seeds, seed mean and t-interval, and the
    difference to the ``reference`` dataset (Welch interval, verdict) where both have it.
    ``per_seed`` maps a label to (N,
    [`per_seed_statistics`][suspension_fabric.evaluation.dataset_comparison.per_seed_statistics] table)."""
    keyed = {
        label: {
            key: rows["value"].to_numpy()
            for key, rows in table.fillna({"theta": -1.0}).groupby(["quantity", "theta"], sort=False)
        }
        for label, (_, table) in per_seed.items()
    }
    rows = []
    for label, (n_particles, _) in per_seed.items():
        for (quantity, theta), values in keyed[label].items():
            interval = t_interval(values, level)
            row = {
                "dataset": label,
                "N": n_particles,
                "seeds": len(values),
                "quantity": quantity,
                "theta": None if theta == -1.0 else theta,
                "mean": interval.mean,
                "low": interval.low,
                "high": interval.high,
                "level": level,
            }
            other = keyed[reference].get((quantity, theta))
            if label != reference and other is not None and len(values) > 1 and len(other) > 1:
                difference = welch_interval(values, other, level)
                row.update(
                    difference=difference.mean,
                    difference_low=difference.low,
                    difference_high=difference.high,
                    verdict="differs" if difference.low > 0 or difference.high < 0 else "agrees",
                )
            rows.append(row)
    return pd.DataFrame(rows)

"""The map over the state point: one row per campaign point (phi, mu) with its steady fabric,
contact number, stress, fitted model parameters, verdict statistics and whether it reached a
steady state; and the published anchor drawn next to it.

Steady state (named before looking at the campaign): for each seed, the mean of a quantity over
the second half of the steady window minus its mean over the first half, divided by the study's
steady value; with the t-interval of that relative drift over seeds at ``level``: "steady" if
the interval lies inside +-``DRIFT_MARGIN``, "drifting" if it excludes 0 and its mean is outside
the margin, "not resolved" otherwise. Checked on <nn>_12 and eta_r; a point is steady only if
both are.

Anchor: the mu(J) and phi(J) laws of Boyer, Guazzelli and Pouliquen, PRL 107, 188301 (2011),
fitted there to frictional spheres (polystyrene and PMMA): with the viscous number
J = eta_f gammadot / P and the particle pressure P = Pi eta_f gammadot (so J = 1 / Pi),
    mu(J) = mu1 + (mu2 - mu1) / (1 + J0 / J) + J + (5/2) phi_m J^(1/2),
    phi(J) = phi_m / (1 + J^(1/2)),
with mu1 = 0.32, mu2 = 0.7, J0 = 0.005, phi_m = 0.585. Then Pi = 1 / J and the relative shear
viscosity (solvent included) eta_r = mu(J) / J, as functions of phi.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import LEVEL, adjusted_p, decide_adjusted, interval_t_test_p, t_interval
from suspension_fabric.analysis.stress import DERIVED_COLUMNS

__all__ = [
    "BGP_PARAMETERS",
    "bgp_viscosities",
    "DRIFT_MARGIN",
    "steady_state_drift",
    "point_row",
    "map_table",
    "fitted_columns",
    "MAP_QUANTITIES",
    "MAP_CLAIMS",
    "claims_multiplicity",
]

#: Boyer, Guazzelli and Pouliquen (2011), frictional spheres
BGP_PARAMETERS = {"mu1": 0.32, "mu2": 0.7, "J0": 0.005, "phi_m": 0.585}
#: Largest relative drift between the halves of the steady window that still counts as steady
DRIFT_MARGIN = 0.1
#: Steady-state quantities of the map: fabric table and stress table columns
FABRIC_QUANTITIES = ("n11", "n22", "n33", "n12", "n13", "n23", "Z")
STRESS_QUANTITIES = DERIVED_COLUMNS  # eta_r, N1, N2, Pi
MAP_QUANTITIES = FABRIC_QUANTITIES + STRESS_QUANTITIES
#: The claims the map reports per point, read at once over all points (one family for Holm's
#: adjustment): the paired model-error statistics after a rotation (> 0: the challenger is better)
#: and the challenger's overshoot
MAP_CLAIMS = ("C3'", "C4'", "C5")


def bgp_viscosities(phi, parameters: dict = BGP_PARAMETERS) -> tuple[np.ndarray, np.ndarray]:
    """(eta_r, Pi) of the BGP laws (module docstring) at volume fractions ``phi`` < phi_m."""
    phi = np.asarray(phi, dtype=float)
    mu1, mu2, j0, phi_m = (parameters[key] for key in ("mu1", "mu2", "J0", "phi_m"))
    if np.any((phi <= 0) | (phi >= phi_m)):
        raise ValueError(f"the BGP law holds for 0 < phi < phi_m = {phi_m}, got {phi}")
    j = (phi_m / phi - 1.0) ** 2
    friction = mu1 + (mu2 - mu1) / (1.0 + j0 / j) + j + 2.5 * phi_m * np.sqrt(j)
    return friction / j, 1.0 / j


def steady_state_drift(runs: pd.DataFrame, quantity: str, window, steady_value: float, level: float = LEVEL) -> dict:
    """Relative drift of ``quantity`` across the steady window of the startup runs (module
    docstring): per seed (second-half mean - first-half mean) / steady_value; its t-interval
    over seeds and the verdict."""
    lo, hi = window
    middle = 0.5 * (lo + hi)
    per_seed = []
    for seed, run in runs.groupby("seed"):
        strain, values = run["strain"].to_numpy(), run[quantity].to_numpy()
        first = values[(strain >= lo) & (strain < middle)]
        second = values[(strain >= middle) & (strain <= hi)]
        if first.size == 0 or second.size == 0:
            raise ValueError(f"seed {seed}: no frames in one half of the steady window {window} for {quantity}")
        per_seed.append((second.mean() - first.mean()) / abs(steady_value))
    interval = t_interval(per_seed, level)
    if -DRIFT_MARGIN < interval.low and interval.high < DRIFT_MARGIN:
        verdict = "steady"
    elif (interval.low > 0 or interval.high < 0) and abs(interval.mean) > DRIFT_MARGIN:
        verdict = "drifting"
    else:
        verdict = "not resolved"
    return {"mean": interval.mean, "low": interval.low, "high": interval.high, "verdict": verdict}


def _model_columns(role: str, entry: dict) -> dict:
    """A compared model's columns: ``<role>_model`` (its label), ``<role>_<parameter>`` with its
    jackknife error ``_err``, and ``<role>_A_over_beta`` for a model with parameters A and beta
    (first-order error of the ratio, their leave-one-out correlation included)."""
    parameters, errors = entry["parameters"], entry["errors"]
    out = {f"{role}_model": entry["label"]}
    for name, value in parameters.items():
        out[f"{role}_{name}"], out[f"{role}_{name}_err"] = value, errors.get(name)
    if {"A", "beta"} <= set(parameters):
        ratio = parameters["A"] / parameters["beta"]
        relative = [_relative(errors.get(name), parameters[name]) for name in ("A", "beta")]
        rho = entry.get("correlations", {}).get("beta,A") or 0.0
        variance = relative[0] ** 2 + relative[1] ** 2 - 2 * rho * relative[0] * relative[1]
        out[f"{role}_A_over_beta"] = ratio
        out[f"{role}_A_over_beta_err"] = abs(ratio) * np.sqrt(max(variance, 0.0))
    return out


def fitted_columns(table: pd.DataFrame) -> list[tuple[str, str, str, str]]:
    """(model label, parameter, column, error column) of every fitted parameter of the compared
    models in a map table (the ``<role>_<parameter>`` columns of `_model_columns`)."""
    out = []
    for role in ("reference", "challenger"):
        labels = table[f"{role}_model"].dropna() if f"{role}_model" in table else []
        model = str(labels.iloc[0]) if len(labels) else role
        for column in table.columns:
            if column.startswith(f"{role}_") and column.endswith("_err"):
                out.append((model, column[len(role) + 1 : -len("_err")], column[: -len("_err")], column))
    return out


def _relative(error, value) -> float:
    return np.nan if error is None else error / value


def point_row(
    point: str,
    study: dict,
    steady: pd.DataFrame,
    stress_steady: pd.DataFrame,
    fits: dict,
    verdicts: pd.DataFrame,
    startup_runs: pd.DataFrame,
    stress_runs: pd.DataFrame,
    level: float = LEVEL,
) -> dict:
    """One campaign point as a row of the map table: its state and engine, every steady
    quantity with its standard error, the fits of the two models its claims compare (the
    study's verdicts.models, by role: `_model_columns`) with their jackknife errors, the
    steady-state check, and each claim's seed-mean statistic with its interval and verdict."""
    row = {
        "point": point,
        "phi": study["particles"]["phi"],
        "mu": study["forces"]["mu"],
        "n": study["particles"]["n"],
        "seeds": len(study["seeds"]),
        "kn": study["forces"]["kn"],
        "dt": study["run"]["dt"],
        "startup_strain": study["run"]["startup_strain"],
    }
    for table, quantities in ((steady, FABRIC_QUANTITIES), (stress_steady, STRESS_QUANTITIES)):
        indexed = table.set_index("quantity")
        for quantity in quantities:
            row[quantity] = float(indexed.loc[quantity, "mean"])
            row[f"{quantity}_sem"] = float(indexed.loc[quantity, "sem_between_seeds"])
    for role in ("reference", "challenger"):
        row.update(_model_columns(role, fits["models"][study["verdicts"]["models"][role]]))
    window = study["analysis"]["steady_window"]
    checks = {"n12": (startup_runs, row["n12"]), "eta_r": (stress_runs, row["eta_r"])}
    verdicts_steady = []
    for quantity, (runs, value) in checks.items():
        drift = steady_state_drift(runs, quantity, window, value, level)
        for key in ("mean", "low", "high", "verdict"):
            row[f"drift_{quantity}_{key}"] = drift[key]
        verdicts_steady.append(drift["verdict"])
    row["steady"] = (
        "steady"
        if all(v == "steady" for v in verdicts_steady)
        else "drifting"
        if "drifting" in verdicts_steady
        else "not resolved"
    )
    for claim in verdicts.itertuples():
        if isinstance(claim.verdict, str) and claim.verdict:
            row[f"{claim.claim}_mean"], row[f"{claim.claim}_low"] = claim.mean, claim.low
            row[f"{claim.claim}_high"], row[f"{claim.claim}_verdict"] = claim.high, claim.verdict
            row[f"{claim.claim}_p"] = interval_t_test_p(claim.mean, claim.low, claim.high, len(study["seeds"]), level)
    return row


def claims_multiplicity(table: pd.DataFrame, claims=MAP_CLAIMS, level: float = LEVEL) -> pd.DataFrame:
    """Adds per claim of ``claims`` the p-value adjusted by Holm's method over every cell of those
    claims at every point (``<claim>_p_holm``: the map's cells are read at once) and the verdict
    that adjustment leaves (``<claim>_verdict_holm``: decided only where the adjusted p is below
    1 - ``level``); cells without a p-value (a point not run, a claim without its angles) stay
    out of the family."""
    table = table.copy()
    present = [claim for claim in claims if f"{claim}_p" in table]
    if not present:
        return table
    stacked = table[[f"{claim}_p" for claim in present]].to_numpy(dtype=float)
    adjusted = adjusted_p(stacked.ravel(), "holm").reshape(stacked.shape)
    for k, claim in enumerate(present):
        table[f"{claim}_p_holm"] = adjusted[:, k]
        table[f"{claim}_verdict_holm"] = [
            decide_adjusted(mean, p, level) if np.isfinite(p) else np.nan
            for mean, p in zip(table[f"{claim}_mean"], adjusted[:, k])
        ]
    return table


def map_table(rows: list[dict], not_run: dict[str, str], level: float = LEVEL) -> pd.DataFrame:
    """The map table: the simulated points' rows, and a row per point not run with its reason
    in ``steady`` (``not run: <reason>``) and its phi, mu from the name; the claims' verdicts
    adjusted over the map's cells
    ([`claims_multiplicity`][suspension_fabric.evaluation.state_map.claims_multiplicity])."""
    extra = []
    for point, reason in not_run.items():
        phi, mu = (float(part[len(prefix) :]) for part, prefix in zip(point.split("_"), ("phi", "mu")))
        extra.append({"point": point, "phi": phi, "mu": mu, "steady": f"not run: {reason}"})
    table = pd.DataFrame(rows + extra).sort_values(["mu", "phi"], ignore_index=True)
    return claims_multiplicity(table, MAP_CLAIMS, level)

"""The paper's claims, each decided by a number with its error bar across seeds.

Inputs are the workflow's tables: ``fits.json`` (fitted parameters, the simulated steady state
and each model's own steady state), the per-seed rotation table (``rotation_runs.csv``: one row
per seed, angle and strain, components in the rotated paper frame) and the model predictions
(``predictions.csv``). Post-rotation components are normalised by the steady <nn>_12 of startup
shear, n12_ss (< 0), as in the paper's Fig. 2.

Measures
    recovery strain of <nn>'_12: the first strain after which |<nn>'_12 / baseline - 1| stays
    within ``tolerance`` (10%) to the end of the run; of <nn>'_23, after which
    |<nn>'_23 / n12_ss| stays within it. For the simulation it is taken on the seed-mean curve
    (a single seed's fluctuations reach ~10% at N = 500). Baselines: the startup's steady n12_ss, or (simulation
    only) the theta = 0 continuation of the same seed from the same checkpoint, which removes
    the slow fluctuation of the steady state a single seed carries through the rotation. A run
    that never settles counts as recovering at its last strain (censored; the table says so).
    overshoot of <nn>'_12: a model's max over strain of <nn>'_12 / n12_ss - 1 (> 0: |<nn>'_12|
    above steady); the simulation's mean of <nn>'_12 / baseline - 1 around that strain.
    rms error of a model on a component: over strains, |model - seed mean| / |n12_ss|.
Errors across seeds: the jackknife over seeds (leave one seed out) of each quantity of the
seed-mean curves.

Verdicts: "confirmed" if the deciding number lies beyond 2 standard errors on the paper's
side, "refuted" if beyond 2 on the other side, otherwise "not resolved at this precision".
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["TOLERANCE", "settle_strain", "jackknife", "recovery_table", "rms_error_table", "overshoot_table",
           "steady_state_verdicts", "rotation_verdicts", "verdict_table"]

TOLERANCE = 0.1
CONFIRMED, REFUTED, UNRESOLVED = "confirmed", "refuted", "not resolved at this precision"
# the paper's fitted parameters (its Sec. 3)
PAPER = {"gw_beta": 10.9, "modified_beta": 9.4, "modified_A": 42.4}
MODELS = ("gw", "modified")


def settle_strain(strain: np.ndarray, deviation: np.ndarray, tolerance: float = TOLERANCE) -> tuple[float, bool]:
    """First strain from which |deviation| <= tolerance to the end; (strain, settled).

    A series still outside the band at its last point is censored: (last strain, False).
    """
    strain, outside = np.asarray(strain, float), np.abs(np.asarray(deviation, float)) > tolerance
    if strain.shape != outside.shape:
        raise ValueError(f"strain and deviation lengths differ: {strain.shape} and {outside.shape}")
    if outside[-1]:
        return float(strain[-1]), False
    last_outside = np.flatnonzero(outside)
    return (float(strain[last_outside[-1] + 1]) if len(last_outside) else float(strain[0])), True


def _verdict(value: float, error: float, paper_sign: int) -> str:
    """Verdict for a number whose sign the claim predicts (paper_sign = +1 or -1)."""
    if not np.isfinite(value):
        return UNRESOLVED
    z = value / error if error > 0 else (np.inf * np.sign(value) if value != 0 else 0.0)
    if paper_sign * z > 2:
        return CONFIRMED
    if paper_sign * z < -2:
        return REFUTED
    return UNRESOLVED


def jackknife(statistic, seeds) -> tuple[float, float]:
    """statistic(all seeds) and its jackknife standard error over seeds."""
    value = statistic(list(seeds))
    if len(seeds) < 2:
        return value, np.nan
    leave_one_out = np.array([statistic([s for s in seeds if s != left]) for left in seeds])
    n = len(seeds)
    return value, float(np.sqrt((n - 1) / n * np.sum((leave_one_out - leave_one_out.mean()) ** 2)))


def _curves(runs: pd.DataFrame, theta: float, column: str) -> tuple[np.ndarray, dict]:
    """Strains and {seed: values} of one component at one angle (all seeds on the same strains)."""
    rows = runs[np.isclose(runs["theta"], theta)].sort_values(["seed", "strain"])
    curves = {seed: group[column].to_numpy() for seed, group in rows.groupby("seed")}
    strain = rows[rows["seed"] == rows["seed"].iloc[0]]["strain"].to_numpy()
    if len({len(c) for c in curves.values()}) != 1:
        raise ValueError(f"theta = {theta}: the seeds' {column} series have different lengths")
    return strain, curves


def _model_series(predictions: pd.DataFrame, model: str, theta: float) -> pd.DataFrame:
    rows = predictions[(predictions["model"] == model) & (predictions["protocol"] == "rotation")
                       & np.isclose(predictions["theta"], theta)]
    return rows.sort_values("strain")


def _model_on(strain: np.ndarray, predictions: pd.DataFrame, model: str, theta: float, column: str) -> np.ndarray:
    series = _model_series(predictions, model, theta)
    return np.interp(strain, series["strain"].to_numpy(), series[column].to_numpy())


def _ratio_curves(runs: pd.DataFrame, theta: float, n12_ss: float) -> tuple[np.ndarray, dict]:
    """Per seed: <nn>'_12 / n12_ss - 1 ("steady"), <nn>'_12 / <nn>'_12(theta = 0) - 1
    ("continuation") and <nn>'_23 / n12_ss ("n23")."""
    strain, n12 = _curves(runs, theta, "n12")
    _, n23 = _curves(runs, theta, "n23")
    _, n12_continued = _curves(runs, 0.0, "n12")
    return strain, {
        "steady": {s: v / n12_ss - 1.0 for s, v in n12.items()},
        "continuation": {s: v / n12_continued[s] - 1.0 for s, v in n12.items() if s in n12_continued},
        "n23": {s: v / n12_ss for s, v in n23.items()},
    }


def recovery_table(runs: pd.DataFrame, predictions: pd.DataFrame, n12_ss: float,
                   tolerance: float = TOLERANCE) -> pd.DataFrame:
    """Recovery strains of <nn>'_12 (steady and theta = 0 baselines) and <nn>'_23 per angle:
    simulation (seed-mean curve, jackknife error over seeds) and both models; ``*_settled``
    is False where the curve never settles within the run (then its last strain is given)."""
    rows = []
    for theta in sorted(runs["theta"].unique()):
        strain, deviations = _ratio_curves(runs, theta, n12_ss)
        row = {"theta": theta}
        for key, per_seed in deviations.items():
            seeds = sorted(per_seed)

            def statistic(subset, per_seed=per_seed):
                return settle_strain(strain, np.mean([per_seed[s] for s in subset], axis=0), tolerance)[0]

            row[f"sim_{key}"], row[f"sim_{key}_err"] = jackknife(statistic, seeds)
            row[f"sim_{key}_settled"] = settle_strain(strain, np.mean(list(per_seed.values()), axis=0), tolerance)[1]
        for model in MODELS:
            series = _model_series(predictions, model, theta)
            model_strain = series["strain"].to_numpy()
            for key, deviation in (("steady", series["n12"].to_numpy() / n12_ss - 1.0),
                                   ("n23", series["n23"].to_numpy() / n12_ss)):
                row[f"{model}_{key}"], row[f"{model}_{key}_settled"] = settle_strain(model_strain, deviation, tolerance)
        rows.append(row)
    return pd.DataFrame(rows)


def rms_error_table(runs: pd.DataFrame, predictions: pd.DataFrame, n12_ss: float) -> pd.DataFrame:
    """Per angle and component (12, 23): rms |model - seed mean| / |n12_ss| of each model, and the
    ratio G-W / modified, with jackknife errors over seeds."""
    rows = []
    for theta in sorted(runs["theta"].unique()):
        for column in ("n12", "n23"):
            strain, curves = _curves(runs, theta, column)
            seeds = sorted(curves)
            models = {model: _model_on(strain, predictions, model, theta, column) for model in MODELS}

            def rms(model, subset):
                mean = np.mean([curves[s] for s in subset], axis=0)
                return float(np.sqrt(np.mean((models[model] - mean) ** 2)) / abs(n12_ss))

            row = {"theta": theta, "component": column}
            for model in MODELS:
                row[f"{model}_rms"], row[f"{model}_rms_err"] = jackknife(lambda subset, m=model: rms(m, subset), seeds)
            with np.errstate(divide="ignore", invalid="ignore"):  # both models exact: no ratio (nan)
                row["ratio"], row["ratio_err"] = jackknife(
                    lambda subset: np.float64(rms("gw", subset)) / rms("modified", subset), seeds)
            rows.append(row)
    return pd.DataFrame(rows)


def overshoot_table(runs: pd.DataFrame, predictions: pd.DataFrame, n12_ss: float,
                    half_window: float = 0.25) -> pd.DataFrame:
    """Per angle: each model's largest <nn>'_12 / n12_ss - 1 and the strain where it occurs; the
    simulation's mean of <nn>'_12 / baseline - 1 over that strain +- ``half_window`` (seed-mean
    curve, jackknife error; steady and theta = 0 baselines). A mean over a window, not a
    maximum, which noise would bias upward."""
    rows = []
    for theta in sorted(runs["theta"].unique()):
        strain, deviations = _ratio_curves(runs, theta, n12_ss)
        row = {"theta": theta}
        for model in MODELS:
            series = _model_series(predictions, model, theta)
            ratio = series["n12"].to_numpy() / n12_ss - 1.0
            row[model], row[f"{model}_strain"] = float(ratio.max()), float(series["strain"].to_numpy()[ratio.argmax()])
        peak = row["modified_strain"]
        window = (strain >= peak - half_window) & (strain <= peak + half_window)
        for key in ("steady", "continuation"):
            per_seed = deviations[key]
            row[f"sim_{key}"], row[f"sim_{key}_err"] = jackknife(
                lambda subset, p=per_seed: float(np.mean([p[s][window] for s in subset])), sorted(per_seed))
        rows.append(row)
    return pd.DataFrame(rows)


def _claim(claim: str, number: str, value: float, error: float, verdict: str, criterion: str) -> dict:
    return {"claim": claim, "deciding number": number, "value": value, "error": error,
            "verdict": verdict, "criterion": criterion}


def steady_state_verdicts(fits: dict) -> list[dict]:
    """The paper's steady-state claims from fits.json (simulated targets with their errors and
    each model's own steady state)."""
    targets, model_ss = fits["targets"], fits["model_steady_state"]
    rows = [
        _claim(f"{label} (paper {name} ~ {PAPER[f'{model}_{name}']:g})", f"{model.replace('gw', 'G-W')} {name}",
               fits[model][name], fits[model][f"{name}_err"], "", f"fitted value; paper {PAPER[f'{model}_{name}']:g}")
        for model, name, label in (("gw", "beta", "G-W fitted on <nn>_12"),
                                   ("modified", "beta", "modified fitted on <nn>_11, <nn>_12"),
                                   ("modified", "A", "modified fitted on <nn>_11, <nn>_12"))
    ]
    differences = {c: (model_ss["gw"][c] - targets[c]["mean"], targets[c]["sem"]) for c in ("n11", "n22", "n33")}
    worst = max(differences.values(), key=lambda d: d[0] / d[1])  # the least negative in sigma
    verdicts = {_verdict(d, s, -1) for d, s in differences.values()}
    verdict = CONFIRMED if verdicts == {CONFIRMED} else REFUTED if REFUTED in verdicts else UNRESOLVED
    rows.append(_claim("G-W underestimates the diagonal components",
                       "largest of G-W - simulation over <nn>_11, _22, _33", worst[0], worst[1], verdict,
                       "confirmed if all three lie below the simulation by > 2 sem"))
    d22, s22 = model_ss["modified"]["n22"] - targets["n22"]["mean"], targets["n22"]["sem"]
    relative = abs(d22) / abs(targets["n22"]["mean"])
    rows.append(_claim("modified captures <nn>_22", "modified - simulation, <nn>_22", d22, s22,
                       CONFIRMED if relative <= TOLERANCE else REFUTED,
                       f"confirmed if within {TOLERANCE:.0%} of the simulation (here {relative:.1%}; "
                       f"{abs(d22) / s22:.0f} sem)"))
    d33, s33 = model_ss["modified"]["n33"] - targets["n33"]["mean"], targets["n33"]["sem"]
    rows.append(_claim("modified overestimates <nn>_33", "modified - simulation, <nn>_33", d33, s33,
                       _verdict(d33, s33, +1), "confirmed if above the simulation by > 2 sem"))
    return rows


def _angle_mean(table: pd.DataFrame, lo: float, hi: float, column: str, error: str) -> tuple[float, float]:
    rows = table[(table["theta"].abs() >= lo - 1e-9) & (table["theta"].abs() <= hi + 1e-9)]
    if rows.empty:
        return np.nan, np.nan
    return float(rows[column].mean()), float(np.sqrt(np.sum(rows[error] ** 2)) / len(rows))


def rotation_verdicts(recovery: pd.DataFrame, rms: pd.DataFrame, overshoot: pd.DataFrame) -> list[dict]:
    """The paper's shear-rotation claims from the recovery, rms-error and overshoot tables."""
    rows = []
    for baseline, key in (("steady <nn>_12", "steady"), ("theta = 0 continuation", "continuation")):
        table = recovery.assign(difference=recovery["gw_steady"] - recovery[f"sim_{key}"],
                                difference_err=recovery[f"sim_{key}_err"])
        value, error = _angle_mean(table, 45, 135, "difference", "difference_err")
        rows.append(_claim(f"G-W overestimates the effect on <nn>_12 for pi/4 <~ |theta| <~ 3pi/4 "
                           f"(baseline: {baseline})",
                           "recovery strain G-W - simulation, mean over 45-135 deg", value, error,
                           _verdict(value, error, +1), "confirmed if G-W recovers later by > 2 sem"))
    table = recovery.assign(difference=recovery["gw_n23"] - recovery["sim_n23"], difference_err=recovery["sim_n23_err"])
    value, error = _angle_mean(table, 90, 180, "difference", "difference_err")
    rows.append(_claim("G-W underestimates the effect on <nn>_23 for pi/2 <~ |theta| <~ pi (recovers too fast)",
                       "recovery strain of <nn>'_23, G-W - simulation, mean over 90-180 deg", value, error,
                       _verdict(value, error, -1), "confirmed if G-W recovers earlier by > 2 sem"))
    for component in ("n12", "n23"):
        part = rms[rms["component"] == component]
        part = part[np.isfinite(part["ratio"])]  # both models exact (e.g. <nn>'_23 at theta = 0): no ratio
        value, error = ((float(part["ratio"].mean()), float(np.sqrt(np.sum(part["ratio_err"] ** 2)) / len(part)))
                        if len(part) else (np.nan, np.nan))
        rows.append(_claim(f"modified significantly better than G-W on <nn>'_{component[1:]}",
                           "rms error G-W / modified, mean over angles", value, error,
                           _verdict(value - 1.0, error, +1), "confirmed if the ratio exceeds 1 by > 2 errors"))
    near = overshoot[(overshoot["theta"].abs() >= 75 - 1e-9) & (overshoot["theta"].abs() <= 105 + 1e-9)]
    if near.empty:
        return rows
    peak = near.loc[near["modified"].idxmax()]
    model_overshoots = peak["modified"] > TOLERANCE
    for baseline, key in (("steady <nn>_12", "steady"), ("theta = 0 continuation", "continuation")):
        value, error = float(peak[f"sim_{key}"]), float(peak[f"sim_{key}_err"])
        below = _verdict(TOLERANCE - value, error, +1)  # confirmed: the simulation stays below the band
        verdict = (REFUTED if not model_overshoots or below == REFUTED
                   else CONFIRMED if below == CONFIRMED else UNRESOLVED)
        rows.append(_claim(f"modified overshoots <nn>_12 near pi/2, the simulations do not (baseline: {baseline})",
                           f"simulation <nn>'_12 / baseline - 1 around the modified model's peak "
                           f"({peak['modified']:+.2f} at theta = {peak['theta']:g}, strain {peak['modified_strain']:.2f})",
                           value, error, verdict,
                           f"confirmed if the model exceeds {TOLERANCE:.0%} and the simulation, averaged over "
                           f"+-0.25 strain around the model's peak, stays below it by > 2 errors"))
    return rows


def verdict_table(fits: dict, runs: pd.DataFrame, predictions: pd.DataFrame) -> tuple[pd.DataFrame, dict]:
    """All verdicts, and the tables that decide them (recovery, rms, overshoot)."""
    n12_ss = fits["targets"]["n12"]["mean"]
    tables = {"recovery": recovery_table(runs, predictions, n12_ss),
              "rms": rms_error_table(runs, predictions, n12_ss),
              "overshoot": overshoot_table(runs, predictions, n12_ss)}
    rows = steady_state_verdicts(fits) + rotation_verdicts(tables["recovery"], tables["rms"], tables["overshoot"])
    return pd.DataFrame(rows), tables

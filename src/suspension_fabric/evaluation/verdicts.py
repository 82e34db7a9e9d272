"""The paper's steady-state claims, and descriptive tables of the shear-rotation transients.

Both compare the two models of the config's ``verdicts.models``
([`suspension_fabric.evaluation.claims.Compared`][suspension_fabric.evaluation.claims.Compared]: the reference, the
paper's G-W, and the challenger, the paper's modified model); tables name them by role.

The shear-rotation claims are decided per seed in
[`suspension_fabric.evaluation.claims`][suspension_fabric.evaluation.claims] (docs/verdict_statistics.md); this module
keeps

- the steady-state claims, decided from ``fits.json`` (the fitted parameters, the simulated
  steady state with its correlation-aware error, each model's own steady state): "confirmed" /
  "refuted" beyond 2 standard errors on the paper's side / the other side, else "undecided";
- description, on which no verdict rests: per angle, the recovery strain (first strain after
  which a seed-mean curve stays inside a 10% band), the rms errors of the models and their ratio,
  and the challenger's overshoot with the simulation around it, each with a seed-bootstrap
  percentile interval ([`suspension_fabric.analysis.seed_statistics.seed_bootstrap_of_mean`][]).

Inputs: the per-seed rotation table (``rotation_runs.csv``: one row per seed, angle and strain,
components in the rotated paper frame) and the model predictions (``predictions.csv``, pooled
fit). Post-rotation components are normalised by the steady <nn>_12 of startup shear, n12_ss
(< 0), as in the paper's Fig. 2.

Measures
    recovery strain of <nn>'_12: the first strain after which |<nn>'_12 / baseline - 1| stays
    within ``tolerance`` (10%) to the end of the run; of <nn>'_23, after which
    |<nn>'_23 / n12_ss| stays within it; baselines: the startup's steady n12_ss, or (simulation
    only) the theta = 0 continuation of the same seed from the same checkpoint. A run that never
    settles counts as recovering at its last strain (censored; the table says so).
    overshoot of <nn>'_12: a model's max over strain of <nn>'_12 / n12_ss - 1; the simulation's
    mean of <nn>'_12 / baseline - 1 over that strain +- 0.25.
    rms error of a model on a component: over strains, |model - seed mean| / |n12_ss|.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import CONFIRMED, LEVEL, REFUTED, UNDECIDED, seed_bootstrap_of_mean
from suspension_fabric.analysis.tables import TOLERANCE, settle_strain, settle_strains

from .claims import ROLES, Compared

__all__ = [
    "recovery_table",
    "rms_error_table",
    "overshoot_table",
    "steady_state_verdicts",
    "verdict_table",
    "descriptive_tables",
]


def _verdict(value: float, error: float, paper_sign: int) -> str:
    """Verdict for a number whose sign the claim predicts (paper_sign = +1 or -1)."""
    if not np.isfinite(value):
        return UNDECIDED
    z = value / error if error > 0 else (np.inf * np.sign(value) if value != 0 else 0.0)
    if paper_sign * z > 2:
        return CONFIRMED
    if paper_sign * z < -2:
        return REFUTED
    return UNDECIDED


def _bootstrap(row: dict, key: str, statistic, per_seed: dict, level: float, vectorized: bool = False) -> None:
    """row[key], row[key_low], row[key_high]: statistic of the seed-mean curve over all seeds and
    its seed-bootstrap interval (``per_seed``: seed -> curve; ``vectorized``: the statistic takes
    the resampled curves stacked, resamples first)."""
    curves = np.stack([per_seed[s] for s in sorted(per_seed)])
    row[key], row[f"{key}_low"], row[f"{key}_high"] = seed_bootstrap_of_mean(
        statistic, curves, level, vectorized=vectorized
    )


def _curves(runs: pd.DataFrame, theta: float, column: str) -> tuple[np.ndarray, dict]:
    """Strains and {seed: values} of one component at one angle (all seeds on the same strains)."""
    rows = runs[np.isclose(runs["theta"], theta)].sort_values(["seed", "strain"])
    curves = {seed: group[column].to_numpy() for seed, group in rows.groupby("seed")}
    strain = rows[rows["seed"] == rows["seed"].iloc[0]]["strain"].to_numpy()
    if len({len(c) for c in curves.values()}) != 1:
        raise ValueError(f"theta = {theta}: the seeds' {column} series have different lengths")
    return strain, curves


def _model_series(predictions: pd.DataFrame, model: str, theta: float) -> pd.DataFrame:
    rows = predictions[
        (predictions["model"] == model)
        & (predictions["protocol"] == "rotation")
        & np.isclose(predictions["theta"], theta)
    ]
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


def recovery_table(
    runs: pd.DataFrame,
    predictions: pd.DataFrame,
    n12_ss: float,
    compared: dict[str, str],
    tolerance: float = TOLERANCE,
    level: float = LEVEL,
) -> pd.DataFrame:
    """Recovery strains of <nn>'_12 (steady and theta = 0 baselines) and <nn>'_23 per angle:
    simulation (seed-mean curve, with ``_low``/``_high`` its seed-bootstrap interval) and both
    models of ``compared`` ({role: model key}), by role; ``*_settled`` is False where the curve
    never settles within the run (then its last strain is given). Description only: a
    first-crossing strain decides nothing."""
    rows = []
    for theta in sorted(runs["theta"].unique()):
        strain, deviations = _ratio_curves(runs, theta, n12_ss)
        row = {"theta": theta}
        for key, per_seed in deviations.items():
            _bootstrap(
                row,
                f"sim_{key}",
                lambda means: settle_strains(strain, means, tolerance)[0],
                per_seed,
                level,
                vectorized=True,
            )
            row[f"sim_{key}_settled"] = settle_strain(strain, np.mean(list(per_seed.values()), axis=0), tolerance)[1]
        for role, model in compared.items():
            series = _model_series(predictions, model, theta)
            model_strain = series["strain"].to_numpy()
            for key, deviation in (
                ("steady", series["n12"].to_numpy() / n12_ss - 1.0),
                ("n23", series["n23"].to_numpy() / n12_ss),
            ):
                row[f"{role}_{key}"], row[f"{role}_{key}_settled"] = settle_strain(model_strain, deviation, tolerance)
        rows.append(row)
    return pd.DataFrame(rows)


def rms_error_table(
    runs: pd.DataFrame, predictions: pd.DataFrame, n12_ss: float, compared: dict[str, str], level: float = LEVEL
) -> pd.DataFrame:
    """Per angle and component (12, 23): rms |model - seed mean| / |n12_ss| of each model of
    ``compared`` ({role: model key}), by role, and the ratio reference / challenger, with
    seed-bootstrap intervals (``_low``, ``_high``). Description only:
    each rms carries the seed-noise floor (claims.py compares the models by paired differences)."""
    rows = []
    for theta in sorted(runs["theta"].unique()):
        for column in ("n12", "n23"):
            strain, curves = _curves(runs, theta, column)
            models = {role: _model_on(strain, predictions, model, theta, column) for role, model in compared.items()}

            def rms(role, means):  # one value per resampled seed-mean curve (rows of means)
                return np.sqrt(np.mean((models[role] - means) ** 2, axis=-1)) / abs(n12_ss)

            row = {"theta": theta, "component": column}
            for role in ROLES:
                _bootstrap(row, f"{role}_rms", lambda means, r=role: rms(r, means), curves, level, vectorized=True)
            with np.errstate(divide="ignore", invalid="ignore"):  # both models exact: no ratio (nan)
                _bootstrap(
                    row,
                    "ratio",
                    lambda means: rms("reference", means) / rms("challenger", means),
                    curves,
                    level,
                    vectorized=True,
                )
            rows.append(row)
    return pd.DataFrame(rows)


def overshoot_table(
    runs: pd.DataFrame,
    predictions: pd.DataFrame,
    n12_ss: float,
    compared: dict[str, str],
    half_window: float = 0.25,
    level: float = LEVEL,
) -> pd.DataFrame:
    """Per angle: each compared model's largest <nn>'_12 / n12_ss - 1 and the strain where it
    occurs (by role); the simulation's mean of <nn>'_12 / baseline - 1 over the strain of the
    challenger's largest value +- ``half_window`` (seed-mean
    curve, seed-bootstrap interval; steady and theta = 0 baselines). Description only."""
    rows = []
    for theta in sorted(runs["theta"].unique()):
        strain, deviations = _ratio_curves(runs, theta, n12_ss)
        row = {"theta": theta}
        for role, model in compared.items():
            series = _model_series(predictions, model, theta)
            ratio = series["n12"].to_numpy() / n12_ss - 1.0
            row[role], row[f"{role}_strain"] = float(ratio.max()), float(series["strain"].to_numpy()[ratio.argmax()])
        peak = row["challenger_strain"]
        window = (strain >= peak - half_window) & (strain <= peak + half_window)
        for key in ("steady", "continuation"):
            per_seed = deviations[key]
            _bootstrap(row, f"sim_{key}", lambda means: means[:, window].mean(axis=1), per_seed, level, vectorized=True)
        rows.append(row)
    return pd.DataFrame(rows)


def _claim(text: str, number: str, value: float, error: float, verdict: str, criterion: str) -> dict:
    return {
        "text": text,
        "statistic": number,
        "mean": value,
        "low": value - 2 * error,
        "high": value + 2 * error,
        "verdict": verdict,
        "criterion": criterion,
    }


def _fitted_to(entry: dict) -> str:
    return ", ".join(f"<nn>_{name[1:]}" for name in entry["fitted_to"])


def steady_state_verdicts(fits: dict, compared: Compared) -> list[dict]:
    """The paper's steady-state claims from fits.json (simulated targets with their errors and
    each model's own steady state): each compared model's fitted parameters against the ones its
    source printed (where it has them), the reference's diagonal, the challenger's <nn>_22 and
    <nn>_33."""
    targets = fits["targets"]
    entries = {role: fits["models"][model.key] for role, model in compared.by_role.items()}
    rows = [
        _claim(
            f"{model.label} fitted on {_fitted_to(entries[role])} (paper {name} ~ {published:g})",
            f"{model.label} {name}",
            entries[role]["parameters"][name],
            entries[role]["errors"][name],
            "",
            f"fitted value +- 2 jackknife errors over seeds; paper {published:g}",
        )
        for role, model in compared.by_role.items()
        for name, published in (model.published or {}).items()
    ]
    reference, challenger = (entries[role]["steady_state"] for role in ROLES)
    differences = {c: (reference[c] - targets[c]["mean"], targets[c]["sem"]) for c in ("n11", "n22", "n33")}
    worst = max(differences.values(), key=lambda d: d[0] / d[1])  # the least negative in sigma
    verdicts = {_verdict(d, s, -1) for d, s in differences.values()}
    verdict = CONFIRMED if verdicts == {CONFIRMED} else REFUTED if REFUTED in verdicts else UNDECIDED
    name = {role: model.label for role, model in compared.by_role.items()}
    rows.append(
        _claim(
            f"{name['reference']} underestimates the diagonal components",
            f"largest of {name['reference']} - simulation over <nn>_11, _22, _33",
            worst[0],
            worst[1],
            verdict,
            "confirmed if all three lie below the simulation by > 2 sem",
        )
    )
    d22, s22 = challenger["n22"] - targets["n22"]["mean"], targets["n22"]["sem"]
    relative = abs(d22) / abs(targets["n22"]["mean"])
    rows.append(
        _claim(
            f"{name['challenger']} captures <nn>_22",
            f"{name['challenger']} - simulation, <nn>_22",
            d22,
            s22,
            CONFIRMED if relative <= TOLERANCE else REFUTED,
            f"confirmed if within {TOLERANCE:.0%} of the simulation (here {relative:.1%}; {abs(d22) / s22:.0f} sem)",
        )
    )
    d33, s33 = challenger["n33"] - targets["n33"]["mean"], targets["n33"]["sem"]
    rows.append(
        _claim(
            f"{name['challenger']} overestimates <nn>_33",
            f"{name['challenger']} - simulation, <nn>_33",
            d33,
            s33,
            _verdict(d33, s33, +1),
            "confirmed if above the simulation by > 2 sem",
        )
    )
    return [{"claim": f"S{k}", **row} for k, row in enumerate(rows, start=1)]


def verdict_table(fits: dict, rotation_claims: pd.DataFrame, compared: Compared) -> pd.DataFrame:
    """The steady-state claims (S1-S6, +- 2 errors) and the shear-rotation claims decided per seed
    ([`suspension_fabric.evaluation.claims.claim_table`][suspension_fabric.evaluation.claims.claim_table]), in one
    table: claim, text, statistic, angles, mean, low, high, level, verdict, seeds_needed, criterion."""
    steady = pd.DataFrame(steady_state_verdicts(fits, compared)).assign(angles="", level=np.nan, seeds_needed=np.nan)
    rotation = rotation_claims.assign(
        criterion=[
            f"confirmed if the {level:.0%} t-interval over {n} seeds lies above 0, refuted if below"
            for level, n in zip(rotation_claims["level"], rotation_claims["n_seeds"])
        ]
    )
    columns = [
        "claim",
        "text",
        "statistic",
        "angles",
        "mean",
        "low",
        "high",
        "level",
        "verdict",
        "seeds_needed",
        "criterion",
    ]
    return pd.concat([steady[columns], rotation[columns]], ignore_index=True)


def descriptive_tables(
    fits: dict, runs: pd.DataFrame, predictions: pd.DataFrame, compared: Compared, level: float = LEVEL
) -> dict[str, pd.DataFrame]:
    """The recovery, rms-error and overshoot tables of the ``compared`` models (description; no
    verdict rests on them)."""
    n12_ss = fits["targets"]["n12"]["mean"]
    keys = {role: model.key for role, model in compared.by_role.items()}
    return {
        "recovery": recovery_table(runs, predictions, n12_ss, keys, level=level),
        "rms": rms_error_table(runs, predictions, n12_ss, keys, level=level),
        "overshoot": overshoot_table(runs, predictions, n12_ss, keys, level=level),
    }

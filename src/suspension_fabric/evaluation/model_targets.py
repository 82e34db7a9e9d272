"""The targets a refined fabric model must meet, checked for every model of a study's leaderboard.

A refined model must, against the reference model (G-W, fitted on the steady state, every angle
held out by construction):

1. **Held-out error** ([`target_table`][suspension_fabric.evaluation.model_targets.target_table]): on <nn>'_12 and
   <nn>'_23, its held-out mean square error net of the seed-noise floor f at most `TARGET_SHARE` of the reference's. Per
   seed, T = share (E_ref - f) - (E_model - f); met where the t-interval of T over seeds lies above 0
   (f per seed as its jackknife pseudo-value, so the interval carries the floor's own error).
   E is the benchmark's per-seed score
   ([`suspension_fabric.evaluation.model_benchmark.seed_errors`][], units (<nn>_12^ss)^2) and
   f the between-seed variance of the simulated curves
   ([`noise_floor`][suspension_fabric.evaluation.model_targets.noise_floor]), what a perfect model scores on one seed.
2. **No overshoot the simulations lack**
   ([`overshoot_table`][suspension_fabric.evaluation.model_targets.overshoot_table]), claim C6's statistic
   ([`suspension_fabric.evaluation.claims`][suspension_fabric.evaluation.claims]): per seed, averaged over the angles
   75-105 degrees, T6 = 0.25 X12(model) - X12(sim), where X12 = int (r12 - 1) dgamma over the strains where the model's
   r12 = <nn>_12 / <nn>_12^ss (the model's own steady value) exceeds 1, the simulation's r12 normalised by its seed's
   steady value. Met unless T6's interval lies above 0 (C6 decided for the model: it overshoots and the simulations do
   not).
3. **Steady state** ([`steady_rows`][suspension_fabric.evaluation.model_targets.steady_rows]): its steady <nn>_11, _22,
   _33 within 3% and <nn>_12 within 1% of the simulated steady state (`STEADY_TOLERANCE`).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.analysis.components import component_label
from suspension_fabric.analysis.frames import sym_to_vec
from suspension_fabric.analysis.seed_statistics import LEVEL, t_interval, variance_pseudo_values
from suspension_fabric.models import fabric_models

from . import claims
from .model_benchmark import SeedCurves

__all__ = [
    "TARGET_SHARE",
    "STEADY_TOLERANCE",
    "SHEAR_COMPONENTS",
    "noise_floor",
    "noise_floor_per_seed",
    "target_table",
    "overshoot_table",
    "overshoot_sentence",
    "percent",
    "steady_rows",
    "scorecard",
    "found_here",
    "scorecard_markdown",
]

#: The largest share of the reference model's held-out error (net of the noise floor) a refined
#: model may keep.
TARGET_SHARE = 0.5
#: Largest relative difference of the model's steady fabric from the simulated steady state.
STEADY_TOLERANCE = {"n11": 0.03, "n22": 0.03, "n33": 0.03, "n12": 0.01}
#: The components the held-out target is set on.
SHEAR_COMPONENTS = ("n12", "n23")
_COMPONENTS = ("n11", "n22", "n33", "n12", "n13", "n23")


def _scaled_rotation(curves: SeedCurves) -> np.ndarray:
    after = curves.rotation_strains > 0.0
    return sym_to_vec(curves.rotation[:, :, after]) / curves.n12_ss  # (seeds, angles, R, 6)


def noise_floor(curves: SeedCurves) -> np.ndarray:
    """Per component (6,): the between-seed variance (ddof 1) of the simulated curves over
    (0, W] in units of (<nn>_12^ss)^2, averaged over the strains and angles: what a perfect model
    scores on one seed."""
    return np.var(_scaled_rotation(curves), axis=0, ddof=1).mean(axis=(0, 1))


def noise_floor_per_seed(curves: SeedCurves) -> np.ndarray:
    """(seeds, 6): the noise floor as each seed's jackknife pseudo-value
    ([`variance_pseudo_values`][suspension_fabric.analysis.seed_statistics.variance_pseudo_values]); their
    mean is [`noise_floor`][suspension_fabric.evaluation.model_targets.noise_floor], and a seed's error net
    of its value carries the floor's own sampling error into an interval over seeds."""
    return variance_pseudo_values(_scaled_rotation(curves)).mean(axis=(1, 2))


def target_table(
    candidate: np.ndarray, reference: np.ndarray, curves: SeedCurves, level: float = LEVEL
) -> pd.DataFrame:
    """Per component: both models' held-out errors (seeds, 6) net of the noise floor (t-intervals
    over seeds), their paired difference, and the target statistic T = share (E_ref - f) -
    (E_cand - f) per seed, met where its interval lies above 0 (`TARGET_SHARE`); f per seed
    ([`noise_floor_per_seed`][suspension_fabric.evaluation.model_targets.noise_floor_per_seed]), so the
    intervals carry the floor's own error."""
    floors = noise_floor_per_seed(curves)
    floor = floors.mean(axis=0)
    rows = []
    for c, component in enumerate(_COMPONENTS):
        mine, theirs = candidate[:, c] - floors[:, c], reference[:, c] - floors[:, c]
        statistic = t_interval(TARGET_SHARE * theirs - mine, level)
        values = {"candidate": t_interval(mine, level), "reference": t_interval(theirs, level)}
        difference = t_interval(mine - theirs, level)
        rows.append(
            {
                "component": component,
                "floor": floor[c],
                **{f"{name}_net": v.mean for name, v in values.items()},
                **{f"{name}_low": v.low for name, v in values.items()},
                **{f"{name}_high": v.high for name, v in values.items()},
                "difference": difference.mean,
                "difference_low": difference.low,
                "difference_high": difference.high,
                "target_statistic": statistic.mean,
                "target_low": statistic.low,
                "target_high": statistic.high,
                "target_met": bool(statistic.low > 0),
            }
        )
    return pd.DataFrame(rows).assign(level=level, share=TARGET_SHARE)


def seed_steady_n12(curves: SeedCurves, steady_window) -> np.ndarray:
    """Each seed's steady <nn>_12 (seeds,): its startup curve averaged over ``steady_window``
    (the claims' normalisation of r12)."""
    low, high = steady_window
    inside = (curves.startup_strains >= low - 1e-9) & (curves.startup_strains <= high + 1e-9)
    return curves.startup[:, inside, 0, 1].mean(axis=1)


def overshoot_table(
    predicted: np.ndarray, model_n12_ss: float, curves: SeedCurves, steady_window, level: float = LEVEL
) -> dict:
    """Claim C6's statistic for a model's predictions after rotation, ``predicted`` (angles, R, 3,
    3) on the curves' angles and strains, shared by every seed, or (seeds, angles, R, 3, 3), one
    per seed; ``model_n12_ss`` is the model's own steady <nn>_12, each seed's simulated r12 is
    normalised by that seed's ([`seed_steady_n12`][suspension_fabric.evaluation.model_targets.seed_steady_n12]). Returns
    the model's and the simulation's X12 and T6 = 0.25 X12(model) - X12(sim) (seed means over the C6 angles,
    t-intervals) and whether the target holds (T6's interval not above 0); without a C6 angle only "met" (True)."""
    claim = next(c for c in claims.CLAIMS if c.key == "C6")
    angles = claims.claim_angles(claim, curves.thetas)
    out = {"angles": ", ".join(f"{a:g}" for a in angles), "level": level}
    chosen = np.isin(curves.thetas, angles)
    if not chosen.any():
        return {**out, "met": True}
    predicted = np.asarray(predicted, dtype=float)
    if predicted.ndim == 4:
        predicted = np.broadcast_to(predicted, (len(curves.seeds), *predicted.shape))
    model_r12 = predicted[..., 0, 1][:, chosen] / model_n12_ss  # (seeds, angles, R)
    sim_r12 = curves.rotation[..., 0, 1][:, chosen] / seed_steady_n12(curves, steady_window)[:, None, None]
    inside = model_r12 > 1.0 + claims.OVERSHOOT_FLOOR
    strain = curves.rotation_strains
    x_model = claims.overshoot_excess(model_r12, strain, inside).mean(axis=1)
    x_sim = claims.overshoot_excess(sim_r12, strain, inside).mean(axis=1)
    share = claims.EFFECT["overshoot_share"]
    for name, values in (("X12_model", x_model), ("X12_sim", x_sim), ("T6", share * x_model - x_sim)):
        interval = t_interval(values, level)
        out.update({name: interval.mean, f"{name}_low": interval.low, f"{name}_high": interval.high})
    out["met"] = not bool(out["T6_low"] > 0)
    return out


def overshoot_sentence(overshoot: dict) -> str:
    """[`overshoot_table`][suspension_fabric.evaluation.model_targets.overshoot_table]'s result in one sentence, every
    number from it."""
    if "T6" not in overshoot:
        return "No rotation angle of claim C6 was simulated: no overshoot statistic."

    def value(name):
        return _interval(overshoot[name], overshoot[f"{name}_low"], overshoot[f"{name}_high"])

    if not overshoot["met"]:
        verdict = "the model overshoots where the simulations do not (target not met)."
    elif overshoot["T6_high"] < 0:
        verdict = "the simulations overshoot at least a quarter as much as the model (target met)."
    else:
        verdict = "undecided, so no overshoot is shown that the simulations lack (target met)."
    return (
        f"Overshoot of ⟨nn⟩₁₂ after rotations of {overshoot['angles']} degrees (claim C6's statistic, held out, "
        f"{int(round(100 * overshoot['level']))}% t-interval): X12 of the model {value('X12_model')}, of the "
        f"simulations {value('X12_sim')}; T6 = 0.25 X12(model) − X12(sim) = {value('T6')}: {verdict}"
    )


def steady_rows(steady_fabric: np.ndarray, targets: dict) -> list[dict]:
    """The model's steady fabric (3, 3) against the simulated steady components (fits.json's
    ``targets``): relative difference and whether it is within `STEADY_TOLERANCE` (NaN
    fabric: not within)."""
    rows = []
    for component, tolerance in STEADY_TOLERANCE.items():
        i, j = int(component[1]) - 1, int(component[2]) - 1
        simulated = targets[component]["mean"]
        relative = steady_fabric[i, j] / simulated - 1.0
        rows.append(
            {
                "component": component,
                "model": steady_fabric[i, j],
                "simulated": simulated,
                "relative_difference": relative,
                "tolerance": tolerance,
                "within": bool(abs(relative) <= tolerance),
            }
        )
    return rows


def scorecard(
    models: dict,
    held_out: dict,
    curves: SeedCurves,
    phi: float,
    targets: dict,
    steady_window,
    *,
    reference: str,
    level: float = LEVEL,
) -> pd.DataFrame:
    """One row per model and fitting mode of the leaderboard (``held_out``: {(key, mode):
    [`HeldOut`][suspension_fabric.evaluation.model_benchmark.HeldOut]}), the reference model's
    steady fit, the baseline, left out: the three targets with their statistics and whether each
    and all are met."""
    base = held_out[(reference, "steady")].errors
    rows = []
    for (key, mode), scores in held_out.items():
        if (key, mode) == (reference, "steady"):
            continue
        fabric_model = models[key]
        row = {"model": key, "label": fabric_model.label, "mode": mode}
        target = target_table(scores.errors, base, curves, level).set_index("component")
        for component in SHEAR_COMPONENTS:
            for field in ("candidate_net", "candidate_low", "candidate_high", "reference_net"):
                row[f"{component}_{field.replace('candidate_', '')}"] = target.loc[component, field]
            for field in ("target_statistic", "target_low", "target_high", "target_met"):
                row[f"{component}_{field}"] = target.loc[component, field]
        try:
            steady = fabric_models.steady_state(fabric_model, scores.parameters, phi)
        except fabric_models.ModelError as failure:  # no steady state reached from no contacts
            print(f"{key} ({mode}): {failure}")
            steady = np.full((3, 3), np.nan)
        overshoot = overshoot_table(scores.predicted, steady[0, 1], curves, steady_window, level)
        row.update({f"overshoot_{name}": value for name, value in overshoot.items() if name not in ("level",)})
        steady_check = steady_rows(steady, targets)
        row.update({f"steady_{r['component']}_relative": r["relative_difference"] for r in steady_check})
        row["steady_met"] = all(r["within"] for r in steady_check)
        row["all_met"] = bool(
            all(row[f"{c}_target_met"] for c in SHEAR_COMPONENTS) and row["overshoot_met"] and row["steady_met"]
        )
        rows.append(row)
    return pd.DataFrame(rows).assign(level=level, share=TARGET_SHARE)


def _interval(mean, low, high) -> str:
    return f"{mean:.3g} [{low:.3g}, {high:.3g}]"


def percent(value: float) -> str:
    """A signed percentage with two decimals; round-off (below 0.005%) reads 0.00%."""
    return "0.00%" if abs(value) < 5e-5 else f"{value:+.2%}"


def _mark(met: bool) -> str:
    return "met" if met else "not met"


def found_here(specs, models: dict, study: str) -> dict[str, str]:
    """{model key: note} for the model files among ``specs`` (models.fabric entries; ``models``
    the resolved models in the same order) found on ``study`` itself (the file's source study):
    their terms saw every angle scored here."""
    notes = {}
    for spec, key in zip(specs, models):
        if spec.endswith(".json") and json.loads(Path(spec).read_text()).get("source", {}).get("study") == study:
            notes[key] = (
                "found on this study's own runs, its terms chosen and fitted on every angle scored here, so "
                "these rows hold out only the refit of its rate (rule discover_model's score holds out every term)"
            )
    return notes


def scorecard_markdown(table: pd.DataFrame, reference_label: str, notes: dict | None = None) -> str:
    """The scorecard as Markdown (every number from ``table``): the statistics, then the targets met,
    and a closing sentence naming the models that meet every target; ``notes`` ({model key:
    sentence}) are printed under the tables and pointed to where such a model meets every target."""
    notes = notes or {}
    if table.empty:
        return "No model besides the reference is on this study's leaderboard.\n"
    level = int(round(100 * table["level"].iloc[0]))
    share = table["share"].iloc[0]
    tolerances = ", ".join(f"{component_label(c)} {t:.0%}" for c, t in STEADY_TOLERANCE.items())
    angles = table["overshoot_angles"].iloc[0]
    reference = table.iloc[0]
    lines = [
        f"Held-out mean square error net of the seed-noise floor, units (⟨nn⟩₁₂ˢˢ)², mean over seeds "
        f"[{level}% t-interval] ({reference_label}, fitted on the steady state: "
        + "; ".join(f"{component_label(c)} {reference[f'{c}_reference_net']:.3g}" for c in SHEAR_COMPONENTS)
        + f"); T = {share:g} (reference − floor) − (model − floor), the held-out target met where its interval "
        f"lies above 0; T6 = 0.25 X12(model) − X12(sim) at {angles or 'no'} degrees (claim C6's statistic), the "
        f"overshoot target met unless its interval lies above 0; the steady state within {tolerances}.",
        "",
        "| model | fit | ⟨nn⟩′₁₂ | T₁₂ | ⟨nn⟩′₂₃ | T₂₃ | T6 |",
        "|---|---|---|---|---|---|---|",
    ]
    for _, row in table.iterrows():
        cells = [row["label"], row["mode"]]
        for c in SHEAR_COMPONENTS:
            cells.append(_interval(row[f"{c}_net"], row[f"{c}_low"], row[f"{c}_high"]))
            cells.append(_interval(row[f"{c}_target_statistic"], row[f"{c}_target_low"], row[f"{c}_target_high"]))
        finite = "overshoot_T6" in row and np.isfinite(row["overshoot_T6"])
        cells.append(
            _interval(row["overshoot_T6"], row["overshoot_T6_low"], row["overshoot_T6_high"]) if finite else "—"
        )
        lines.append("| " + " | ".join(str(c) for c in cells) + " |")
    lines += [
        "",
        "| model | fit | ⟨nn⟩′₁₂ target | ⟨nn⟩′₂₃ target | no overshoot | steady state (worst component) "
        "| every target |",
        "|---|---|---|---|---|---|---|",
    ]
    for _, row in table.iterrows():
        relative = {c: row[f"steady_{c}_relative"] for c in STEADY_TOLERANCE}
        used = {c: abs(v) / STEADY_TOLERANCE[c] if np.isfinite(v) else np.inf for c, v in relative.items()}
        worst = max(used, key=used.get)
        cells = [
            row["label"],
            row["mode"],
            *(_mark(row[f"{c}_target_met"]) for c in SHEAR_COMPONENTS),
            _mark(row["overshoot_met"]),
            f"{_mark(row['steady_met'])} ({component_label(worst)} {percent(relative[worst])})",
            "**yes**" if row["all_met"] else "no",
        ]
        lines.append("| " + " | ".join(str(c) for c in cells) + " |")
    for key, note in notes.items():
        labels = table.loc[table["model"] == key, "label"]
        if len(labels):
            lines += ["", f"{labels.iloc[0]}: {note}."]
    winners = table[table["all_met"]]
    lines += [
        "",
        "Reading, plainly: "
        + (
            "every target is met by "
            + ", ".join(
                f"{r['label']} ({r['mode']} fit{', see the note above' if r['model'] in notes else ''})"
                for _, r in winners.iterrows()
            )
            + "."
            if len(winners)
            else "no model meets every target."
        ),
    ]
    return "\n".join(lines) + "\n"

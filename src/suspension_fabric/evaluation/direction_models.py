"""Fabric models after a change of flow direction at the points of a flow-curve campaign (the
shear-thickening study): do G-W-type models follow the transient, and does that change across the
thickening transition?

At each point every model of the study is fitted on that point's startup steady state (its
fits.json: every rotation held out by construction) and scored per seed and angle theta != 0 on
<nn>'_12 and <nn>'_23 by the mean square of (model - seed) over (0, W] in units of the point's
(<nn>_12^ss)^2 ([`suspension_fabric.evaluation.model_benchmark.seed_errors`][]), net of the
seed-noise floor (the between-seed variance of the simulated curves, subtracted per seed as its
jackknife pseudo-value: [`suspension_fabric.analysis.seed_statistics.variance_pseudo_values`][]). A
component every model keeps at 0 by the flow's symmetry (<nn>_23 after a reversal) is left out.
The window W is the study's (verdicts.window); the tables repeat the scores at `SENSITIVITY_WINDOWS`
so that a reader sees which verdicts depend on it.

1. **Skill** ([`skill_table`][suspension_fabric.evaluation.direction_models.skill_table]): against
   "instant steady state", the new flow's steady fabric from the change on (the point's own steady
   fabric in the new frame: a jump with no transient). Per seed D = E(instant) - E(model), decided
   where D's t-interval excludes 0 after Holm's adjustment over the window's cells. After a reversal
   the instant jump is far off in the first tenth of a strain, where <nn>'_12 still has its old sign,
   so a model that merely starts turning over earns most of its gain there: a gain says the model
   beats the jump, not that it follows the transient's pace.
2. **Between the points** ([`state_comparison`][suspension_fabric.evaluation.direction_models.state_comparison]):
   each model's net error at every other point minus the first point's (the campaign's order: the
   unthickened stress first). The points share their packings (a packing depends on the seed and the
   particles only), so the difference is taken per seed (paired t-interval), Holm over the window's
   cells; > 0: the model does worse there. A model fitted on the steady state sees the transition
   only through the steady fabric, so a difference here is the simulation's transient changing.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import (
    LEVEL,
    adjusted_p,
    decide_adjusted,
    t_interval,
    t_test_p,
    variance_pseudo_values,
)

from .model_benchmark import SeedCurves, model_curves, seed_errors

__all__ = ["NO_TRANSIENT", "NO_TRANSIENT_LABEL", "SCORED", "SENSITIVITY_WINDOWS", "point_scores", "skill_table",
           "state_comparison"]  # fmt: skip

#: The baseline's key and label: the new flow's steady fabric from the change on.
NO_TRANSIENT = "no_transient"
NO_TRANSIENT_LABEL = "instant steady state"
#: Windows (strain after the change) the scores are repeated at, beside the study's own.
SENSITIVITY_WINDOWS = (0.5, 1.0, 2.0)
#: Scored components: (index in seed_errors' six, name, tensor indices)
SCORED = ((3, "n12", (0, 1)), (5, "n23", (1, 2)))


def point_scores(
    models: Mapping, fitted: Mapping, curves: SeedCurves, phi: float, startup_strain: float, steady_window,
    point: str, windows,
) -> pd.DataFrame:  # fmt: skip
    """Per window W of ``windows`` (strain after the change; the curves must reach the largest),
    seed, angle theta != 0, model (and `NO_TRANSIENT`: the seed-mean fabric over ``steady_window``
    of the startup) and scored component: the error ``error`` over (0, W] and the seed's floor
    ``floor`` (its pseudo-value; the same units). ``fitted``: fits.json's ``models`` section (each
    model's steady-state parameters)."""
    low, high = steady_window
    inside = (curves.startup_strains >= low - 1e-9) & (curves.startup_strains <= high + 1e-9)
    steady = curves.startup[:, inside].mean(axis=(0, 1))
    rows = []
    for theta in curves.thetas:
        if abs(theta) < 1e-9:
            continue
        predictions = {NO_TRANSIENT: np.broadcast_to(steady, (1, len(curves.rotation_strains), 3, 3))}
        for key, model in models.items():
            predictions[key] = model_curves(model, fitted[key]["parameters"], phi, curves, startup_strain, [theta])[1]
        for window in windows:
            keep = curves.rotation_strains <= window + 1e-9
            if curves.rotation_strains[keep][-1] < window - 1e-9:
                raise ValueError(
                    f"{point}: the rotation runs reach strain {curves.rotation_strains[-1]:g}, not {window:g}"
                )
            cut = curves._replace(rotation_strains=curves.rotation_strains[keep], rotation=curves.rotation[:, :, keep])
            ratio = cut.rotation[:, np.isclose(cut.thetas, theta)][:, 0] / cut.n12_ss  # (seeds, R, 3, 3)
            after = cut.rotation_strains > 0.0
            for c, component, (i, j) in SCORED:
                if all(np.abs(p[..., i, j]).max() < 1e-12 for key, p in predictions.items() if key != NO_TRANSIENT):
                    continue  # kept at 0 by the flow's symmetry
                floors = variance_pseudo_values(ratio[:, after, i, j]).mean(axis=1)
                for key, predicted in predictions.items():
                    errors = seed_errors(predicted[:, keep], cut, [theta])[:, c]
                    rows += [
                        {
                            "point": point,
                            "window": float(window),
                            "theta": float(theta),
                            "model": key,
                            "component": component,
                            "seed": int(seed),
                            "error": float(error),
                            "floor": float(floor),
                        }
                        for seed, error, floor in zip(cut.seeds, errors, floors)
                    ]
    return pd.DataFrame(rows)


def _label(labels: Mapping[str, str], model: str) -> str:
    return NO_TRANSIENT_LABEL if model == NO_TRANSIENT else labels.get(model, model)


def _holm_by_window(table: pd.DataFrame) -> pd.DataFrame:
    """``p_holm``: Holm's adjustment of ``p`` over each window's cells (NaN p stays out)."""
    table["p_holm"] = np.nan
    for _, index in table.groupby("window").groups.items():
        table.loc[index, "p_holm"] = adjusted_p(table.loc[index, "p"].to_numpy(dtype=float), "holm")
    return table


def skill_table(scores: pd.DataFrame, labels: Mapping[str, str], level: float = LEVEL) -> pd.DataFrame:
    """Per window, point, angle, component and model: the net error (mean [t-interval] over seeds)
    and D = E(instant steady state) - E(model) per seed with its interval, two-sided p, Holm's p
    over the window's gains and the verdict ("beats the jump" where D is decided above 0, "worse
    than the jump" below, "undecided")."""
    rows = []
    for (window, point, theta, component), block in scores.groupby(
        ["window", "point", "theta", "component"], sort=False
    ):
        wide = block.pivot(index="seed", columns="model", values="error")
        floor = block.drop_duplicates("seed").set_index("seed")["floor"].reindex(wide.index)
        for model in [NO_TRANSIENT, *[m for m in wide.columns if m != NO_TRANSIENT]]:
            net = t_interval(wide[model] - floor, level)
            row = {
                "window": window,
                "point": point,
                "theta": theta,
                "component": component,
                "model": model,
                "label": _label(labels, model),
                "seeds": len(wide),
                "net_error": net.mean,
                "net_low": net.low,
                "net_high": net.high,
                "floor": floor.mean(),
            }
            if model != NO_TRANSIENT:
                gain = wide[NO_TRANSIENT] - wide[model]
                skill = t_interval(gain, level)
                row |= {"skill": skill.mean, "skill_low": skill.low, "skill_high": skill.high, "p": t_test_p(gain)}
            rows.append(row)
    table = _holm_by_window(pd.DataFrame(rows))
    readings = {"confirmed": "beats the jump", "refuted": "worse than the jump"}
    table["verdict"] = [
        np.nan if np.isnan(p) else readings.get(decide_adjusted(gain, adjusted, level), "undecided")
        for gain, p, adjusted in zip(table["skill"], table["p"], table["p_holm"])
    ]
    return table.assign(level=level)


def state_comparison(scores: pd.DataFrame, labels: Mapping[str, str], level: float = LEVEL) -> pd.DataFrame:
    """Per window, model, angle and component: its net error at every point after the first minus
    at the first, per seed over the seeds both points have (they share their packings: paired
    t-interval), the two-sided p and Holm's p over the window's cells."""
    points = list(dict.fromkeys(scores["point"]))
    net = scores.assign(net=scores["error"] - scores["floor"])
    rows = []
    for other in points[1:]:
        keys = ["window", "model", "theta", "component"]
        for (window, model, theta, component), block in net.groupby(keys, sort=False):
            wide = block[block["point"].isin([points[0], other])].pivot(index="seed", columns="point", values="net")
            wide = wide.dropna()
            if len(wide) < 2 or other not in wide or points[0] not in wide:
                continue
            shift = wide[other] - wide[points[0]]
            interval = t_interval(shift, level)
            rows.append(
                {
                    "window": window,
                    "model": model,
                    "label": _label(labels, model),
                    "theta": theta,
                    "component": component,
                    "point": other,
                    "versus": points[0],
                    "seeds": len(shift),
                    "difference": interval.mean,
                    "difference_low": interval.low,
                    "difference_high": interval.high,
                    "p": t_test_p(shift),
                }
            )
    table = pd.DataFrame(rows)
    return (table if table.empty else _holm_by_window(table)).assign(level=level)

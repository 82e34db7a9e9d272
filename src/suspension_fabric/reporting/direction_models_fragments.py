"""Fabric models after a change of flow direction at each stress of a flow-curve campaign as a
Markdown fragment for the docs (rule direction_models, from
[`suspension_fabric.evaluation.direction_models`][suspension_fabric.evaluation.direction_models]), so that no
number of it is typed by hand."""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

from suspension_fabric.evaluation.direction_models import NO_TRANSIENT

from .html_tables import format_interval, format_number, format_value_error
from .leaderboard_fragments import markdown_table

__all__ = ["direction_models_summary", "fits_line"]

_COMPONENTS = {"n12": "⟨nn⟩′₁₂", "n23": "⟨nn⟩′₂₃"}
_KEYS = ["point", "theta", "component", "model"]


def _change(theta: float) -> str:
    return "reversal" if abs(abs(theta) - 180.0) < 1e-9 else f"rotation by {theta:g}°"


def _windows(table: pd.DataFrame, primary: float) -> list[float]:
    """The primary window first, then the others in order."""
    return [primary, *sorted(w for w in table["window"].unique() if w != primary)]


def fits_line(fits: Mapping[str, dict], points: Mapping[str, str], labels: Mapping[str, str]) -> str:
    """What each point's models were fitted on: per point (its label) the steady <nn>_12 with its
    standard error and each model's parameters with their jackknife errors (``fits``: each point's
    fits.json)."""
    parts = []
    for point, fitted in fits.items():
        target = fitted["targets"]["n12"]
        cells = [f"⟨nn⟩₁₂ˢˢ = {format_value_error(target['mean'], target['sem'])}"]
        for key, model in fitted["models"].items():
            values = ", ".join(
                f"{name} = {format_value_error(value, model['errors'][name])}"
                for name, value in model["parameters"].items()
            )
            cells.append(f"{labels.get(key, key)} {values}")
        parts.append(f"{points.get(point, point)}: " + "; ".join(cells))
    return "Fitted on each point's startup steady state: " + ". ".join(parts) + ".\n"


def direction_models_summary(
    skill: pd.DataFrame, comparison: pd.DataFrame, points: Mapping[str, str], window: float, fitted: str = ""
) -> str:
    """The skill table (per stress, change, component and model: net error over the study's window
    ``window``, then the gain over the instant steady state and its verdict at each window) and the
    comparison between the stresses (paired, Holm's p per window), each under a caption saying what
    is scored and how it is decided; ``points``: each point's label (its stress); ``fitted``: a line
    saying what the models were fitted on (`fits_line`), first."""
    percent = f"{100 * skill['level'].iloc[0]:g}%"
    windows = _windows(skill, window)
    by_window = {w: skill[skill["window"] == w].set_index(_KEYS) for w in windows}
    rows = []
    for key, row in by_window[window].iterrows():
        point, theta, component, model = key
        cells = [points.get(point, point), _change(theta), _COMPONENTS[component], row["label"]]
        cells.append(format_interval(row["net_error"], row["net_low"], row["net_high"]))
        for w in windows:
            other = by_window[w].loc[key]
            cells.append(
                "the baseline"
                if model == NO_TRANSIENT
                else f"{format_interval(other['skill'], other['skill_low'], other['skill_high'])} {other['verdict']}"
            )
        rows.append(cells)
    gains = int(by_window[window]["p"].notna().sum())
    parts = [fitted] if fitted else []
    parts += [
        "Each model fitted on the point's own startup steady state (every change of direction held out), scored per "
        f"seed over the strain (0, W] after the change, W = {window:g} (the study's window), in units of the point's "
        f"(⟨nn⟩₁₂ˢˢ)², net of the seed-noise floor: mean over seeds [{percent} t-interval]. Gain: the error of the "
        "instant steady state (the new flow's steady fabric from the change on) minus the model's, per seed, decided "
        f"by Holm's adjustment over each window's {gains} gains; the same at the other windows, to show which "
        "verdicts depend on W.\n",
        markdown_table(
            ["stress", "change", "component", "model", f"net error, W = {window:g}"]
            + [f"gain, W = {w:g}" for w in windows],
            rows,
        ),
    ]
    if not comparison.empty:
        by_window = {
            w: comparison[comparison["window"] == w].set_index(["model", "theta", "component"]) for w in windows
        }
        rows = []
        for key, row in by_window[window].iterrows():
            model, theta, component = key
            stresses = f"{points.get(row['point'], row['point'])} − {points.get(row['versus'], row['versus'])}"
            cells = [row["label"], _change(theta), _COMPONENTS[component], stresses]
            for w in windows:
                other = by_window[w].loc[key]
                interval = format_interval(other["difference"], other["difference_low"], other["difference_high"])
                cells.append(f"{interval} (p {format_number(other['p_holm'], 2)})")
            rows.append(cells)
        parts += [
            "Each model's net error at the second stress minus at the first, per seed (the two stresses share their "
            f"packings: paired t-interval, {percent}; > 0: worse at the second stress), Holm's p over each window's "
            f"{len(by_window[window])} cells:\n",
            markdown_table(["model", "change", "component", "stresses"] + [f"W = {w:g}" for w in windows], rows),
        ]
    return "\n".join(parts)

"""The report page of rule verdicts: the verdict on each of the paper's claims, the choices each
verdict may hinge on, T per angle, the range edges and the recovery strains (description); the
compared models (config verdicts.models) named by their labels."""

from __future__ import annotations

import math
import os
from pathlib import Path

import pandas as pd

from .html_tables import (
    MISSING,
    format_angle,
    format_angles,
    format_interval,
    format_number,
    is_missing,
    write_html_tables,
)

__all__ = [
    "seeds_text",
    "verdicts_display_table",
    "choices_display_table",
    "per_angle_display_table",
    "write_verdicts_page",
]


def seeds_text(seeds) -> str:
    """The seeds an undecided claim would need (seed_statistics.seeds_needed): an integer or "> 10000"."""
    if is_missing(seeds):
        return MISSING
    return f"{int(seeds)}" if math.isfinite(seeds) else "> 10000"


def _cell(mean, low, high, verdict, seeds) -> str:
    needed = f"; {seeds_text(seeds)} seeds would decide" if verdict == "undecided" else ""
    return f"{format_interval(mean, low, high)} {verdict}{needed}"


def verdicts_display_table(verdicts: pd.DataFrame) -> pd.DataFrame:
    """The paper's claims, each with its verdict next to it, then its interval, the seeds that
    would decide it, its angles, decision statistic and criterion (the long texts wrap in their
    cells, so the verdict stays in view in a 1400 px window)."""
    verdict = ["(parameter)" if is_missing(v) or v == "" else str(v) for v in verdicts["verdict"]]
    return pd.DataFrame(
        {
            "": verdicts["claim"],
            "claim of the paper": verdicts["text"],
            "verdict": verdict,
            "T [interval]": [
                format_interval(m, lo, hi) for m, lo, hi in zip(verdicts["mean"], verdicts["low"], verdicts["high"])
            ],
            "seeds that would decide": [
                seeds_text(n) if v == "undecided" else "" for n, v in zip(verdicts["seeds_needed"], verdict)
            ],
            "angles (deg)": [format_angles(a) for a in verdicts["angles"]],
            "decision statistic T (> 0: as the paper says)": verdicts["statistic"],
            "criterion": verdicts["criterion"],
        }
    )


def choices_display_table(choices: pd.DataFrame) -> pd.DataFrame:
    """Claims by rows, with the summary (``robust``: the verdict and the choices it differs under)
    next to the claim, then choices (and comparison datasets) by columns: T [interval] and verdict."""
    cells = choices.assign(
        cell=[
            _cell(*row)
            for row in zip(
                choices["mean"], choices["low"], choices["high"], choices["verdict"], choices["seeds_needed"]
            )
        ]
    )
    wide = cells.pivot(index="claim", columns="choice", values="cell")
    wide = wide.loc[list(dict.fromkeys(choices["claim"])), list(dict.fromkeys(choices["choice"]))]
    robust = choices.drop_duplicates("claim").set_index("claim")["robust"]
    wide.insert(0, "robust", robust)  # the summary next to the claim, in view however many choices follow
    return wide.reset_index()


def per_angle_display_table(per_angle: pd.DataFrame, labels: dict[str, str]) -> pd.DataFrame:
    """T per claim and angle with its interval and verdict, and the seed means behind it (the
    compared models by their ``labels``, {role: label})."""
    return pd.DataFrame(
        {
            "claim": per_angle["claim"],
            "θ (deg)": [format_angle(t) for t in per_angle["theta"]],
            "T [interval]": [
                format_interval(m, lo, hi) for m, lo, hi in zip(per_angle["mean"], per_angle["low"], per_angle["high"])
            ],
            "verdict": per_angle["verdict"],
            "quantity": per_angle["quantity"],
            **{
                name: [format_number(x, 3) for x in per_angle[key]]
                for key, name in (("sim", "simulation"), *labels.items())
                if key in per_angle
            },
        }
    )


def write_verdicts_page(
    verdicts: pd.DataFrame,
    per_angle: pd.DataFrame,
    edges: pd.DataFrame,
    choices: pd.DataFrame,
    recovery: pd.DataFrame,
    labels: dict[str, str],
    path: str | os.PathLike,
) -> Path:
    """The report page of rule verdicts: the verdict table, the choices table, the per-angle and
    range-edge tables, and the recovery strains (description); ``labels``: {role: the compared
    model's label}."""
    level = float(choices["level"].iloc[0])
    recovery_text = pd.DataFrame(
        {
            "θ (deg)": [format_angle(t) for t in recovery["theta"]],
            **{
                label: [
                    format_interval(v, lo, hi)
                    for v, lo, hi in zip(recovery[key], recovery[f"{key}_low"], recovery[f"{key}_high"])
                ]
                for key, label in (
                    ("sim_steady", "simulation, ⟨nn⟩′₁₂ (steady)"),
                    ("sim_continuation", "simulation, ⟨nn⟩′₁₂ (θ = 0)"),
                )
            },
            **{
                f"{label}, ⟨nn⟩′₁₂": [format_number(v, 3) for v in recovery[f"{role}_steady"]]
                for role, label in labels.items()
            },
            "simulation, ⟨nn⟩′₂₃": [
                format_interval(v, lo, hi)
                for v, lo, hi in zip(recovery["sim_n23"], recovery["sim_n23_low"], recovery["sim_n23_high"])
            ],
            **{
                f"{label}, ⟨nn⟩′₂₃": [format_number(v, 3) for v in recovery[f"{role}_n23"]]
                for role, label in labels.items()
            },
        }
    )
    edge_text = edges.assign(
        angles=[format_angles(a) for a in edges["angles"]],
        **{
            "T [interval]": [
                format_interval(m, lo, hi) for m, lo, hi in zip(edges["mean"], edges["low"], edges["high"])
            ]
        },
    )
    return write_html_tables(
        path,
        "The paper's claims (verdicts.csv)",
        [
            (
                "Each claim of the paper, its decision statistic T per seed, the interval over seeds and the verdict",
                verdicts_display_table(verdicts),
                f"Shear-rotation claims (C): T computed on each seed alone (own steady state, fit and predictions), "
                f"averaged over the claim's angles within the seed; {level:.0%} two-sided t-interval over seeds; "
                "confirmed if it lies above 0, refuted if below "
                "(effect sizes built into T: docs/verdict_statistics.md). "
                "Steady-state claims (S): ± 2 standard errors.",
            ),
            (
                "The choices each verdict may hinge on (claims by rows, the summary, then choices by columns)",
                choices_display_table(choices),
                "Each cell: T [interval] and verdict under one change from the primary choices (models from their own "
                "strain-5 state, window 2, steady-state fit, steady baseline); "
                "columns after the study's own choices are "
                "other datasets (config verdicts.comparisons) under the primary choices.",
            ),
            (
                "T per angle",
                per_angle_display_table(per_angle, labels),
                "The seed means of the quantity behind T: D12, E23, X12 (strain units), MSE (in units of (⟨nn⟩₁₂ˢˢ)²), "
                f"O12 the overshoot of {labels['challenger']}.",
            ),
            (
                "The claims' angle ranges moved by one simulated angle at either edge",
                edge_text[["claim", "edges", "angles", "T [interval]", "verdict"]],
                None,
            ),
            (
                "Recovery strain after a rotation (description: no verdict rests on it)",
                recovery_text,
                f"First strain from which ⟨nn⟩′₁₂ stays within 10% of its steady value (steady: startup's ⟨nn⟩₁₂ˢˢ; "
                f"θ = 0: the same seed's continuation) and ⟨nn⟩′₂₃ within 0.1 |⟨nn⟩₁₂ˢˢ| of 0, on the seed-mean curve; "
                f"[{level:.0%} seed-bootstrap percentile interval].",
            ),
        ],
    )

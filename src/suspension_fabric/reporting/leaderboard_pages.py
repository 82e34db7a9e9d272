"""The report pages of the leaderboards: fabric models (leaderboard.csv, model_parameters.csv;
[`suspension_fabric.evaluation.model_benchmark`][suspension_fabric.evaluation.model_benchmark]) and stress relations
(stress_leaderboard.csv;
[`suspension_fabric.evaluation.stress_benchmark`][suspension_fabric.evaluation.stress_benchmark]), on held-out rotation
angles."""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from .html_tables import component_label, format_interval, format_number, format_value_error, write_html_tables

__all__ = [
    "leaderboard_tables",
    "write_leaderboard_page",
    "stress_leaderboard_tables",
    "write_stress_leaderboard_page",
]


def leaderboard_tables(board: pd.DataFrame, parameters: pd.DataFrame) -> tuple[pd.DataFrame, ...]:
    """The leaderboard of [`suspension_fabric.evaluation.model_benchmark.leaderboard`][] as three display
    tables: held-out mean square errors per component, their paired differences from G-W, and the
    in-sample errors with the fitted parameters, k and AIC; one row per model and fitting mode."""
    keys = list(dict.fromkeys(zip(board["model"], board["mode"])))
    reference = [c for c in board.columns if c.startswith("held_out_difference_vs_")]
    held, paired, inside = [], [], []
    for model_key, mode in keys:
        rows = board[(board["model"] == model_key) & (board["mode"] == mode)].set_index("component")
        head = {"Model": rows["label"].iloc[0], "Fit": mode}
        held.append(
            {
                **head,
                **{
                    component_label(c): format_interval(r.held_out_mse, r.held_out_low, r.held_out_high)
                    for c, r in rows.iterrows()
                },
            }
        )
        if reference:
            suffix = reference[0][len("held_out_difference") :]
            paired.append(
                {
                    **head,
                    **{
                        component_label(c): format_interval(
                            r[f"held_out_difference{suffix}"],
                            r[f"held_out_difference_low{suffix}"],
                            r[f"held_out_difference_high{suffix}"],
                        )
                        for c, r in rows.iterrows()
                    },
                }
            )
        mine = parameters[(parameters["model"] == model_key) & (parameters["mode"] == mode)]
        inside.append(
            {
                **head,
                "Parameters": ", ".join(
                    f"{p.parameter} = {format_value_error(p.value, p.error)}" for p in mine.itertuples()
                ),
                "k": int(rows["n_parameters"].iloc[0]),
                **{
                    component_label(c): format_interval(r.in_sample_mse, r.in_sample_low, r.in_sample_high)
                    for c, r in rows.iterrows()
                },
                "AIC": format_number(rows["aic"].iloc[0], 4),
            }
        )
    return pd.DataFrame(held), pd.DataFrame(paired), pd.DataFrame(inside)


def write_leaderboard_page(
    board: pd.DataFrame, parameters: pd.DataFrame, path: str | os.PathLike, level: float
) -> Path:
    """The report page of the fabric-model leaderboard (leaderboard.csv, model_parameters.csv)."""
    held, paired, inside = leaderboard_tables(board, parameters)
    unit = "mean square of (model − seed curve) / ⟨nn⟩₁₂ˢˢ over the strains after the rotation and the angles"
    return write_html_tables(
        path,
        "Fabric models on held-out rotation angles (leaderboard.csv)",
        [
            (
                f"Held-out error per component, seed mean [{level:.0%} t-interval over seeds]",
                held,
                f"{unit}. Fit 'steady': fitted to the steady state only, every angle is held out; 'global': "
                "weighted least squares on the startup curve and the other folds of angles.",
            ),
            (
                f"Held-out error minus that of G-W fitted to the steady state, per seed [{level:.0%} t-interval]",
                paired,
                "< 0: the model predicts the unseen rotations better than the paper's G-W fit (paired per seed).",
            ),
            (
                f"In-sample error, parameters (± jackknife over seeds), k and AIC [{level:.0%} t-interval]",
                inside,
                "AIC = χ² + 2k of the global fit (frames along a curve are correlated: it ranks, it does not weigh "
                "evidence); — for the steady fits, which minimise no curve.",
            ),
        ],
    )


def stress_leaderboard_tables(board: pd.DataFrame, parameters: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The stress-relation leaderboard of [`suspension_fabric.evaluation.stress_benchmark.relation_leaderboard`][]
    as two display tables, one row per relation and mode: the held-out error of eta_r after rotation
    with its paired difference from G-W and the fitted values; the in-sample error and bias of every
    scored quantity."""
    keys = list(dict.fromkeys(zip(board["relation"], board["mode"])))
    reference = [c for c in board.columns if c.startswith("held_out_difference_vs_")]
    held, inside = [], []
    for key, mode in keys:
        rows = board[(board["relation"] == key) & (board["mode"] == mode)].set_index("quantity")
        head = {"Relation": rows["label"].iloc[0], "Fit": mode}
        rotation = rows.loc["eta_r rotation"]
        mine = parameters[(parameters["relation"] == key) & (parameters["mode"] == mode)]
        row = {
            **head,
            "η_r after rotation, held-out angles": format_interval(
                rotation.held_out_mse, rotation.held_out_low, rotation.held_out_high
            ),
        }
        if reference:
            suffix = reference[0][len("held_out_difference") :]
            row["minus G-W"] = format_interval(
                rotation[f"held_out_difference{suffix}"],
                rotation[f"held_out_difference_low{suffix}"],
                rotation[f"held_out_difference_high{suffix}"],
            )
        row["Fitted"] = ", ".join(f"{p.parameter} = {format_value_error(p.value, p.error)}" for p in mine.itertuples())
        row["k"] = int(rows["n_fitted"].iloc[0])
        held.append(row)
        inside.append(
            {
                **head,
                **{
                    quantity: f"{format_interval(r.in_sample_mse, r.in_sample_low, r.in_sample_high)}; "
                    f"bias {format_interval(r.bias, r.bias_low, r.bias_high)}"
                    for quantity, r in rows.iterrows()
                },
            }
        )
    return pd.DataFrame(held), pd.DataFrame(inside)


def write_stress_leaderboard_page(
    board: pd.DataFrame, parameters: pd.DataFrame, path: str | os.PathLike, level: float
) -> Path:
    """The report page of the stress-relation leaderboard (stress_leaderboard.csv, stress_relation_parameters.csv)."""
    held, inside = stress_leaderboard_tables(board, parameters)
    return write_html_tables(
        path,
        "Stress relations on held-out rotation angles (stress_leaderboard.csv)",
        [
            (
                f"Held-out error of η_r after the rotations, seed mean [{level:.0%} t-interval over seeds]",
                held,
                "mean square of (relation on the seed's fabric − the seed's η_r) / η_rˢˢ over the strains after the "
                "rotation and the angles; 'minus G-W' < 0: better than the G-W relation (paired per seed); a_H, a_C "
                "fitted to the steady σ₁₂ parts, shape parameters (± jackknife over seeds) on the other folds.",
            ),
            (
                f"In-sample mean square error and signed bias (relation − simulation) / η_rˢˢ [{level:.0%} t-interval]",
                inside,
                "Steady N1, N2, Pi: at each seed's steady fabric; a relation whose a_H, a_C absorb its shape "
                "at the steady state predicts them the same as G-W.",
            ),
        ],
    )

"""The leaderboards the docs quote, as Markdown fragments from a study's tables, so that no score
of a model is typed by hand (rule summary_fragments writes them; the reference rebuild's test
compares each with its committed copy in ``docs/generated/``).

- [`parameters_table`][suspension_fabric.reporting.leaderboard_fragments.parameters_table]: every
  fabric model's fitted parameters in each fitting mode, ± jackknife over seeds
  (tables/model_parameters.csv).
- [`held_out_table`][suspension_fabric.reporting.leaderboard_fragments.held_out_table]: every
  model's held-out mean square error on the shear components after a rotation, with its paired
  difference from the reference model fitted on the steady state (tables/leaderboard.csv).
- [`stress_table`][suspension_fabric.reporting.leaderboard_fragments.stress_table]: every stress
  relation's fitted values, its held-out error of eta_r after a rotation with the paired difference
  from the first relation, its biases, its error in startup and its steady normal-stress biases
  (tables/stress_leaderboard.csv, stress_relation_parameters.csv).
"""

from __future__ import annotations

import pandas as pd

from .html_tables import component_label, format_interval, format_number, format_value_error, is_missing

__all__ = ["markdown_table", "parameters_table", "held_out_table", "stress_table"]

#: The steady normal stresses a stress relation is scored on, as stress_leaderboard.csv names them.
STEADY_STRESSES = {"N1 steady": "N₁", "N2 steady": "N₂", "Pi steady": "Π"}


def markdown_table(header: list[str], rows: list[list[str]]) -> str:
    """A Markdown table: the header, its rule and one line per row."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def _value(value, error) -> str:
    """value ± error (error to two significant digits), or the value alone to 4 significant
    digits when there is no error (a coefficient fitted exactly)."""
    return format_number(value) if is_missing(error) else format_value_error(value, error)


def _fitted(rows: pd.DataFrame) -> str:
    return ", ".join(f"{r.parameter} = {_value(r.value, r.error)}" for r in rows.itertuples())


def _keys(table: pd.DataFrame, key: str) -> list[tuple[str, str]]:
    return list(dict.fromkeys(zip(table[key], table["mode"])))


def _reference_suffix(board: pd.DataFrame) -> str | None:
    """The suffix of the paired-difference columns (``_vs_gw``), None without them."""
    names = [c for c in board.columns if c.startswith("held_out_difference_vs_")]
    return names[0][len("held_out_difference") :] if names else None


def parameters_table(parameters: pd.DataFrame) -> str:
    """tables/model_parameters.csv: a row per model and fitting mode with its parameters."""
    rows = []
    for model, mode in _keys(parameters, "model"):
        mine = parameters[(parameters["model"] == model) & (parameters["mode"] == mode)]
        rows.append([mine["label"].iloc[0], mode, _fitted(mine)])
    return markdown_table(["model", "fit", "parameters (± jackknife over seeds)"], rows)


def held_out_table(board: pd.DataFrame, components=("n12", "n23")) -> str:
    """tables/leaderboard.csv on ``components``: a row per model and fitting mode, per component
    the held-out mean square error [interval] and its paired difference from the reference model
    fitted on the steady state [interval], left blank on the reference's own row."""
    suffix = _reference_suffix(board)
    reference = suffix[len("_vs_") :] if suffix else None
    header = ["model", "fit"]
    for component in components:
        header.append(component_label(component).replace("⟩", "⟩′"))
        if suffix:
            header.append(f"minus {board.loc[board['model'] == reference, 'label'].iloc[0]}")
    rows = []
    for model, mode in _keys(board, "model"):
        mine = board[(board["model"] == model) & (board["mode"] == mode)].set_index("component")
        row = [mine["label"].iloc[0], mode]
        for component in components:
            r = mine.loc[component]
            row.append(format_interval(r.held_out_mse, r.held_out_low, r.held_out_high))
            if suffix:
                own = (model, mode) == (reference, "steady")
                row.append(
                    ""
                    if own
                    else format_interval(
                        r[f"held_out_difference{suffix}"],
                        r[f"held_out_difference_low{suffix}"],
                        r[f"held_out_difference_high{suffix}"],
                    )
                )
        rows.append(row)
    return markdown_table(header, rows)


def stress_table(board: pd.DataFrame, parameters: pd.DataFrame) -> str:
    """tables/stress_leaderboard.csv and stress_relation_parameters.csv: a row per relation and
    fitting mode: its fitted values; held out, the mean square error of eta_r after the rotations
    [interval] and its paired difference from the first relation (blank on that relation's row);
    the bias of eta_r after the rotations; in sample, the error of eta_r in startup; the biases of
    the steady normal stresses. Every error and bias in the units of the leaderboard."""
    suffix = _reference_suffix(board)
    first = board["relation"].iloc[0]
    header = ["relation", "fit", "fitted", "η_r after a rotation, held-out angles"]
    header += [f"minus {board['label'].iloc[0]}"] if suffix else []
    header += [
        "bias of η_r after a rotation",
        "η_r in startup, in sample",
        "steady bias: " + ", ".join(STEADY_STRESSES.values()),
    ]
    rows = []
    for relation, mode in _keys(board, "relation"):
        mine = board[(board["relation"] == relation) & (board["mode"] == mode)].set_index("quantity")
        fitted = parameters[(parameters["relation"] == relation) & (parameters["mode"] == mode)]
        rotation, startup = mine.loc["eta_r rotation"], mine.loc["eta_r startup"]
        row = [mine["label"].iloc[0], mode, _fitted(fitted)]
        row.append(format_interval(rotation.held_out_mse, rotation.held_out_low, rotation.held_out_high))
        if suffix:
            row.append(
                ""
                if relation == first
                else format_interval(
                    rotation[f"held_out_difference{suffix}"],
                    rotation[f"held_out_difference_low{suffix}"],
                    rotation[f"held_out_difference_high{suffix}"],
                )
            )
        row.append(format_interval(rotation.bias, rotation.bias_low, rotation.bias_high))
        row.append(format_interval(startup.in_sample_mse, startup.in_sample_low, startup.in_sample_high))
        row.append(
            "; ".join(
                f"{name} {format_interval(mine.loc[q, 'bias'], mine.loc[q, 'bias_low'], mine.loc[q, 'bias_high'])}"
                for q, name in STEADY_STRESSES.items()
                if q in mine.index
            )
        )
        rows.append(row)
    return markdown_table(header, rows)

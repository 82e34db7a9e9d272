"""The protocols' results as a Markdown page fragment, written from the tables (never typed): for
each protocol, which fabric model predicts it best and by how much, against G-W, and how the
stress relations do on the simulated fabric.

Rows per protocol: every fabric model in both fitting modes with its mean square error over the
six components (in units of (<nn>_12^ss)^2, mean over seeds and t-interval) and the paired
per-seed difference from G-W's steady fit with its t-interval; then every stress relation's error
of eta_r (in units of (eta_r^ss)^2) and its paired difference from the G-W relation. A difference
whose interval lies wholly below zero is marked "better", wholly above "worse", else "not decided".
"""

from __future__ import annotations

import pandas as pd

from suspension_fabric.models.protocol_benchmark import ALL_COMPONENTS

__all__ = ["summary_markdown", "comparison"]


def comparison(low: float, high: float) -> str:
    """The reading of a difference's interval: better (below 0), worse (above), not decided."""
    if high < 0.0:
        return "better"
    if low > 0.0:
        return "worse"
    return "not decided"


def _interval(mean: float, low: float, high: float) -> str:
    return f"{mean:.3g} [{low:.3g}, {high:.3g}]"


def summary_markdown(board: pd.DataFrame, stress_board: pd.DataFrame, level: float, reference: str = "gw") -> str:
    """The page fragment (module docstring) from protocol_leaderboard.csv and
    protocol_stress_leaderboard.csv."""
    percent = f"{100 * level:g}%"
    fabric = board[board["component"] == ALL_COMPONENTS]
    eta = stress_board[stress_board["quantity"] == "eta_r"]
    lines = []
    for protocol in dict.fromkeys(fabric["protocol"]):
        lines += [
            f"**{protocol}**",
            "",
            f"| model | fitted on | error, six components ({percent}) | minus G-W steady ({percent}) | |",
            "|---|---|--:|--:|---|",
        ]
        for _, row in fabric[fabric["protocol"] == protocol].iterrows():
            shift = (
                row[f"difference_vs_{reference}"],
                row[f"difference_low_vs_{reference}"],
                row[f"difference_high_vs_{reference}"],
            )
            is_reference = row["model"] == reference and row["mode"] == "steady"
            fitted = "startup steady state" if row["mode"] == "steady" else "startup + rotations"
            lines.append(
                f"| {row['label']} | {fitted} | {_interval(row['mse'], row['mse_low'], row['mse_high'])} | "
                + ("reference | |" if is_reference else f"{_interval(*shift)} | {comparison(*shift[1:])} |")
            )
        lines += [
            "",
            f"| stress relation | error of eta_r ({percent}) | minus G-W relation ({percent}) | |",
            "|---|--:|--:|---|",
        ]
        for _, row in eta[eta["protocol"] == protocol].iterrows():
            shift = (
                row[f"difference_vs_{reference}"],
                row[f"difference_low_vs_{reference}"],
                row[f"difference_high_vs_{reference}"],
            )
            lines.append(
                f"| {row['label']} | {_interval(row['mse'], row['mse_low'], row['mse_high'])} | "
                + (
                    "reference | |"
                    if row["relation"] == reference
                    else f"{_interval(*shift)} | {comparison(*shift[1:])} |"
                )
            )
        lines.append("")
    return "\n".join(lines)

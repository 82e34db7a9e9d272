"""The response to a change of flow direction at each steady state of a campaign as a Markdown
fragment for the docs (rule direction_response, from
[`suspension_fabric.evaluation.direction_response`][suspension_fabric.evaluation.direction_response]), so that no
number of it is typed by hand."""

from __future__ import annotations

import pandas as pd

from .html_tables import format_interval, format_number
from .leaderboard_fragments import markdown_table

__all__ = ["direction_response_summary"]

#: How each quantity's response is printed
_QUANTITIES = {
    "eta_r": "η_r, relative change",
    "frictional_fraction": "frictional fraction f, change",
    "Z_touching": "contacts per particle, change",
    "n12": "⟨nn⟩₁₂, change",
}


def direction_response_summary(table: pd.DataFrame, comparisons: pd.DataFrame, level: float) -> str:
    """The cells of the response table (point, angle, quantity, window: mean [t-interval], Holm-adjusted
    p, reading), then the differences between points (paired per seed where the points share their seeds,
    Welch otherwise)."""
    header = ["point", "θ", "quantity", "strain after the change", "mean over seeds", "Holm p", "reading", "seeds"]
    rows = [
        [
            row["label"],
            f"{row['theta']:g}",
            _QUANTITIES[row["quantity"]],
            f"{row['window_low']:g} to {row['window_high']:g}",
            format_interval(row["mean"], row["low"], row["high"]),
            format_number(row["p_holm"], 2),
            row["reading"],
            f"{row['n_seeds']:d}",
        ]
        for _, row in table.iterrows()
    ]
    lines = [
        f"Each rotated run against the run at θ = 0 continued from the same seed's startup, window means, "
        f"mean over seeds [{level:.0%} t-interval]; Holm over the {len(table)} cells:",
        "",
        markdown_table(header, rows),
        "",
    ]
    for _, row in comparisons.iterrows():
        lines.append(
            f"- θ = {row['theta']:g}, {_QUANTITIES[row['quantity']]} over strain {row['window_low']:g} to "
            f"{row['window_high']:g}: {row['first']} minus {row['second']} = "
            f"{format_interval(row['mean'], row['low'], row['high'])} "
            f"({'paired per seed' if row.get('test', 'Welch') == 'paired' else 'Welch'}, {level:.0%})."
        )
    return "\n".join(lines) + "\n"

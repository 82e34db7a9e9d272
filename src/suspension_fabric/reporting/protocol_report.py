"""The protocols' results as a Markdown page fragment, written from the tables (never typed): for
each protocol, which fabric model predicts it best and by how much, against G-W, and how the
stress relations do on the simulated fabric.

Rows per protocol: every fabric model in both fitting modes with its mean square error (in units
of (<nn>_12^ss)^2, mean over seeds and t-interval) over the six components and on the shear
components <nn>_12 and <nn>_23 (the diagonal components, which G-W fitted on the steady state
misses by construction, dominate the six-component mean), each with the paired per-seed
difference from G-W's steady fit and its t-interval; then every stress relation's error of eta_r
(in units of (eta_r^ss)^2) and its paired difference from the G-W relation. A difference whose
interval lies wholly below zero is marked "better", wholly above "worse", else "not decided".
"""

from __future__ import annotations

import pandas as pd

from suspension_fabric.models.protocol_benchmark import ALL_COMPONENTS

__all__ = ["summary_markdown", "comparison", "SHOWN"]


def comparison(low: float, high: float) -> str:
    """The reading of a difference's interval: better (below 0), worse (above), not decided."""
    if high < 0.0:
        return "better"
    if low > 0.0:
        return "worse"
    return "not decided"


def _interval(mean: float, low: float, high: float) -> str:
    return f"{mean:.3g} [{low:.3g}, {high:.3g}]"


#: The fabric scores shown: the mean over the six components, and the two shear components the
#: paper's claims after a rotation are about.
SHOWN = (ALL_COMPONENTS, "n12", "n23")


def _difference(row, reference: str) -> tuple[float, float, float]:
    return tuple(row[f"difference{suffix}_vs_{reference}"] for suffix in ("", "_low", "_high"))


def _cell(row, reference: str, is_reference: bool) -> str:
    """Error [interval]; and, but for the reference, the difference from it [interval] and its reading."""
    error = _interval(row["mse"], row["mse_low"], row["mse_high"])
    if is_reference:
        return f"{error}; reference"
    shift = _difference(row, reference)
    return f"{error}; {_interval(*shift)} {comparison(*shift[1:])}"


def summary_markdown(board: pd.DataFrame, stress_board: pd.DataFrame, level: float, reference: str = "gw") -> str:
    """The page fragment (module docstring) from protocol_leaderboard.csv and
    protocol_stress_leaderboard.csv."""
    percent = f"{100 * level:g}%"
    eta = stress_board[stress_board["quantity"] == "eta_r"]
    lines = [
        f"Each cell: error [{percent} interval]; minus G-W fitted on the steady state [{percent} interval] and "
        "its reading. Fabric errors in units of (<nn>_12^ss)^2, eta_r's in (eta_r^ss)^2.",
        "",
    ]
    for protocol in dict.fromkeys(board["protocol"]):
        mine = board[board["protocol"] == protocol]
        names = {ALL_COMPONENTS: "six components", "n12": "<nn>_12", "n23": "<nn>_23"}
        lines += [
            f"**{protocol}**",
            "",
            "| model | fitted on | " + " | ".join(names[c] for c in SHOWN) + " |",
            "|---|---|" + "---|" * len(SHOWN),
        ]
        for (model, mode), rows in mine.groupby(["model", "mode"], sort=False):
            by_component = rows.set_index("component")
            fitted = "startup steady state" if mode == "steady" else "startup + rotations"
            is_reference = model == reference and mode == "steady"
            cells = [_cell(by_component.loc[c], reference, is_reference) for c in SHOWN]
            lines.append(f"| {rows['label'].iloc[0]} | {fitted} | " + " | ".join(cells) + " |")
        lines += ["", "| stress relation | eta_r |", "|---|---|"]
        for _, row in eta[eta["protocol"] == protocol].iterrows():
            lines.append(f"| {row['label']} | {_cell(row, reference, row['relation'] == reference)} |")
        lines.append("")
    return "\n".join(lines)

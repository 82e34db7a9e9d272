"""The map over the state point as Markdown fragments for the docs, so that no number of the map
is typed by hand: rule campaign_map writes them from the map table
([`suspension_fabric.evaluation.state_map.map_table`][suspension_fabric.evaluation.state_map.map_table]),
and the map's rebuild test compares them with their committed copy in ``docs/generated/``.

- [`map_state_table`][suspension_fabric.reporting.map_fragments.map_state_table]: per point the
  steady eta_r, Pi, Z and <nn>_12, the fitted parameters of the two models the claims compare, and
  the steady-state check.
- [`map_claims_table`][suspension_fabric.reporting.map_fragments.map_claims_table]: per point the
  seed mean and interval of each claim statistic the map reports, with its verdict.
"""

from __future__ import annotations

import pandas as pd

from suspension_fabric.evaluation.state_map import MAP_CLAIMS, fitted_columns

from .html_tables import MISSING, format_interval, is_missing, parameter_label
from .leaderboard_fragments import markdown_table

__all__ = ["MAP_CLAIMS", "holm_count", "map_claims_table", "map_state_table", "map_summary"]

#: Steady quantities of the state table: (column, heading, significant figures)
_STATE = (("eta_r", "eta_r", 3), ("Pi", "Pi", 3), ("Z", "Z", 3), ("n12", "<nn>_12", 3))


def _not_run(table: pd.DataFrame) -> pd.Series:
    """The rows state_map.map_table wrote for points not run (``steady`` = "not run: <reason>")."""
    return table["steady"].astype(str).str.startswith("not run")


def _simulated(table: pd.DataFrame) -> pd.DataFrame:
    return table[~_not_run(table)]


def _point(entry: dict) -> str:
    return f"{entry['phi']:.2f}, {entry['mu']:g}"


def _significant(value: float, digits: int) -> str:
    """``value`` to ``digits`` significant figures, trailing zeros kept (8.30, 120, -0.080)."""
    if is_missing(value):
        return MISSING
    text = f"{value:#.{digits}g}"
    return f"{value:.0f}" if "e" in text else text.rstrip(".")


def map_state_table(table: pd.DataFrame) -> str:
    """The simulated points of the map table (in its order: by mu, then phi) as a Markdown table:
    steady eta_r, Pi, Z and <nn>_12 (3 significant figures), each compared model's fitted
    parameters (4; their jackknife errors are in the map's report page), and the steady-state check."""
    fitted = fitted_columns(table)
    header = ["phi, mu", *(h for _, h, _ in _STATE), *(f"{m} {parameter_label(p)}" for m, p, _, _ in fitted)]
    rows = [
        [
            _point(entry),
            *(_significant(entry[column], digits) for column, _, digits in _STATE),
            *(_significant(entry[column], 4) for _, _, column, _ in fitted),
            entry["steady"],
        ]
        for entry in _simulated(table).to_dict("records")
    ]
    return markdown_table([*header, "steady state"], rows)


def _holm_note(entry: dict, claim: str) -> str:
    """ " (Holm: <verdict>)" where the adjustment over the map's cells changes the cell's verdict."""
    adjusted = entry.get(f"{claim}_verdict_holm")
    if is_missing(adjusted) or adjusted == entry[f"{claim}_verdict"]:
        return ""
    return f" (Holm: {adjusted})"


def holm_count(table: pd.DataFrame, claims=MAP_CLAIMS) -> tuple[int, int]:
    """(verdicts decided at the cells' own level, of them still decided after Holm's adjustment)."""
    decided = kept = 0
    for entry in _simulated(table).to_dict("records"):
        for claim in claims:
            verdict = entry.get(f"{claim}_verdict")
            if isinstance(verdict, str) and verdict in ("confirmed", "refuted"):
                decided += 1
                kept += entry.get(f"{claim}_verdict_holm") == verdict
    return decided, kept


def map_claims_table(table: pd.DataFrame, claims=MAP_CLAIMS) -> str:
    """The simulated points' claim statistics as a Markdown table: per claim the seed mean
    [t-interval] and the verdict, with the verdict Holm's adjustment over the map's cells leaves
    where it differs."""
    header = ["phi, mu", *claims]
    rows = []
    for entry in _simulated(table).to_dict("records"):
        cells = [_point(entry)]
        for claim in claims:
            mean = entry.get(f"{claim}_mean")
            if is_missing(mean):
                cells.append(MISSING)
                continue
            interval = format_interval(mean, entry[f"{claim}_low"], entry[f"{claim}_high"])
            cells.append(f"{interval} {entry[f'{claim}_verdict']}{_holm_note(entry, claim)}")
        rows.append(cells)
    return markdown_table(header, rows)


def map_summary(table: pd.DataFrame, level: float) -> str:
    """Both tables, each under a one-line caption (``level``: the claims' interval level), and
    the points not run with their reason."""
    not_run = table[_not_run(table)]
    parts = [
        "Steady state (mean over seeds) and fits:\n",
        map_state_table(table),
        f"Claim statistics, seed mean [{level:.0%} t-interval over seeds] and verdict:\n",
        map_claims_table(table),
    ]
    decided, kept = holm_count(table)
    if decided:
        parts.append(
            f"The table's cells are read at once: Holm's adjustment of each cell's t-test p-value over all of "
            f"them (family-wise error {1 - level:.0%}) keeps {kept} of the {decided} decided verdicts; a cell it "
            "leaves undecided says so in brackets.\n"
        )
    if len(not_run):
        listed = "; ".join(f"({_point(e)}): {e['steady'][len('not run: ') :]}" for e in not_run.to_dict("records"))
        parts.append(f"Not run: {listed}.\n")
    return "\n".join(parts)

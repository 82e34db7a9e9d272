"""The report page of the map over the state point (map.csv,
[`suspension_fabric.evaluation.state_map`][suspension_fabric.evaluation.state_map])."""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from suspension_fabric.evaluation.state_map import fitted_columns

from .html_tables import MISSING, format_interval, format_value_error, is_missing, parameter_label, write_html_tables

__all__ = ["map_display_table", "write_map_page"]

#: Steady values shown as "value ± error" (column, error column, heading)
_MAP_VALUES = (
    ("Z", "Z_sem", "Z"),
    ("n12", "n12_sem", "<nn>₁₂"),
    ("eta_r", "eta_r_sem", "η_r"),
    ("Pi", "Pi_sem", "Π"),
    ("N1", "N1_sem", "N₁"),
    ("N2", "N2_sem", "N₂"),
)
#: Claims shown per point: the paired model-error statistics
_MAP_CLAIMS = ("C3'", "C4'")


def map_display_table(table: pd.DataFrame) -> pd.DataFrame:
    """The map table (state_map.map_table) as text: state point, engine, steady-state check,
    each value with its error, the paired model-error claims with interval and verdict."""
    rows = []
    fitted = [
        (column, error, f"{model} {parameter_label(name)}") for model, name, column, error in fitted_columns(table)
    ]
    for entry in table.to_dict("records"):  # not itertuples: "C3'_mean" is no identifier
        row = {"φ": f"{entry['phi']:.2f}", "μ": f"{entry['mu']:g}", "steady state": entry["steady"]}
        simulated = not str(entry["steady"]).startswith("not run")
        row["kn, dt"] = f"{entry['kn']:.3g}, {entry['dt']:.3g}" if simulated else MISSING
        for column, error, heading in (*_MAP_VALUES, *fitted):
            row[heading] = format_value_error(entry.get(column), entry.get(error)) if simulated else MISSING
        for claim in _MAP_CLAIMS:
            mean = entry.get(f"{claim}_mean")
            row[claim] = (
                (
                    f"{format_interval(mean, entry.get(f'{claim}_low'), entry.get(f'{claim}_high'))} "
                    f"{entry.get(f'{claim}_verdict')}"
                )
                if simulated and not is_missing(mean)
                else MISSING
            )
        rows.append(row)
    return pd.DataFrame(rows)


def write_map_page(table: pd.DataFrame, path: str | os.PathLike) -> Path:
    """The map over the state point as an HTML page."""
    note = (
        "Steady values: mean over the steady window, ± the standard error from the scatter of the seed "
        "means; fits ± jackknife errors over seeds; claims: seed mean [t-interval] and verdict "
        "(docs/verdict_statistics.md). Steady state: relative drift of <nn>₁₂ and η_r between the halves "
        "of the steady window within ±10% at the 95% level (suspension_fabric.evaluation.state_map)."
    )
    return write_html_tables(path, "Map over the state point", [("Per state point", map_display_table(table), note)])

"""The report page of the steady state of startup shear (steady_state.csv,
[`suspension_fabric.analysis.tables.steady_state`][suspension_fabric.analysis.tables.steady_state])."""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from .html_tables import component_label, format_angle, format_number, format_value_error, write_html_tables

__all__ = ["steady_state_table", "write_steady_state_page"]


def steady_state_table(steady: pd.DataFrame) -> pd.DataFrame:
    """The steady-state table (one row per theta and quantity) for reading: mean ± standard
    error, the between-seed standard error, the autocorrelation strain, frames and seeds.

    The angle column is kept only when the table holds more than one angle; the strain
    window, the same for every row, is left to the caption.
    """
    frame = pd.DataFrame(
        {
            "Angle θ (deg)": [format_angle(t) for t in steady["theta"]],
            "Quantity": [component_label(q) for q in steady["quantity"]],
            "Mean ± s.e.": [format_value_error(m, s) for m, s in zip(steady["mean"], steady["sem"])],
            "s.e. between seeds": [format_number(s, 2) for s in steady["sem_between_seeds"]],
            "Autocorrelation strain": [format_number(t, 2) for t in steady["tau_strain"]],
            "Frames per seed": [str(int(n)) for n in steady["n_frames"]],
            "Seeds": [str(int(n)) for n in steady["n_seeds"]],
        }
    )
    if steady["theta"].nunique() <= 1:
        frame = frame.drop(columns="Angle θ (deg)")
    return frame.reset_index(drop=True)


def write_steady_state_page(steady: pd.DataFrame, path: str | os.PathLike) -> Path:
    """The report page of the steady-state table of
    [`suspension_fabric.analysis.tables.steady_state`][suspension_fabric.analysis.tables.steady_state]."""
    low, high = float(steady["strain_min"].iloc[0]), float(steady["strain_max"].iloc[0])
    return write_html_tables(
        path,
        "Steady state of startup shear (steady_state.csv)",
        [
            (
                f"Simulated steady state over the strain window {low:g} ≤ γ ≤ {high:g}",
                steady_state_table(steady),
                "s.e.: correlation-aware standard error of the seed average (each seed's variance of the mean "
                "from its integrated autocorrelation time); s.e. between seeds: from the scatter of the seed "
                "means, an assumption-free check; autocorrelation strain: the integrated autocorrelation time "
                "in units of strain (mean over seeds); frames per seed: the fewest of any seed.",
            ),
        ],
    )

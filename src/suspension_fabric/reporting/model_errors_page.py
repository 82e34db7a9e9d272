"""The report page of the model-error summary (model_errors_summary.csv,
[`suspension_fabric.evaluation.model_vs_simulation.summarise_errors`][])."""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from .html_tables import PROTOCOL_LABELS, component_label, format_number, write_html_tables

__all__ = ["error_summary_table", "write_error_summary_page"]


def error_summary_table(summary: pd.DataFrame, labels: dict[str, str], significant: int = 3) -> pd.DataFrame:
    """The angle-averaged rms errors (in units of |⟨nn⟩₁₂ˢˢ|) per protocol and quantity for every
    model (``labels``: {key: display name}, else the key), and the ratio of two models' errors
    (a column ``<a>_over_<b>``) when the summary has one."""
    frame = pd.DataFrame(
        {
            "Protocol": [PROTOCOL_LABELS.get(p, p) for p in summary["protocol"]],
            "Quantity": [component_label(c) for c in summary["component"]],
        }
    )
    for column in summary.columns:
        if column.startswith("rms_"):
            key = column[len("rms_") :]
            frame[f"rms error, {labels.get(key, key)}"] = [format_number(x, significant) for x in summary[column]]
    for column in summary.columns:
        first, _, second = column.partition("_over_")
        if second and first in labels and second in labels:
            frame[f"Ratio {labels[first]} / {labels[second]}"] = [
                format_number(x, significant) for x in summary[column]
            ]
    return frame


def write_error_summary_page(summary: pd.DataFrame, labels: dict[str, str], path: str | os.PathLike) -> Path:
    """The report page of the model-error summary (``labels``: {model key: display name})."""
    return write_html_tables(
        path,
        "Model versus simulation (model_errors_summary.csv)",
        [
            (
                "Angle-averaged rms error of the models, in units of |⟨nn⟩₁₂ˢˢ|",
                error_summary_table(summary, labels),
                "rms over the simulated strains of (model − simulation seed mean) / |⟨nn⟩₁₂ˢˢ|, averaged over "
                "the simulated angles; ratio > 1: the second model is closer to the simulation.",
            ),
        ],
    )

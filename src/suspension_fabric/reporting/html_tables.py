"""Self-contained HTML pages of captioned tables, and the number formats of every report page.

The report of Snakemake 9 shows an HTML result inline (in a frame) but offers a CSV or TSV only as a
download, so the numbers a reader wants next to the figures are turned into small HTML pages: one
module per page (``fits_page``, ``steady_state_page``, ``model_errors_page``, ``leaderboard_pages``,
``verdicts_page``, ``stress_page``, ``map_page``), each a DataFrame of strings with human-readable
column names written by [`write_html_tables`][suspension_fabric.reporting.html_tables.write_html_tables]. Uncertain
values are written "value ± error" ([`format_value_error`][suspension_fabric.reporting.html_tables.format_value_error])
or "value [low, high]" ([`format_interval`][suspension_fabric.reporting.html_tables.format_interval]),
angles one way ([`format_angle`][suspension_fabric.reporting.html_tables.format_angle]: "0", "15", "22.5") and
lists as prose ([`format_list`][suspension_fabric.reporting.html_tables.format_list]: "0, 15, 30"), never as
Python writes them ("[0.0, 15.0]"). A page stays readable in a 1400 px window: long text wraps in
its cell, numbers do not, and a table still too wide scrolls sideways in its own box.
"""

from __future__ import annotations

import html
import math
import os
from pathlib import Path

import pandas as pd

from suspension_fabric.analysis.components import component_label  # component_label: re-exported

__all__ = [
    "MISSING",
    "PROTOCOL_LABELS",
    "is_missing",
    "format_number",
    "format_value_error",
    "format_interval",
    "format_angle",
    "format_angles",
    "format_list",
    "component_label",
    "components_label",
    "parameter_label",
    "write_html_tables",
]

#: Shown for a value that does not exist (e.g. an error the fit could not propagate).
MISSING = "—"


PROTOCOL_LABELS = {"startup": "startup shear", "rotation": "shear rotation"}


def is_missing(x) -> bool:
    return x is None or (isinstance(x, float) and math.isnan(x))


def format_number(value, significant: int = 4) -> str:
    """``value`` to ``significant`` significant figures (no exponent between 1e-4 and 1e6)."""
    if is_missing(value):
        return MISSING
    value = float(value) + 0.0  # no "-0"
    if value == 0.0 or not math.isfinite(value):
        return f"{value:g}"
    if 1e-4 <= abs(value) < 1e6:
        decimals = max(significant - 1 - math.floor(math.log10(abs(value))), 0)
        return f"{value:.{decimals}f}"
    return f"{value:.{significant - 1}e}"


def format_value_error(value, error, error_digits: int = 2) -> str:
    """Format as "value ± error": the error to ``error_digits`` significant figures and the
    value rounded to the same decimal place, e.g. (10.7474, 0.18753) -> "10.75 ± 0.19".

    A missing error (None or NaN, as fits.json's null) gives "value ± —", a zero or
    infinite one "value ± 0" / "value ± inf", with the value to 4 significant figures.
    Very large or small numbers share one power of ten: "(1.234 ± 0.056)e-9".
    """
    if is_missing(value):
        return MISSING
    value = float(value)
    if is_missing(error):
        return f"{format_number(value)} ± {MISSING}"
    error = abs(float(error))
    if error == 0.0 or not math.isfinite(error) or not math.isfinite(value):
        return f"{format_number(value)} ± {error:g}"
    exponent = math.floor(math.log10(error))
    decimals = error_digits - 1 - exponent
    # rounding may carry into a new digit (0.0996 -> 0.10): recompute on the rounded error
    rounded = round(error, decimals)
    if rounded > 0 and math.floor(math.log10(rounded)) > exponent:
        decimals -= 1
        rounded = round(error, decimals)
    if decimals < -4 or decimals > 8:  # very large or very small: one shared power of ten
        shared = math.floor(math.log10(max(abs(value), rounded)))
        shown = max(decimals + shared, 0)
        scale = 10.0**shared
        return f"({value / scale:.{shown}f} ± {rounded / scale:.{shown}f})e{shared:+d}"
    shown = max(decimals, 0)
    return f"{round(value, decimals) + 0.0:.{shown}f} ± {rounded:.{shown}f}"


def format_interval(value, low, high, digits: int = 2) -> str:
    """Format as "value [low, high]", all three rounded to the decimal place of the interval's
    width to ``digits`` significant figures, e.g. (0.2791, 0.1434, 0.4148) -> "0.28 [0.14, 0.41]".
    A bound that rounding would turn into 0 or into the other sign keeps ``digits`` significant
    figures of its own, so that the printed interval says on which side of 0 it lies:
    (0.05, -0.0035, 0.11) -> "0.05 [-0.0035, 0.11]". A missing or infinite bound (one seed) gives
    "value [—]"."""
    if is_missing(value):
        return MISSING
    value = float(value)
    if is_missing(low) or is_missing(high) or not (math.isfinite(float(low)) and math.isfinite(float(high))):
        return f"{format_number(value)} [{MISSING}]"
    low, high = float(low), float(high)
    width = high - low
    if width <= 0.0 or not math.isfinite(value):
        return f"{format_number(value)} [{format_number(low)}, {format_number(high)}]"
    decimals = max(digits - 1 - math.floor(math.log10(width)), 0)

    def bound(x: float) -> str:
        rounded = round(x, decimals) + 0.0
        if x != 0.0 and (rounded == 0.0 or (rounded > 0.0) != (x > 0.0)):
            return format_number(x, digits)  # its sign would be lost
        return f"{rounded:.{decimals}f}"

    return f"{round(value, decimals) + 0.0:.{decimals}f} [{bound(low)}, {bound(high)}]"


def format_angle(degrees) -> str:
    """An angle in degrees as written: a whole number of degrees without decimals ("0", "15",
    "105"), any other to the precision it has ("22.5", "7.25"); the same for 15, 15.0 and "15"."""
    if is_missing(degrees) or (isinstance(degrees, str) and not degrees.strip()):
        return MISSING
    degrees = round(float(degrees), 6) + 0.0  # no "-0", no float noise (15.000000000000002)
    return f"{degrees:.0f}" if degrees.is_integer() else f"{degrees:g}"


def format_list(values, format_item=str) -> str:
    """A list as prose, its items joined by ", " ("0, 15, 30"), each written by ``format_item``;
    a string (already a list as text, as the tables store "45, 90, 135") is split on commas first."""
    if isinstance(values, str):
        values = [item.strip() for item in values.strip().strip("[]()").split(",") if item.strip()]
    elif is_missing(values):
        return ""
    return ", ".join(format_item(value) for value in values)


def format_angles(values) -> str:
    """Angles as prose, each by `format_angle`: [0.0, 15.0, 22.5] or "0.0, 15.0, 22.5" -> "0, 15, 22.5"."""
    return format_list(values, format_angle)


#: Model parameters as shown (any other name as it is).
_PARAMETER_LABELS = {"beta": "β", "beta_e": "β_e", "beta_c": "β_c", "A_over_beta": "A/β"}


def parameter_label(name: str) -> str:
    """Display name of a model parameter: "beta" -> "β", "A_over_beta" -> "A/β"."""
    return _PARAMETER_LABELS.get(name, name)


def components_label(names) -> str:
    return ", ".join(component_label(n) for n in names)


_STYLE = """
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, Helvetica, Arial, sans-serif;
       font-size: 14px; color: #1f2328; margin: 1.5em; }
h1 { font-size: 1.25em; margin: 0 0 0.8em 0; }
table { border-collapse: collapse; margin: 0 0 1.8em 0; }
caption { caption-side: top; text-align: left; font-weight: 600; padding-bottom: 0.5em; max-width: 60em; }
div.table { max-width: 100%; overflow-x: auto; margin: 0 0 1.8em 0; }
div.table table { margin: 0; }
th, td { padding: 0.3em 0.9em; text-align: left; vertical-align: top; border-bottom: 1px solid #d0d7de;
         white-space: nowrap; }
thead th { border-bottom: 2px solid #57606a; vertical-align: bottom; white-space: normal; min-width: 4em; }
td.text { white-space: normal; min-width: 10em; max-width: 26em; }
td { font-variant-numeric: tabular-nums; }
tbody tr:nth-child(even) { background: #f6f8fa; }
p.note { color: #57606a; max-width: 60em; margin: -1.2em 0 1.8em 0; }
"""


#: A column whose longest cell is longer than this (and has spaces) is text: it wraps in its cell.
TEXT_CELL = 30


def text_columns(frame: pd.DataFrame) -> list[bool]:
    """For each column: is it text that wraps (a cell longer than TEXT_CELL characters, with
    spaces), rather than numbers and short values kept on one line?"""
    return [any(len(str(v)) > TEXT_CELL and " " in str(v) for v in frame.iloc[:, k]) for k in range(frame.shape[1])]


def _cell_text(value) -> str:
    return "" if is_missing(value) else str(value)


def _table_html(frame: pd.DataFrame, caption: str, note: str | None) -> str:
    head = "".join(f'<th scope="col">{html.escape(str(c))}</th>' for c in frame.columns)
    classes = ['<td class="text">' if text else "<td>" for text in text_columns(frame)]
    body = "\n".join(
        "<tr>" + "".join(f"{td}{html.escape(_cell_text(v))}</td>" for td, v in zip(classes, row)) + "</tr>"
        for row in frame.itertuples(index=False, name=None)
    )
    text = (
        f'<div class="table"><table>\n<caption>{html.escape(caption)}</caption>\n<thead><tr>{head}</tr></thead>\n'
        f"<tbody>\n{body}\n</tbody>\n</table></div>\n"
    )
    if note:
        text += f'<p class="note">{html.escape(note)}</p>\n'
    return text


def write_html_tables(path: str | os.PathLike, title: str, tables) -> Path:
    """Write one self-contained HTML page (inline style, UTF-8) with captioned tables.

    ``tables`` is a sequence of ``(caption, DataFrame)`` or ``(caption, DataFrame, note)``;
    every cell is written as text (HTML-escaped). The file is replaced atomically.
    """
    sections = []
    for entry in tables:
        caption, frame, note = (*entry, None)[:3]
        sections.append(_table_html(frame, caption, note))
    page = (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{html.escape(title)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>\n"
        f"<h1>{html.escape(title)}</h1>\n" + "".join(sections) + "</body>\n</html>\n"
    )
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(page, encoding="utf-8")
    os.replace(tmp, path)
    return path

"""Readable tables of the study's numbers for the Snakemake report.

The report of Snakemake 9 shows an HTML result inline (in a frame) but offers a CSV
or TSV only as a download, so the numbers a reader wants next to the figures are
turned into small self-contained HTML pages here:

* :func:`fit_parameters_table` and :func:`fit_targets_table` -- fits.json
  (:func:`suspension_fabric.models.model_vs_simulation.fit_steady_state`): fitted parameters with their
  1-sigma errors (jackknife over seeds, and the linear propagation of the targets' standard
  errors), and the steady-state targets next to the models' own steady states;
* :func:`steady_state_table` -- the steady-state table of
  :func:`suspension_fabric.analysis.tables.steady_state`;
* :func:`error_summary_table` -- :func:`suspension_fabric.models.model_vs_simulation.summarise_errors`.

Every table is a DataFrame of strings with human-readable column names;
uncertain values are written "value ± error" by :func:`format_value_error`.
:func:`write_html_tables` writes one page with one or more captioned tables, and
:func:`write_fits_page`, :func:`write_steady_state_page` and
:func:`write_error_summary_page` the three pages of the report (rule report_tables).
"""

from __future__ import annotations

import html
import math
import os
from pathlib import Path

import pandas as pd

from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.models.model_vs_simulation import MODEL_NAMES
from suspension_fabric.models.stress_model import SOURCES

__all__ = [
    "format_value_error",
    "format_number",
    "component_label",
    "fit_parameters_table",
    "JACKKNIFE_COLUMN",
    "PROPAGATED_COLUMN",
    "fit_targets_table",
    "fit_settings",
    "steady_state_table",
    "error_summary_table",
    "write_html_tables",
    "write_fits_page",
    "write_steady_state_page",
    "write_error_summary_page",
    "listed_models_table",
    "leaderboard_tables",
    "write_leaderboard_page",
    "stress_leaderboard_tables",
    "write_stress_leaderboard_page",
    "format_interval",
    "viscosity_transient_table",
    "map_display_table",
    "write_map_page",
    "MISSING",
]

#: Shown for a value that does not exist (e.g. an error the fit could not propagate).
MISSING = "—"

_SUBSCRIPT = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")
_PARAMETER_LABELS = {"beta": "β", "A": "A"}
_PROTOCOL_LABELS = {"startup": "startup shear", "rotation": "shear rotation"}


def _is_missing(x) -> bool:
    return x is None or (isinstance(x, float) and math.isnan(x))


def format_number(value, significant: int = 4) -> str:
    """``value`` to ``significant`` significant figures (no exponent between 1e-4 and 1e6)."""
    if _is_missing(value):
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
    if _is_missing(value):
        return MISSING
    value = float(value)
    if _is_missing(error):
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


def component_label(name: str) -> str:
    """Display name of a fabric component or quantity: "n12" -> "⟨nn⟩₁₂", "Z" -> "Z"."""
    if name in COMPONENTS:
        return f"⟨nn⟩{name[1:].translate(_SUBSCRIPT)}"
    return name


def _components_label(names) -> str:
    return ", ".join(component_label(n) for n in names)


#: Columns of :func:`fit_parameters_table` with the parameter ± its two errors.
JACKKNIFE_COLUMN = "Value ± 1σ (jackknife over seeds)"
PROPAGATED_COLUMN = "Value ± 1σ (propagated)"


def _fit_errors(entry: dict, parameter: str, jackknifed: bool):
    """(jackknife, propagated) error of a parameter of fits.json; a fits.json written before the
    jackknife (no ``fit_errors`` key) holds only the propagated error, as ``<parameter>_err``."""
    if not jackknifed:
        return None, entry.get(f"{parameter}_err")
    return entry.get(f"{parameter}_err"), entry.get(f"{parameter}_err_propagated")


def fit_parameters_table(fits: dict) -> pd.DataFrame:
    """One row per fitted parameter: Model, Parameter, the value ± its jackknife error over seeds
    (fits.json ``<parameter>_err``), ± its propagated error (``<parameter>_err_propagated``), and
    the fit targets."""
    jackknifed = "fit_errors" in fits
    rows = []
    for key in MODEL_NAMES:
        entry = fits[key]
        for parameter, label in _PARAMETER_LABELS.items():
            if parameter not in entry:
                continue
            jackknife_error, propagated_error = _fit_errors(entry, parameter, jackknifed)
            rows.append(
                {
                    "Model": MODEL_NAMES[key],
                    "Parameter": label,
                    JACKKNIFE_COLUMN: format_value_error(entry[parameter], jackknife_error),
                    PROPAGATED_COLUMN: format_value_error(entry[parameter], propagated_error),
                    "Fitted to (steady state)": _components_label(entry.get("fitted_to", ())),
                }
            )
    return pd.DataFrame(
        rows, columns=["Model", "Parameter", JACKKNIFE_COLUMN, PROPAGATED_COLUMN, "Fitted to (steady state)"]
    )


def fit_targets_table(fits: dict) -> pd.DataFrame:
    """The simulated steady state (the fit targets, mean ± standard error) per quantity next
    to each model's own steady state with the fitted parameters; "fit target of" names the
    models fitted to that quantity."""
    targets = fits.get("targets", {})
    model_ss = fits.get("model_steady_state", {})
    rows = []
    for name, target in targets.items():
        row = {
            "Quantity": component_label(name),
            "Simulation (mean ± s.e.)": format_value_error(target.get("mean"), target.get("sem")),
        }
        for key, display in MODEL_NAMES.items():
            row[f"{display} steady state"] = format_number(model_ss.get(key, {}).get(name))
        fitted_by = [MODEL_NAMES[key] for key in MODEL_NAMES if name in fits.get(key, {}).get("fitted_to", ())]
        row["Fit target of"] = ", ".join(fitted_by) or MISSING
        rows.append(row)
    columns = [
        "Quantity",
        "Simulation (mean ± s.e.)",
        *(f"{display} steady state" for display in MODEL_NAMES.values()),
        "Fit target of",
    ]
    return pd.DataFrame(rows, columns=columns)


def fit_settings(fits: dict) -> pd.DataFrame:
    """The settings of the fit as a two-column table (Setting, Value): phi, the strain
    window of the steady state, the number of seeds and, if recorded, the study and N."""
    provenance = fits.get("provenance", {})
    rows = [("Volume fraction φ", f"{fits['phi']:g}")]
    if "steady_window" in fits:
        low, high = fits["steady_window"]
        rows.append(("Steady-state strain window", f"{low:g} ≤ γ ≤ {high:g}"))
    if "n_seeds" in fits:
        rows.append(("Seeds (independent packings)", str(fits["n_seeds"])))
    if "N" in provenance:
        rows.append(("Particles N", str(provenance["N"])))
    if "study" in provenance:
        rows.append(("Study", str(provenance["study"])))
    return pd.DataFrame(rows, columns=["Setting", "Value"])


def steady_state_table(steady: pd.DataFrame) -> pd.DataFrame:
    """The steady-state table (one row per theta and quantity) for reading: mean ± standard
    error, the between-seed standard error, the autocorrelation strain, frames and seeds.

    The angle column is kept only when the table holds more than one angle; the strain
    window, the same for every row, is left to the caption.
    """
    frame = pd.DataFrame(
        {
            "Angle θ (deg)": [f"{t:g}" for t in steady["theta"]],
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


def error_summary_table(summary: pd.DataFrame, significant: int = 3, labels: dict | None = None) -> pd.DataFrame:
    """The angle-averaged rms errors of :func:`suspension_fabric.models.model_vs_simulation.summarise_errors`
    (in units of |⟨nn⟩₁₂ˢˢ|) per protocol and quantity for every model (``labels``: {key: display
    name}, default the paper's names, else the key), and the ratio G-W / modified when present."""
    labels = {**MODEL_NAMES, **(labels or {})}
    frame = pd.DataFrame(
        {
            "Protocol": [_PROTOCOL_LABELS.get(p, p) for p in summary["protocol"]],
            "Quantity": [component_label(c) for c in summary["component"]],
        }
    )
    for column in summary.columns:
        if column.startswith("rms_"):
            key = column[len("rms_") :]
            frame[f"rms error, {labels.get(key, key)}"] = [format_number(x, significant) for x in summary[column]]
    if "gw_over_modified" in summary:
        frame["Ratio G-W / modified"] = [format_number(x, significant) for x in summary["gw_over_modified"]]
    return frame


_STYLE = """
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, Helvetica, Arial, sans-serif;
       font-size: 14px; color: #1f2328; margin: 1.5em; }
h1 { font-size: 1.25em; margin: 0 0 0.8em 0; }
table { border-collapse: collapse; margin: 0 0 1.8em 0; }
caption { caption-side: top; text-align: left; font-weight: 600; padding-bottom: 0.5em; max-width: 60em; }
th, td { padding: 0.3em 0.9em; text-align: left; border-bottom: 1px solid #d0d7de; white-space: nowrap; }
thead th { border-bottom: 2px solid #57606a; }
td { font-variant-numeric: tabular-nums; }
tbody tr:nth-child(even) { background: #f6f8fa; }
p.note { color: #57606a; max-width: 60em; margin: -1.2em 0 1.8em 0; }
"""


def _table_html(frame: pd.DataFrame, caption: str, note: str | None) -> str:
    head = "".join(f'<th scope="col">{html.escape(str(c))}</th>' for c in frame.columns)
    body = "\n".join(
        "<tr>" + "".join(f"<td>{html.escape(str(v))}</td>" for v in row) + "</tr>"
        for row in frame.itertuples(index=False, name=None)
    )
    text = (
        f"<table>\n<caption>{html.escape(caption)}</caption>\n<thead><tr>{head}</tr></thead>\n"
        f"<tbody>\n{body}\n</tbody>\n</table>\n"
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


def _fit_errors_note(fits: dict) -> str:
    """The note under the fitted parameters: what the two errors are, and the correlation of
    the modified model's β and A over the leave-one-out fits."""
    note = (
        "1σ errors. Jackknife over seeds: the whole fit repeated with each seed left out, "
        "σ = √((n−1)/n Σᵢ (pᵢ − p̄)²) over the n leave-one-out fits; it includes the covariance of "
        f"the fitted ⟨nn⟩₁₁ and ⟨nn⟩₁₂ across seeds ({MISSING} with one seed). Propagated: linear "
        "propagation of the standard errors of the fit targets, ignoring their covariance "
        f"({MISSING} where a target ± σ/10 leaves the fittable range)."
    )
    if "fit_errors" not in fits:
        return note + " This fits.json predates the jackknife: only the propagated errors exist."
    correlation = fits["modified"].get("beta_A_correlation")
    shown = MISSING + " (fewer than 3 seeds)" if _is_missing(correlation) else format_number(correlation, 3)
    return note + f" Correlation of the modified model's β and A over the leave-one-out fits: {shown}."


def listed_models_table(fits: dict, significant: int = 4) -> pd.DataFrame:
    """Every model of fits.json's ``models`` (models.fabric): its parameters with their jackknife
    errors over seeds and the steady components it is fitted to."""
    rows = []
    for key, entry in fits.get("models", {}).items():
        for name, value in entry["parameters"].items():
            rows.append(
                {
                    "Model": entry["label"],
                    "Key": key,
                    "Parameter": name,
                    "Value": format_number(value, significant),
                    "s.e. (jackknife)": format_number(entry["errors"][name], 2),
                    "Fitted to": ", ".join(component_label(c) for c in entry["fitted_to"]),
                }
            )
    return pd.DataFrame(rows, columns=["Model", "Key", "Parameter", "Value", "s.e. (jackknife)", "Fitted to"])


def write_fits_page(fits: dict, path: str | os.PathLike) -> Path:
    """The report page of fits.json: fitted parameters, fit targets vs model steady states, settings."""
    return write_html_tables(
        path,
        "Model fits (fits.json)",
        [
            ("Fitted model parameters", fit_parameters_table(fits), _fit_errors_note(fits)),
            (
                "Every model of models.fabric fitted to the steady state",
                listed_models_table(fits),
                "Each model's parameters reproduce the simulated steady components it is fitted to; s.e.: "
                "jackknife over seeds of the whole fit.",
            ),
            (
                "Steady state of startup shear: simulation (fit targets) and the fitted models",
                fit_targets_table(fits),
                "Simulation: seed mean over the steady-state strain window with its correlation-aware "
                f"standard error. Models: their own steady state with the fitted parameters ({MISSING}: "
                "not a model output).",
            ),
            ("Fit settings", fit_settings(fits)),
        ],
    )


def write_steady_state_page(steady: pd.DataFrame, path: str | os.PathLike) -> Path:
    """The report page of the steady-state table of :func:`suspension_fabric.analysis.tables.steady_state`."""
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


def leaderboard_tables(board: pd.DataFrame, parameters: pd.DataFrame) -> tuple[pd.DataFrame, ...]:
    """The leaderboard of :func:`suspension_fabric.models.model_benchmark.leaderboard` as three display
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
    """The stress-relation leaderboard of :func:`suspension_fabric.models.stress_benchmark.relation_leaderboard`
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
            "η_r after rotation, held out": format_interval(
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


def write_error_summary_page(summary: pd.DataFrame, path: str | os.PathLike, labels: dict | None = None) -> Path:
    """The report page of the model-error summary
    (:func:`suspension_fabric.models.model_vs_simulation.summarise_errors`)."""
    return write_html_tables(
        path,
        "Model versus simulation (model_errors_summary.csv)",
        [
            (
                "Angle-averaged rms error of the models, in units of |⟨nn⟩₁₂ˢˢ|",
                error_summary_table(summary, labels=labels),
                "rms over the simulated strains of (model − simulation seed mean) / |⟨nn⟩₁₂ˢˢ|, averaged over "
                "the simulated angles; ratio > 1: the modified model is closer to the simulation.",
            ),
        ],
    )


def _seeds_text(seeds) -> str:
    """The seeds an undecided claim would need (seed_statistics.seeds_needed): an integer or "> 10000"."""
    if _is_missing(seeds):
        return MISSING
    return f"{int(seeds)}" if math.isfinite(seeds) else "> 10000"


def _cell(mean, low, high, verdict, seeds) -> str:
    needed = f"; {_seeds_text(seeds)} seeds would decide" if verdict == "undecided" else ""
    return f"{format_interval(mean, low, high)} {verdict}{needed}"


def verdicts_display_table(verdicts: pd.DataFrame) -> pd.DataFrame:
    """The paper's claims, each with its decision statistic, interval and verdict."""
    return pd.DataFrame(
        {
            "": verdicts["claim"],
            "claim of the paper": verdicts["text"],
            "decision statistic T (> 0: as the paper says)": verdicts["statistic"],
            "angles (deg)": verdicts["angles"],
            "T [interval]": [
                format_interval(m, lo, hi) for m, lo, hi in zip(verdicts["mean"], verdicts["low"], verdicts["high"])
            ],
            "verdict": verdicts["verdict"].replace("", "(parameter)"),
            "seeds that would decide": [
                _seeds_text(n) if v == "undecided" else ""
                for n, v in zip(verdicts["seeds_needed"], verdicts["verdict"])
            ],
            "criterion": verdicts["criterion"],
        }
    )


def choices_display_table(choices: pd.DataFrame) -> pd.DataFrame:
    """Claims by rows, choices (and comparison datasets) by columns: T [interval] and verdict."""
    cells = choices.assign(
        cell=[
            _cell(*row)
            for row in zip(
                choices["mean"], choices["low"], choices["high"], choices["verdict"], choices["seeds_needed"]
            )
        ]
    )
    wide = cells.pivot(index="claim", columns="choice", values="cell")
    wide = wide.loc[list(dict.fromkeys(choices["claim"])), list(dict.fromkeys(choices["choice"]))]
    robust = choices.drop_duplicates("claim").set_index("claim")["robust"]
    return wide.assign(robust=robust).reset_index()


def per_angle_display_table(per_angle: pd.DataFrame) -> pd.DataFrame:
    """T per claim and angle with its interval and verdict, and the seed means behind it."""
    return pd.DataFrame(
        {
            "claim": per_angle["claim"],
            "θ (deg)": [format_number(t) for t in per_angle["theta"]],
            "T [interval]": [
                format_interval(m, lo, hi) for m, lo, hi in zip(per_angle["mean"], per_angle["low"], per_angle["high"])
            ],
            "verdict": per_angle["verdict"],
            "quantity": per_angle["quantity"],
            **{
                name: [format_number(x, 3) for x in per_angle[key]]
                for key, name in (("sim", "simulation"), ("gw", "G-W"), ("modified", "modified"))
                if key in per_angle
            },
        }
    )


def write_verdicts_page(
    verdicts: pd.DataFrame,
    per_angle: pd.DataFrame,
    edges: pd.DataFrame,
    choices: pd.DataFrame,
    recovery: pd.DataFrame,
    path: str | os.PathLike,
) -> Path:
    """The report page of rule verdicts: the verdict table, the choices table, the per-angle and
    range-edge tables, and the recovery strains (description)."""
    level = float(choices["level"].iloc[0])
    recovery_text = pd.DataFrame(
        {
            "θ (deg)": [format_number(t) for t in recovery["theta"]],
            **{
                label: [
                    format_interval(v, lo, hi)
                    for v, lo, hi in zip(recovery[key], recovery[f"{key}_low"], recovery[f"{key}_high"])
                ]
                for key, label in (
                    ("sim_steady", "simulation, ⟨nn⟩′₁₂ (steady)"),
                    ("sim_continuation", "simulation, ⟨nn⟩′₁₂ (θ = 0)"),
                )
            },
            "G-W, ⟨nn⟩′₁₂": [format_number(v, 3) for v in recovery["gw_steady"]],
            "modified, ⟨nn⟩′₁₂": [format_number(v, 3) for v in recovery["modified_steady"]],
            "simulation, ⟨nn⟩′₂₃": [
                format_interval(v, lo, hi)
                for v, lo, hi in zip(recovery["sim_n23"], recovery["sim_n23_low"], recovery["sim_n23_high"])
            ],
            "G-W, ⟨nn⟩′₂₃": [format_number(v, 3) for v in recovery["gw_n23"]],
            "modified, ⟨nn⟩′₂₃": [format_number(v, 3) for v in recovery["modified_n23"]],
        }
    )
    edge_text = edges.assign(
        **{
            "T [interval]": [
                format_interval(m, lo, hi) for m, lo, hi in zip(edges["mean"], edges["low"], edges["high"])
            ]
        }
    )
    return write_html_tables(
        path,
        "The paper's claims (verdicts.csv)",
        [
            (
                "Each claim of the paper, its decision statistic T per seed, the interval over seeds and the verdict",
                verdicts_display_table(verdicts),
                f"Shear-rotation claims (C): T computed on each seed alone (own steady state, fit and predictions), "
                f"averaged over the claim's angles within the seed; {level:.0%} two-sided t-interval over seeds; "
                "confirmed if it lies above 0, refuted if below "
                "(effect sizes built into T: docs/verdict_statistics.md). "
                "Steady-state claims (S): ± 2 standard errors.",
            ),
            (
                "The choices each verdict may hinge on (claims by rows, choices by columns)",
                choices_display_table(choices),
                "Each cell: T [interval] and verdict under one change from the primary choices (models from their own "
                "strain-5 state, window 2, steady-state fit, steady baseline); "
                "columns after the study's own choices are "
                "other datasets (config verdicts.comparisons) under the primary choices.",
            ),
            (
                "T per angle",
                per_angle_display_table(per_angle),
                "The seed means of the quantity behind T: D12, E23, X12 (strain units), MSE (in units of (⟨nn⟩₁₂ˢˢ)²), "
                "O12 the modified model's overshoot.",
            ),
            (
                "The claims' angle ranges moved by one simulated angle at either edge",
                edge_text[["claim", "edges", "angles", "T [interval]", "verdict"]],
                None,
            ),
            (
                "Recovery strain after a rotation (description: no verdict rests on it)",
                recovery_text,
                f"First strain from which ⟨nn⟩′₁₂ stays within 10% of its steady value (steady: startup's ⟨nn⟩₁₂ˢˢ; "
                f"θ = 0: the same seed's continuation) and ⟨nn⟩′₂₃ within 0.1 |⟨nn⟩₁₂ˢˢ| of 0, on the seed-mean curve; "
                f"[{level:.0%} seed-bootstrap percentile interval].",
            ),
        ],
    )


_STRESS_QUANTITY_LABELS = {
    "eta_r": "ηᵣ = σ₁₂/η_f γ̇",
    "N1": "N₁",
    "N2": "N₂",
    "Pi": "Π (particle pressure)",
    "total_23": "σ′₂₃",
    "contact_12": "σ₁₂ contact",
    "lubrication_12": "σ₁₂ lubrication",
}


def stress_relation_table(relation: pd.DataFrame) -> pd.DataFrame:
    """The fitted stress-relation coefficients per fabric source and the steady stress they predict."""
    rows = {
        "Fabric source": [SOURCES.get(s, s) for s in relation["source"]],
        "a_H": [format_value_error(v, e) for v, e in zip(relation["a_H"], relation["a_H_err"])],
        "a_C": [format_value_error(v, e) for v, e in zip(relation["a_C"], relation["a_C_err"])],
    }
    for name in ("eta_r", "N1", "N2", "Pi"):
        rows[f"{_STRESS_QUANTITY_LABELS[name]}: relation"] = [
            format_number(v, 3) for v in relation[f"{name}_predicted"]
        ]
        rows[f"{_STRESS_QUANTITY_LABELS[name]}: simulation"] = [
            format_value_error(v, e) for v, e in zip(relation[f"{name}_simulated"], relation[f"{name}_simulated_sem"])
        ]
    return pd.DataFrame(rows)


def stress_error_table(summary: pd.DataFrame, significant: int = 3) -> pd.DataFrame:
    """Angle-averaged rms errors of the stress relation per protocol, quantity and fabric source."""
    frame = pd.DataFrame(
        {
            "Protocol": [_PROTOCOL_LABELS.get(p, p) for p in summary["protocol"]],
            "Quantity": [_STRESS_QUANTITY_LABELS.get(q, q) for q in summary["quantity"]],
        }
    )
    for column in summary.columns:
        if column.startswith("rms_"):
            source = column[len("rms_") :]
            frame[f"rms error, {SOURCES.get(source, source)}"] = [
                format_number(x, significant) for x in summary[column]
            ]
    return frame


def format_interval(value, low, high, digits: int = 2) -> str:
    """Format as "value [low, high]", all three rounded to the decimal place of the interval's
    width to ``digits`` significant figures, e.g. (0.2791, 0.1434, 0.4148) -> "0.28 [0.14, 0.41]".
    A missing or infinite bound (one seed) gives "value [—]"."""
    if _is_missing(value):
        return MISSING
    value = float(value)
    if _is_missing(low) or _is_missing(high) or not (math.isfinite(float(low)) and math.isfinite(float(high))):
        return f"{format_number(value)} [{MISSING}]"
    low, high = float(low), float(high)
    width = high - low
    if width <= 0.0 or not math.isfinite(value):
        return f"{format_number(value)} [{format_number(low)}, {format_number(high)}]"
    decimals = max(digits - 1 - math.floor(math.log10(width)), 0)
    shown = [f"{round(x, decimals) + 0.0:.{decimals}f}" for x in (value, low, high)]
    return f"{shown[0]} [{shown[1]}, {shown[2]}]"


def viscosity_transient_table(transients: pd.DataFrame) -> tuple[pd.DataFrame, str]:
    """The viscosity after a rotation per angle (stress_model.viscosity_transients) and the note
    saying what each interval is: the integrated deficit with its t-interval over seeds, the
    minimum, its strain and the recovery strain with their seed-bootstrap percentile intervals."""
    window, level = float(transients["window"].iloc[0]), float(transients["level"].iloc[0])
    percent = f"{100 * level:g}%"
    table = pd.DataFrame(
        {
            "θ (deg)": [f"{t:g}" for t in transients["theta"]],
            f"deficit ∫₀^{window:g} (1 − ηᵣ/ηᵣˢˢ) dγ [{percent} t-interval]": [
                format_interval(v, lo, hi)
                for v, lo, hi in zip(transients["deficit"], transients["deficit_low"], transients["deficit_high"])
            ],
            "s.e.": [format_number(x, 2) for x in transients["deficit_se"]],
            "seeds": [str(int(n)) for n in transients["n_seeds"]],
            f"min ηᵣ/ηᵣˢˢ [{percent} bootstrap]": [
                format_interval(v, lo, hi)
                for v, lo, hi in zip(transients["minimum"], transients["minimum_low"], transients["minimum_high"])
            ],
            f"at strain [{percent} bootstrap]": [
                format_interval(v, lo, hi)
                for v, lo, hi in zip(
                    transients["strain_at_min"], transients["strain_at_min_low"], transients["strain_at_min_high"]
                )
            ],
            f"recovery strain (10%) [{percent} bootstrap]": [
                format_interval(v, lo, hi) + ("" if ok else " (not recovered: lower bound)")
                for v, lo, hi, ok in zip(
                    transients["recovery_strain"],
                    transients["recovery_strain_low"],
                    transients["recovery_strain_high"],
                    transients["recovery_settled"].astype(bool),
                )
            ],
        }
    )
    note = (
        f"Deficit: per seed, ∫ over the first {window:g} strain after the rotation of 1 − ηᵣ/ηᵣˢˢ, with ηᵣˢˢ "
        "that seed's own steady viscosity (trapezoidal rule on the frames; 0.1 = 10% below steady for one "
        f"strain); seed mean, its standard error and the two-sided {percent} Student t-interval over the "
        "seeds (n − 1 degrees of freedom). Minimum, its strain and the recovery strain (first strain from "
        "which ηᵣ/ηᵣˢˢ stays within 10% of 1): on the seed-mean ηᵣ/ηᵣˢˢ smoothed over "
        f"{format_number(float(transients['smoothing_strain'].iloc[0]))} strain, with the {percent} percentile "
        "interval over bootstrap resamples of whole seeds; description only, no verdict rests on them."
    )
    return table, note


def write_stress_page(
    steady: pd.DataFrame,
    relation: pd.DataFrame,
    summary: pd.DataFrame,
    transients: pd.DataFrame,
    path: str | os.PathLike,
) -> Path:
    """The report page of the stress: its steady state, the fitted G-W stress relation, the
    relation's errors through startup and rotations, and the viscosity after a rotation per angle
    (:func:`viscosity_transient_table`)."""
    shown = steady[
        steady["quantity"].isin(["eta_r", "N1", "N2", "Pi", "contact_12", "lubrication_12", "kinetic_12", "total_23"])
    ]
    low, high = float(steady["strain_min"].iloc[0]), float(steady["strain_max"].iloc[0])
    steady_text = pd.DataFrame(
        {
            "Quantity": [_STRESS_QUANTITY_LABELS.get(q, q) for q in shown["quantity"]],
            "Mean ± s.e. (η_f γ̇)": [format_value_error(m, s) for m, s in zip(shown["mean"], shown["sem"])],
            "s.e. between seeds": [format_number(s, 2) for s in shown["sem_between_seeds"]],
            "Autocorrelation strain": [format_number(t, 2) for t in shown["tau_strain"]],
        }
    )
    transient_text, transient_note = viscosity_transient_table(transients)
    return write_html_tables(
        path,
        "Stress (stress_*.csv)",
        [
            (
                f"Steady stress of startup shear over {low:g} ≤ γ ≤ {high:g}, units η_f γ̇",
                steady_text,
                "ηᵣ includes the solvent (1) and the Einstein term (2.5 φ); Π is the particle pressure of the contact, "
                "lubrication and kinetic parts. Errors as in the fabric's steady-state table.",
            ),
            (
                "G-W stress relation σᵖ/η_f γ̇ = a_H ⟨nnnn⟩:Ê + a_C ⟨nnnn⟩:Ê_c, fitted per fabric source",
                stress_relation_table(relation),
                "a_H from the steady lubrication σ₁₂, a_C from the steady contact σ₁₂ (errors: those of the stress "
                "targets only); the normal stresses and the pressure are then predictions.",
            ),
            ("rms error of the relation, in units of σ₁₂ˢˢ, averaged over angles", stress_error_table(summary)),
            (
                "Viscosity after a rotation per angle: the integrated deficit per seed with its t-interval; the "
                "minimum and the recovery strain as description",
                transient_text,
                transient_note,
            ),
        ],
    )


#: Map columns shown as "value ± error" (column, error column, heading)
_MAP_VALUES = (
    ("Z", "Z_sem", "Z"),
    ("n12", "n12_sem", "<nn>₁₂"),
    ("eta_r", "eta_r_sem", "η_r"),
    ("Pi", "Pi_sem", "Π"),
    ("N1", "N1_sem", "N₁"),
    ("N2", "N2_sem", "N₂"),
    ("gw_beta", "gw_beta_err", "G-W β"),
    ("modified_beta", "modified_beta_err", "modified β"),
    ("modified_A", "modified_A_err", "modified A"),
    ("modified_A_over_beta", "modified_A_over_beta_err", "A/β"),
)
#: Claims shown per point: the paired model-error statistics
_MAP_CLAIMS = ("C3'", "C4'")


def map_display_table(table: pd.DataFrame) -> pd.DataFrame:
    """The map table (state_map.map_table) as text: state point, engine, steady-state check,
    each value with its error, the paired model-error claims with interval and verdict."""
    rows = []
    for point in table.itertuples(index=False):
        entry = point._asdict()
        row = {"φ": f"{entry['phi']:.2f}", "μ": f"{entry['mu']:g}", "steady state": entry["steady"]}
        simulated = not str(entry["steady"]).startswith("not run")
        row["kn, dt"] = f"{entry['kn']:.3g}, {entry['dt']:.3g}" if simulated else MISSING
        for column, error, heading in _MAP_VALUES:
            row[heading] = format_value_error(entry.get(column), entry.get(error)) if simulated else MISSING
        for claim in _MAP_CLAIMS:
            mean = entry.get(f"{claim}_mean")
            row[claim] = (
                (
                    f"{format_interval(mean, entry.get(f'{claim}_low'), entry.get(f'{claim}_high'))} "
                    f"{entry.get(f'{claim}_verdict')}"
                )
                if simulated and not _is_missing(mean)
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
        "of the steady window within ±10% at the 95% level (suspension_fabric.reporting.state_map)."
    )
    return write_html_tables(path, "Map over the state point", [("Per state point", map_display_table(table), note)])

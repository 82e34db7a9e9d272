"""The report page of fits.json (rule report_tables): every model's fitted parameters with their
1-sigma errors (jackknife over seeds, and the linear propagation of the targets' standard errors),
the steady-state targets next to each model's own steady state, and the fit's settings
([`suspension_fabric.evaluation.model_vs_simulation.fit_steady_state`][],
[`suspension_fabric.models.fits_file`][suspension_fabric.models.fits_file])."""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from .html_tables import (
    MISSING,
    component_label,
    components_label,
    format_number,
    format_value_error,
    is_missing,
    parameter_label,
    write_html_tables,
)

__all__ = [
    "JACKKNIFE_COLUMN",
    "PROPAGATED_COLUMN",
    "fit_parameters_table",
    "fit_targets_table",
    "fit_settings",
    "write_fits_page",
]

#: Columns of [`fit_parameters_table`][suspension_fabric.reporting.fits_page.fit_parameters_table] with the parameter ±
#: its two errors.
JACKKNIFE_COLUMN = "Value ± 1σ (jackknife over seeds)"
PROPAGATED_COLUMN = "Value ± 1σ (propagated)"


def fit_parameters_table(fits: dict) -> pd.DataFrame:
    """One row per model of fits.json and fitted parameter: Model (its label), Parameter, the value
    ± its jackknife error over seeds, ± its propagated error, and the fit targets."""
    rows = []
    for entry in fits["models"].values():
        for name, value in entry["parameters"].items():
            rows.append(
                {
                    "Model": entry["label"],
                    "Parameter": parameter_label(name),
                    JACKKNIFE_COLUMN: format_value_error(value, entry["errors"].get(name)),
                    PROPAGATED_COLUMN: format_value_error(value, entry.get("errors_propagated", {}).get(name)),
                    "Fitted to (steady state)": components_label(entry["fitted_to"]),
                }
            )
    return pd.DataFrame(
        rows, columns=["Model", "Parameter", JACKKNIFE_COLUMN, PROPAGATED_COLUMN, "Fitted to (steady state)"]
    )


def fit_targets_table(fits: dict) -> pd.DataFrame:
    """The simulated steady state (the fit targets, mean ± standard error) per quantity next
    to each model's own steady state with the fitted parameters; "fit target of" names the
    models fitted to that quantity."""
    models = fits["models"]
    rows = []
    for name, target in fits["targets"].items():
        row = {
            "Quantity": component_label(name),
            "Simulation (mean ± s.e.)": format_value_error(target.get("mean"), target.get("sem")),
        }
        for entry in models.values():
            row[f"{entry['label']} steady state"] = format_number((entry.get("steady_state") or {}).get(name))
        fitted_by = [entry["label"] for entry in models.values() if name in entry["fitted_to"]]
        row["Fit target of"] = ", ".join(fitted_by) or MISSING
        rows.append(row)
    columns = [
        "Quantity",
        "Simulation (mean ± s.e.)",
        *(f"{entry['label']} steady state" for entry in models.values()),
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


def _fit_errors_note(fits: dict) -> str:
    """The note under the fitted parameters: what the two errors are, and the correlation of each
    model's parameters over the leave-one-out fits."""
    note = (
        "1σ errors. Jackknife over seeds: the whole fit repeated with each seed left out, "
        "σ = √((n−1)/n Σᵢ (pᵢ − p̄)²) over the n leave-one-out fits; it includes the covariance of "
        f"the fitted components across seeds ({MISSING} with one seed). Propagated: linear "
        "propagation of the standard errors of the fit targets, ignoring their covariance "
        f"({MISSING} where a target ± σ/10 leaves the fittable range)."
    )
    if "fit_errors" not in fits:
        return note + " These fits predate the jackknife: only the propagated errors exist."
    shown = [
        f"{entry['label']} {pair.replace(',', ' and ')}: "
        + (MISSING + " (fewer than 3 seeds)" if is_missing(r) else format_number(r, 3))
        for entry in fits["models"].values()
        for pair, r in entry.get("correlations", {}).items()
    ]
    if not shown:
        return note
    return note + " Correlation of the parameters over the leave-one-out fits: " + "; ".join(shown) + "."


def write_fits_page(fits: dict, path: str | os.PathLike) -> Path:
    """The report page of fits.json: fitted parameters, fit targets vs model steady states, settings."""
    return write_html_tables(
        path,
        "Model fits (fits.json)",
        [
            (
                "Every model of models.fabric fitted to the steady state",
                fit_parameters_table(fits),
                _fit_errors_note(fits),
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

"""The report page of the stress (rule report_stress): its steady state, the G-W stress relation
fitted per fabric source, the relation's errors through startup and rotations, and the viscosity
after a rotation per angle."""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from .html_tables import (
    PROTOCOL_LABELS,
    format_angle,
    format_interval,
    format_number,
    format_value_error,
    write_html_tables,
)

__all__ = ["stress_relation_table", "stress_error_table", "viscosity_transient_table", "write_stress_page"]

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
        "Fabric source": list(relation["label"]),
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


def stress_error_table(summary: pd.DataFrame, labels: dict[str, str], significant: int = 3) -> pd.DataFrame:
    """Angle-averaged rms errors of the stress relation per protocol, quantity and fabric source
    (``labels``: {source: display name})."""
    frame = pd.DataFrame(
        {
            "Protocol": [PROTOCOL_LABELS.get(p, p) for p in summary["protocol"]],
            "Quantity": [_STRESS_QUANTITY_LABELS.get(q, q) for q in summary["quantity"]],
        }
    )
    for column in summary.columns:
        if column.startswith("rms_"):
            source = column[len("rms_") :]
            frame[f"rms error, {labels.get(source, source)}"] = [format_number(x, significant) for x in summary[column]]
    return frame


def viscosity_transient_table(transients: pd.DataFrame) -> tuple[pd.DataFrame, str]:
    """The viscosity after a rotation per angle (stress_model.viscosity_transients) and the note
    saying what each interval is: the integrated deficit with its t-interval over seeds, the
    minimum, its strain and the recovery strain with their seed-bootstrap percentile intervals."""
    window, level = float(transients["window"].iloc[0]), float(transients["level"].iloc[0])
    percent = f"{100 * level:g}%"
    table = pd.DataFrame(
        {
            "θ (deg)": [format_angle(t) for t in transients["theta"]],
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
    ([`viscosity_transient_table`][suspension_fabric.reporting.stress_page.viscosity_transient_table])."""
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
            (
                "rms error of the relation, in units of σ₁₂ˢˢ, averaged over angles",
                stress_error_table(summary, dict(zip(relation["source"], relation["label"]))),
            ),
            (
                "Viscosity after a rotation per angle: the integrated deficit per seed with its t-interval; the "
                "minimum and the recovery strain as description",
                transient_text,
                transient_note,
            ),
        ],
    )

"""The flow curves as a Markdown fragment for the docs, so that no number of them is typed by hand:
rule flow_curve writes it from the flow-curve table and the onset stresses
([`suspension_fabric.evaluation.flow_curve`][suspension_fabric.evaluation.flow_curve]); the rebuild test
compares it with its committed copy in ``docs/generated/``."""

from __future__ import annotations

import pandas as pd

from ..evaluation.flow_curve import SLOPE_EFFECT
from .html_tables import MISSING, format_interval, format_number, is_missing
from .leaderboard_fragments import markdown_table

__all__ = ["flow_curve_summary"]

#: The imposed and the measured of rate and stress: (table column, heading, the control that imposes it)
_CONTROLLED = (("rate_ratio", "γ̇/γ̇₀", "rate"), ("sigma", "σ/σ₀", "stress"))
#: The other columns of the fragment's table: (table column, heading)
_COLUMNS = (
    ("eta_r", "η_r"),
    ("frictional_fraction", "frictional fraction f"),
    ("Z_touching", "contacts per particle"),
    ("Pi", "Π"),
)


#: The imposed quantity of each control as printed
_IMPOSED = {"rate": "γ̇/γ̇₀", "stress": "σ/σ₀"}

#: What a thickening exponent can say under each control
_EXPONENT_READING = {
    "stress": "above 1 where the rate falls as the stress rises",
    "rate": "below 1 by construction under rate control",
}

#: The Wyart-Cates parameters as printed
_WYART_CATES = {"A": "A", "phi_J0": "φ_J⁰", "phi_Jmu": "φ_J^μ", "rms_log_residual": "rms residual of ln η_r"}


def flow_curve_summary(
    table: pd.DataFrame,
    onsets: pd.DataFrame,
    differences: pd.DataFrame,
    exponents: pd.DataFrame,
    wyart_cates: pd.DataFrame,
    level: float,
    frictionless: pd.DataFrame | None = None,
    shape: pd.DataFrame | None = None,
) -> str:
    """Per point the rate ratio and the steady sigma/sigma_0, eta_r, frictional fraction, contacts per
    particle and Pi with their t-intervals; then each curve's Wyart-Cates onset stress, its thickening
    exponents between neighbouring rates and its shape (``curve_shape`` rows, if any), and the
    Wyart-Cates viscosity fitted per friction coefficient."""
    header = [
        "φ, μ",
        "imposed",
        *(heading for _, heading, _ in _CONTROLLED),
        *(heading for _, heading in _COLUMNS),
        "seeds",
    ]

    def controlled(row, column, control):  # the imposed value bare, the measured one with its interval
        if row["control"] == control:
            return f"{row[column]:g}"
        return format_interval(row[column], row[f"{column}_low"], row[f"{column}_high"])

    rows = [
        [
            f"{row['phi']:.2f}, {row['mu']:g}",
            row["control"],
            *(controlled(row, column, control) for column, _, control in _CONTROLLED),
            *(format_interval(row[c], row[f"{c}_low"], row[f"{c}_high"]) for c, _ in _COLUMNS),
            f"{row['n_seeds']:d}",
        ]
        for _, row in table.iterrows()
    ]
    lines = [
        f"Steady state over the startup's steady window, mean over seeds [{level:.0%} t-interval]; each point "
        "imposes its rate or its stress and measures the other:",
        "",
        markdown_table(header, rows),
    ]
    for _, onset in onsets.iterrows():
        star = onset["sigma_star"]
        curve = f"φ = {onset['phi']:.2f}, μ = {onset['mu']:g}" + (
            ", stress imposed" if onset["control"] == "stress" else ""
        )
        if is_missing(star):
            lines.append(f"- {curve}: no onset stress (a seed has no point with 0 < f < 1).")
            continue
        spread = (
            f"{format_number(onset['estimate_min'], 3)} to {format_number(onset['estimate_max'], 3)}"
            if not is_missing(onset.get("estimate_min"))
            else MISSING
        )
        lines.append(
            f"- {curve}: σ*/σ₀ = {format_interval(star, onset['low'], onset['high'])} (per-seed slope of "
            f"−ln f against σ₀/σ over {onset['points_per_seed']} points with 0 < f < 1 per seed; "
            f"the per-point estimates −ln f · σ/σ₀ span {spread}){_equal_weights(onset)}."
        )
    for _, row in differences.iterrows():
        lines.append(
            f"- σ*/σ₀ at φ = {row['phi_high']:.2f} minus at φ = {row['phi_low']:.2f} (μ = {row['mu']:g}, imposed "
            f"{row['control']}): {format_interval(row['difference'], row['low'], row['high'])} (Welch over the seeds)."
        )
    for (phi, mu, control), curve in exponents.groupby(["phi", "mu", "control"]):
        secants = "; ".join(
            f"{row['target_low']:g} to {row['target_high']:g}: "
            f"{format_interval(row['exponent'], row['low'], row['high'])}"
            for _, row in curve.iterrows()
        )
        imposed = _IMPOSED[control]
        lines.append(
            f"- φ = {phi:.2f}, μ = {mu:g}: thickening exponent Δln η_r / Δln σ between neighbouring imposed "
            f"{imposed}, per seed ({_EXPONENT_READING[control]}): {secants}."
        )
    shapes = shape if shape is not None else pd.DataFrame(columns=["phi", "mu"])
    for (phi, mu), curve in shapes.groupby(["phi", "mu"]):
        by_statistic = curve.set_index("statistic")
        slope, curvature = by_statistic.loc["slope"], by_statistic.loc["curvature"]
        lines.append(
            f"- φ = {phi:.2f}, μ = {mu:g}: shape over imposed {_IMPOSED[slope['control']]} = "
            f"{slope['targets'].replace(' ', ', ')}, "
            f"per seed with every one of these points ({slope['n_seeds']:d} seeds): slope of ln γ̇ in ln σ "
            f"b = {format_interval(slope['value'], slope['low'], slope['high'], 3)} ({_slope_reading(slope)}); "
            f"quadratic coefficient c = {format_interval(curvature['value'], curvature['low'], curvature['high'], 3)} "
            f"(interval {_side_of_zero(curvature['low'], curvature['high'])})."
        )
    joined = ""
    if frictionless is not None and not frictionless.empty:
        curve_phis = set(table["phi"]) if "phi" in table else set()
        phis = ", ".join(f"{phi:.2f}" for phi in sorted(set(frictionless["phi"]) - curve_phis))
        joined = f" and the frictionless points (μ = 0, f = 0) at φ = {phis}"
    for mu, fit in wyart_cates.groupby("mu"):
        values = ", ".join(
            f"{_WYART_CATES[row['parameter']]} = {format_interval(row['value'], row['low'], row['high'])}"
            for _, row in fit.iterrows()
        )
        lines.append(
            f"- Wyart-Cates viscosity η_r = A (1 − φ/φ_J(f))⁻², φ_J(f) = f φ_J^μ + (1 − f) φ_J⁰, at μ = {mu:g} "
            f"with the measured f, fitted per seed over every point of the curves{joined}: {values}."
        )
    return "\n".join(lines) + "\n"


def _side_of_zero(low: float, high: float) -> str:
    if is_missing(low) or is_missing(high):
        return "not defined"
    return "above 0" if low > 0 else "below 0" if high < 0 else "contains 0"


def _slope_reading(slope: pd.Series) -> str:
    """The slope's interval against 0 and against the effect size named before the fresh runs."""
    side = _side_of_zero(slope["low"], slope["high"])
    if side != "not defined" and -SLOPE_EFFECT < slope["low"] and slope["high"] < SLOPE_EFFECT:
        return f"interval {side}, inside ±{SLOPE_EFFECT:g}: vertical within that"
    return f"interval {side}"


def _equal_weights(onset: pd.Series) -> str:
    """The onset stress with every point weighted alike, if the onset has it."""
    if is_missing(onset.get("sigma_star_equal_weights")):
        return ""
    value = format_interval(onset["sigma_star_equal_weights"], onset["equal_weights_low"], onset["equal_weights_high"])
    difference = format_interval(
        onset["weighting_difference"], onset["weighting_difference_low"], onset["weighting_difference_high"]
    )
    return (
        f"; every point weighted alike (per seed the geometric mean of those estimates): {value}, "
        f"paired per seed minus the fit {difference}"
    )

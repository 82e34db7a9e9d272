"""What a rotation does, per angle, as Markdown fragments for the docs from a study's tables, so
that no per-angle number is typed by hand (rule summary_fragments writes them; the reference
rebuild's test compares each with its committed copy in ``docs/generated/``).

- [`peak_ratios`][suspension_fabric.reporting.rotation_fragments.peak_ratios] and
  [`peak_table`][suspension_fabric.reporting.rotation_fragments.peak_table]: the peak of
  <nn>'_12 / <nn>_12^ss over the first strain after each rotation, the simulation's seed mean
  (tables/rotation_aggregate.csv) against every model's prediction from its steady fit
  (tables/predictions.csv).
- [`viscosity_table`][suspension_fabric.reporting.rotation_fragments.viscosity_table]: the
  viscosity after each rotation (tables/stress_viscosity_transients.csv): the integrated deficit
  decided per seed, and the minimum, its strain and the recovery strain as description.
"""

from __future__ import annotations

import pandas as pd

from suspension_fabric.analysis.tables import TOLERANCE

from .html_tables import format_angle, format_interval
from .leaderboard_fragments import markdown_table

__all__ = ["peak_ratios", "peak_table", "viscosity_table"]

#: Strain tolerance of "within the window" (the strains are multiples of the dump strain).
_EDGE = 1e-9


def peak_ratios(predictions: pd.DataFrame, aggregate: pd.DataFrame, steady_n12: float, window: float) -> pd.DataFrame:
    """Per rotation angle strictly between 0 and 180 degrees, the largest <nn>'_12 / ``steady_n12``
    over the strains (0, ``window``] after the rotation: the column ``simulation`` from the seed-mean
    curve of ``aggregate`` (tables/rotation_aggregate.csv), one column per model key of
    ``predictions`` (tables/predictions.csv, protocol "rotation"). Every curve is divided by the
    same simulated steady <nn>_12; the models fitted on it share it."""
    after = aggregate[(aggregate["strain"] > _EDGE) & (aggregate["strain"] <= window + _EDGE)]
    thetas = sorted(t for t in after["theta"].unique() if 0.0 < t < 180.0)
    table = pd.DataFrame(index=pd.Index(thetas, name="theta"))
    table["simulation"] = [(after.loc[after["theta"] == t, "n12_mean"] / steady_n12).max() for t in thetas]
    rotation = predictions[
        (predictions["protocol"] == "rotation")
        & (predictions["strain"] > _EDGE)
        & (predictions["strain"] <= window + _EDGE)
    ]
    for model, rows in rotation.groupby("model", sort=False):
        table[model] = [(rows.loc[rows["theta"] == t, "n12"] / steady_n12).max() for t in thetas]
    return table


def peak_table(peaks: pd.DataFrame, labels: dict[str, str]) -> str:
    """[`peak_ratios`][suspension_fabric.reporting.rotation_fragments.peak_ratios] as a Markdown
    table: a row per angle, the simulation and then each model (headed by ``labels``, model key ->
    label), to three decimals."""
    columns = list(peaks.columns)
    header = ["θ (deg)", *(labels.get(c, c) for c in columns)]
    rows = [[format_angle(theta), *(f"{row[c]:.3f}" for c in columns)] for theta, row in peaks.iterrows()]
    return markdown_table(header, rows)


def _censored(value, low, high, settled: bool) -> str:
    text = format_interval(value, low, high)
    return text if settled else f"> {text} (not within the run)"


def viscosity_table(transients: pd.DataFrame, tolerance: float = TOLERANCE) -> str:
    """tables/stress_viscosity_transients.csv as a Markdown table, a row per angle: the integrated
    deficit V [t-interval over seeds], then (description, seed-bootstrap intervals) the minimum of
    the smoothed seed-mean eta_r / eta_r^ss, the strain of the minimum and the strain from which
    it stays within ``tolerance`` of steady."""
    level = f"{transients['level'].iloc[0]:.0%}"
    header = [
        "θ (deg)",
        f"deficit V [{level} t-interval]",
        "minimum of η_r/η_rˢˢ",
        "at strain",
        f"within {tolerance:.0%} of steady from strain",
    ]
    rows = [
        [
            format_angle(r.theta),
            format_interval(r.deficit, r.deficit_low, r.deficit_high),
            format_interval(r.minimum, r.minimum_low, r.minimum_high),
            format_interval(r.strain_at_min, r.strain_at_min_low, r.strain_at_min_high),
            _censored(r.recovery_strain, r.recovery_strain_low, r.recovery_strain_high, bool(r.recovery_settled)),
        ]
        for r in transients.sort_values("theta").itertuples()
    ]
    return markdown_table(header, rows)

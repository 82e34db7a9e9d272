"""The viscosity after a rotation as Fig. 4 (e-g) and the stress report page show it: the
integrated deficit with its t-interval, the minimum and the recovery strain with their
seed-bootstrap intervals, read back from the matplotlib artists and the HTML table. The input
is stress_model.viscosity_transients on synthetic per-seed curves, so the columns drawn are the
ones the workflow writes."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest

from suspension_fabric.evaluation import stress_model
from suspension_fabric.reporting import figures, html_tables, stress_page

STRAIN = np.round(np.arange(0.0, 2.0 + 1e-9, 0.05), 10)
THETAS = (0.0, 90.0, 180.0)
ETA_SS = {1: 6.0, 2: 7.0, 3: 8.0}


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def curve(theta: float, seed: int) -> np.ndarray:
    """eta_r/eta_ss,s = 1 - a exp(-g/g0), deeper and slower at larger angles; at 180 deg it never
    comes back within 10% by strain 2 (recovery censored)."""
    amplitude = 0.1 + 0.004 * theta + 0.03 * seed
    g0 = 0.2 + 0.005 * theta
    return 1.0 - amplitude * np.exp(-STRAIN / g0)


def transients(level=0.9, window=1.5) -> pd.DataFrame:
    rows = [
        pd.DataFrame({"seed": seed, "theta": theta, "strain": STRAIN, "eta_r": eta * curve(theta, seed)})
        for theta in THETAS
        for seed, eta in ETA_SS.items()
    ]
    return stress_model.viscosity_transients(pd.concat(rows, ignore_index=True), ETA_SS, window, level)


def rotation_inputs():
    """Minimal rotation aggregate and predictions for the polar panels (a-d)."""
    sim, predicted = [], []
    for theta in THETAS:
        sim.append(
            pd.DataFrame(
                {
                    "theta": theta,
                    "strain": STRAIN,
                    "total_12_mean": 10.0 - theta / 90.0,
                    "total_23_mean": np.sin(np.radians(theta)),
                }
            )
        )
        predicted.append(
            pd.DataFrame(
                {
                    "source": "simulation",
                    "protocol": "rotation",
                    "theta": theta,
                    "strain": STRAIN,
                    "total_12": 9.0,
                    "total_23": 0.0,
                }
            )
        )
    return pd.concat(sim, ignore_index=True), pd.concat(predicted, ignore_index=True)


def bar_segments(ax):
    """(x, low, high) of the vertical error-bar segments in ``ax``."""
    segments = [s for c in ax.collections for s in c.get_segments()]
    return np.array([[s[0, 0], min(s[0, 1], s[1, 1]), max(s[0, 1], s[1, 1])] for s in segments])


def test_transients_table_has_the_deficit_and_the_bootstrap_columns():
    out = transients()
    assert list(out.columns) == [
        "theta",
        "window",
        "deficit",
        "deficit_se",
        "deficit_low",
        "deficit_high",
        "n_seeds",
        "level",
        "minimum",
        "minimum_low",
        "minimum_high",
        "strain_at_min",
        "strain_at_min_low",
        "strain_at_min_high",
        "recovery_strain",
        "recovery_strain_low",
        "recovery_strain_high",
        "recovery_settled",
        "smoothing_strain",
    ]
    for name in ("minimum", "strain_at_min", "recovery_strain"):
        assert (out[f"{name}_low"] <= out[name]).all() and (out[name] <= out[f"{name}_high"]).all()
    assert out["recovery_settled"].tolist() == [True, True, False]


def test_fig4_draws_the_deficit_t_interval_and_the_bootstrap_intervals():
    """(e) deficit markers at the seed means with bars exactly [deficit_low, deficit_high]; (f) the
    minimum and (g) the recovery strain at their values with bars [low, high] (asymmetric); the
    censored recovery drawn open; titles name the window, the level and the interval kind."""
    table = transients()
    sim, predicted = rotation_inputs()
    fig = figures.figure_stress_rotation(sim, predicted, table, 10.0)
    ax_def, ax_min, ax_rec = [ax for ax in fig.axes if ax.get_title()[:3] in ("(e)", "(f)", "(g)")]
    assert "1.5 strain" in ax_def.get_title() and "90% t-interval" in ax_def.get_title()
    assert "3 seeds" in ax_def.get_title()
    assert "bootstrap 90%" in ax_min.get_title() and "bootstrap 90%" in ax_rec.get_title()
    theta = table["theta"].to_numpy()
    for ax, name in ((ax_def, "deficit"), (ax_min, "minimum")):
        np.testing.assert_allclose(
            bar_segments(ax), np.column_stack([theta, table[f"{name}_low"], table[f"{name}_high"]]), rtol=1e-12
        )
        (line,) = [line for line in ax.get_lines() if line.get_marker() == "o"]  # not the caps or the zero line
        np.testing.assert_allclose(line.get_xdata(), theta)
        np.testing.assert_allclose(line.get_ydata(), table[name], rtol=1e-12)
    settled = table["recovery_settled"].to_numpy()
    rec = table[["theta", "recovery_strain_low", "recovery_strain_high"]].to_numpy()
    np.testing.assert_allclose(bar_segments(ax_rec), np.vstack([rec[settled], rec[~settled]]), rtol=1e-12)
    markers = {line.get_label(): line for line in ax_rec.get_lines() if line.get_marker() in ("o", "^")}
    open_marker = markers["not within 10% by the end\n(lower bound)"]
    assert open_marker.get_marker() == "^" and open_marker.get_markerfacecolor() == "none"
    np.testing.assert_allclose(open_marker.get_ydata(), table["recovery_strain"][~settled])
    np.testing.assert_allclose(markers["recovered"].get_ydata(), table["recovery_strain"][settled])


def test_report_table_names_the_level_and_each_interval():
    table, note = stress_page.viscosity_transient_table(transients())
    columns = list(table.columns)
    assert columns == [
        "θ (deg)",
        "deficit ∫₀^1.5 (1 − ηᵣ/ηᵣˢˢ) dγ [90% t-interval]",
        "s.e.",
        "seeds",
        "min ηᵣ/ηᵣˢˢ [90% bootstrap]",
        "at strain [90% bootstrap]",
        "recovery strain (10%) [90% bootstrap]",
    ]
    assert "Student t-interval" in note and "bootstrap resamples of whole seeds" in note
    assert "no verdict rests on them" in note and "own steady viscosity" in note
    assert table["seeds"].tolist() == ["3", "3", "3"] and table["θ (deg)"].tolist() == ["0", "90", "180"]
    assert table.iloc[2, -1].endswith("(not recovered: lower bound)")


@pytest.mark.parametrize(
    "value, low, high, expected",
    [
        (0.2791, 0.1434, 0.4148, "0.28 [0.14, 0.41]"),
        (0.0452, -0.1089, 0.1984, "0.05 [-0.11, 0.20]"),
        (0.0, 0.0, 1.72, "0.0 [0.0, 1.7]"),
        (1.94, 1.94, 1.94, "1.940 [1.940, 1.940]"),
        (0.3, -np.inf, np.inf, "0.3000 [—]"),
        (0.3, np.nan, np.nan, "0.3000 [—]"),
        # a bound that would round to 0 keeps its sign: two significant figures of its own
        (0.05, -0.0035, 0.11, "0.05 [-0.0035, 0.11]"),
        (-0.08, -0.15, 0.0021, "-0.08 [-0.15, 0.0021]"),
        (0.05, 0.0, 0.11, "0.05 [0.00, 0.11]"),
    ],
)
def test_format_interval(value, low, high, expected):
    assert html_tables.format_interval(value, low, high) == expected

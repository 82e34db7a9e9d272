"""The leaderboards and the per-angle results the docs include (reporting.leaderboard_fragments,
reporting.rotation_fragments), on small tables whose text is known."""

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.reporting.leaderboard_fragments import held_out_table, parameters_table, stress_table
from suspension_fabric.reporting.rotation_fragments import peak_ratios, peak_table, viscosity_table


def test_the_parameters_table_has_a_row_per_model_and_fit():
    parameters = pd.DataFrame(
        {
            "model": ["gw", "gw", "modified", "modified"],
            "label": ["G-W", "G-W", "modified", "modified"],
            "mode": ["steady", "global", "steady", "steady"],
            "parameter": ["beta", "beta", "beta", "A"],
            "value": [10.972986, 49.72, 9.347843, 45.11065],
            "error": [0.083825, 3.28, 0.035236, 0.204355],
        }
    )
    assert parameters_table(parameters).splitlines() == [
        "| model | fit | parameters (± jackknife over seeds) |",
        "|---|---|---|",
        "| G-W | steady | beta = 10.973 ± 0.084 |",
        "| G-W | global | beta = 49.7 ± 3.3 |",
        "| modified | steady | beta = 9.348 ± 0.035, A = 45.11 ± 0.20 |",
    ]


def _board(rows):
    columns = ["model", "label", "mode", "component", "held_out_mse", "held_out_low", "held_out_high"]
    columns += ["held_out_difference_vs_gw", "held_out_difference_low_vs_gw", "held_out_difference_high_vs_gw"]
    return pd.DataFrame(rows, columns=columns)


def test_the_held_out_table_leaves_the_reference_difference_blank():
    board = _board(
        [
            ("gw", "G-W", "steady", "n12", 0.0301, 0.0273, 0.0330, 0.0, 0.0, 0.0),
            ("gw", "G-W", "steady", "n23", 0.0271, 0.0238, 0.0305, 0.0, 0.0, 0.0),
            ("modified", "modified", "global", "n12", 0.1293, 0.1245, 0.1341, 0.0991, 0.0945, 0.1038),
            ("modified", "modified", "global", "n23", 0.0232, 0.0213, 0.0251, -0.0039, -0.0065, -0.0013),
        ]
    )
    lines = held_out_table(board).splitlines()
    assert lines[0] == "| model | fit | ⟨nn⟩′₁₂ | minus G-W | ⟨nn⟩′₂₃ | minus G-W |"
    assert lines[2] == "| G-W | steady | 0.0301 [0.0273, 0.0330] |  | 0.0271 [0.0238, 0.0305] |  |"
    assert lines[3].endswith("| 0.0232 [0.0213, 0.0251] | -0.0039 [-0.0065, -0.0013] |")


def test_the_stress_table_quotes_fits_errors_and_biases():
    quantities = ["eta_r rotation", "eta_r startup", "N1 steady", "N2 steady", "Pi steady"]
    rows = []
    for relation, label, mode, held, bias in (
        ("gw", "G-W", "steady", 0.0142, 0.048),
        ("jam", "J", "global", 0.0057, 0.002),
    ):
        for q in quantities:
            rotation = q == "eta_r rotation"
            rows.append(
                {
                    "relation": relation,
                    "label": label,
                    "mode": mode,
                    "quantity": q,
                    "in_sample_mse": 0.015,
                    "in_sample_low": 0.0136,
                    "in_sample_high": 0.0166,
                    "bias": bias if rotation else 0.179,
                    "bias_low": bias - 0.007 if rotation else 0.166,
                    "bias_high": bias + 0.007 if rotation else 0.192,
                    "held_out_mse": held if rotation else np.nan,
                    "held_out_low": held - 0.0009 if rotation else np.nan,
                    "held_out_high": held + 0.0009 if rotation else np.nan,
                    "held_out_difference_vs_gw": held - 0.0142 if rotation else np.nan,
                    "held_out_difference_low_vs_gw": held - 0.0152 if rotation else np.nan,
                    "held_out_difference_high_vs_gw": held - 0.0132 if rotation else np.nan,
                }
            )
    parameters = pd.DataFrame(
        {
            "relation": ["gw", "gw", "jam", "jam", "jam"],
            "mode": ["steady", "steady", "global", "global", "global"],
            "parameter": ["a_H", "a_C", "a_H", "a_C", "Z_J"],
            "value": [25.436909, 131.767612, 25.436909, 18.135075, 5.56333],
            "error": [np.nan, np.nan, np.nan, np.nan, 0.068823],
        }
    )
    lines = stress_table(pd.DataFrame(rows), parameters).splitlines()
    assert lines[0].startswith("| relation | fit | fitted | η_r after a rotation, held-out angles | minus G-W |")
    assert lines[2].startswith(
        "| G-W | steady | a_H = 25.44, a_C = 131.8 | 0.0142 [0.0133, 0.0151] |  | 0.048 [0.041, 0.055] |"
    )
    assert "Z_J = 5.563 ± 0.069" in lines[3] and "-0.0085 [-0.0095, -0.0075]" in lines[3]
    assert lines[3].endswith("| N₁ 0.179 [0.166, 0.192]; N₂ 0.179 [0.166, 0.192]; Π 0.179 [0.166, 0.192] |")


def test_the_peaks_divide_every_curve_by_the_simulated_steady_value_within_the_window():
    strains = [0.0, 0.5, 1.0, 2.0, 2.5]
    aggregate = pd.DataFrame(
        {"theta": [90.0] * 5 + [180.0] * 5, "strain": strains * 2, "n12_mean": [0, -0.11, -0.12, -0.1, -0.2] * 2}
    )
    predictions = pd.DataFrame(
        {
            "model": ["gw"] * 6,
            "protocol": ["startup"] + ["rotation"] * 5,
            "theta": [0.0] + [90.0] * 5,
            "strain": [1.0, *strains],
            "n12": [-0.5, 0.0, -0.09, -0.1, -0.105, -0.3],
        }
    )
    peaks = peak_ratios(predictions, aggregate, -0.1, 2.0)
    assert list(peaks.index) == [90.0]  # 0 < theta < 180 only
    assert peaks.loc[90.0, "simulation"] == pytest.approx(1.2) and peaks.loc[90.0, "gw"] == pytest.approx(
        1.05
    )  # 2.5: outside
    assert peak_table(peaks, {"gw": "G-W"}).splitlines()[2] == "| 90 | 1.200 | 1.050 |"


def test_the_viscosity_table_marks_a_recovery_the_run_does_not_reach():
    transients = pd.DataFrame(
        {
            "theta": [180.0, 90.0],
            "level": 0.95,
            "deficit": [0.654, 0.073],
            "deficit_low": [0.619, 0.024],
            "deficit_high": [0.688, 0.122],
            "minimum": [0.375, 0.863],
            "minimum_low": [0.366, 0.838],
            "minimum_high": [0.385, 0.881],
            "strain_at_min": [0.30, 0.14],
            "strain_at_min_low": [0.28, 0.08],
            "strain_at_min_high": [0.32, 0.24],
            "recovery_strain": [2.0, 0.34],
            "recovery_strain_low": [1.38, 0.24],
            "recovery_strain_high": [2.0, 0.48],
            "recovery_settled": [False, True],
        }
    )
    lines = viscosity_table(transients).splitlines()
    assert lines[0].startswith("| θ (deg) | deficit V [95% t-interval] |") and lines[0].endswith(
        "within 10% of steady from strain |"
    )
    assert lines[2] == "| 90 | 0.073 [0.024, 0.122] | 0.863 [0.838, 0.881] | 0.14 [0.08, 0.24] | 0.34 [0.24, 0.48] |"
    assert lines[3].endswith("| > 2.00 [1.38, 2.00] (not within the run) |")

"""The fragments the README and the docs quote (reporting.summary_fragments), on small tables whose
text is known: the numbers in the text are the tables' numbers, rounded as stated."""

import pandas as pd
import pytest

from suspension_fabric.reporting.summary_fragments import (
    _estimate,
    choices_table,
    fits_paragraph,
    headline_paragraph,
    verdict_table,
)


@pytest.mark.parametrize(
    "value, error, text",
    [
        (10.972986, 0.083825, "10.973 ± 0.084"),  # the error to two significant digits, the value to its place
        (45.110649, 0.204355, "45.11 ± 0.20"),
        (-0.105376, 0.000523, "-0.10538 ± 0.00052"),
        (12.2364, 0.18458, "12.24 ± 0.18"),
        (132.4, 3.2, "132.4 ± 3.2"),
        (1520.0, 41.0, "1520 ± 41"),
        (3.5, 0.0, "3.5"),
    ],
)
def test_an_estimate_keeps_two_significant_digits_of_its_error(value, error, text):
    assert _estimate(value, error) == text


FITS = {
    "steady_window": [2.0, 5.0],
    "n_seeds": 4,
    "models": {
        "gw": {"parameters": {"beta": 11.0}, "errors": {"beta": 0.12}},
        "modified": {"parameters": {"beta": 9.5, "A": 44.0}, "errors": {"beta": 0.05, "A": 0.3}},
    },
}


def state(quantities):
    return pd.DataFrame({"quantity": list(quantities), "mean": list(quantities.values()), "sem_between_seeds": 0.01})


def test_the_fits_paragraph_quotes_each_fit_and_steady_value():
    fabric = state({"n11": 0.5, "n22": 0.6, "n33": 0.6, "n12": -0.1, "n13": 0.0, "n23": 0.0, "Z": 3.5})
    stress = state({"eta_r": 15.5, "N1": -1.2, "N2": -5.6, "Pi": 12.2})
    text = fits_paragraph(FITS, fabric, stress)
    assert "strain 2-5" in text and "the 4 seeds" in text
    assert "G-W beta = 11.00 ± 0.12 (paper 10.9)" in text
    assert "modified beta = 9.500 ± 0.050, A = 44.00 ± 0.30 (paper 9.4, 42.4)" in text
    assert "<nn>_12 = -0.100 ± 0.010" in text and "Z = 3.500 ± 0.010" in text and "Pi = 12.200 ± 0.010" in text


def test_the_choices_table_has_a_row_per_choice_and_bold_decided_verdicts():
    choices = pd.DataFrame(
        {
            "choice": ["primary", "primary", "window 1", "window 1"],
            "claim": ["C1", "C2", "C1", "C2"],
            "mean": [0.2, 0.01, 0.1, -0.3],
            "low": [0.1, -0.02, 0.05, -0.4],
            "high": [0.3, 0.04, 0.15, -0.2],
            "verdict": ["confirmed", "undecided", "confirmed", "refuted"],
        }
    )
    lines = choices_table(choices).splitlines()
    assert lines[0] == "| choice | C1 | C2 |"
    assert lines[2].startswith("| primary | 0.20 [0.10, 0.30] **confirmed** | 0.010 [-0.020, 0.040] undecided |")
    assert "**refuted**" in lines[3] and len(lines) == 4


def test_the_headline_names_the_verdicts_and_the_best_stress_relation():
    verdicts = pd.DataFrame({"claim": ["S1", "C1", "C2", "C3"], "verdict": ["", "confirmed", "confirmed", "refuted"]})
    board = pd.DataFrame(
        {
            "relation": ["gw", "jamming", "gw"],
            "label": ["G-W", "diverging", "G-W"],
            "mode": ["steady", "global", "steady"],
            "quantity": ["eta_r rotation", "eta_r rotation", "N1 steady"],
            "held_out_mse": [0.02, 0.005, 0.1],
        }
    )
    text = headline_paragraph(FITS, verdicts, board, "test: N = 40, 2 seeds")
    assert text.startswith("What the data say, in short (test: N = 40, 2 seeds): G-W beta = 11.00 ± 0.12")
    assert "C1 and C2 are confirmed; C3 is refuted." in text
    assert "± one jackknife standard error over seeds" in text
    assert "“diverging” (global fit) predicts the viscosity after a rotation best" in text and "75% smaller" in text


def test_the_verdict_table_has_a_column_per_dataset_and_the_seeds_an_undecided_claim_needs():
    rows = [
        ("primary", "C1", 16, 0.217, 0.180, 0.254, "confirmed", float("nan")),
        ("primary", "C2", 16, 0.038, -0.015, 0.060, "undecided", 5.0),
        ("window 1", "C1", 16, 0.1, 0.05, 0.15, "confirmed", float("nan")),
        ("N = 500 (data/default)", "C1", 3, 0.30, 0.07, 0.53, "confirmed", float("nan")),
        ("N = 500 (data/default)", "C2", 3, 0.0, -0.15, 0.15, "undecided", float("inf")),
    ]
    choices = pd.DataFrame(
        rows, columns=["choice", "claim", "n_seeds", "mean", "low", "high", "verdict", "seeds_needed"]
    ).assign(
        text=lambda t: t["claim"].map({"C1": "G-W overestimates for pi/4 <~ |theta|", "C2": "G-W underestimates"}),
        statistic="D12(ref) - 1.25 D12(sim)",
    )
    lines = verdict_table(choices, "test: N = 40, 16 seeds", ["N = 500 (data/default)", "absent"]).splitlines()
    assert lines[0] == (
        "| | claim of the paper | T (> 0: as the paper says) | test: N = 40, 16 seeds | "
        "N = 500 (data/default), 3 seeds |"
    )
    assert len(lines) == 4  # the analysis choices and an absent dataset make no column
    assert lines[2].startswith("| C1 | G-W overestimates for pi/4 <~ &#124;theta&#124; | D12(ref) - 1.25 D12(sim) |")
    assert lines[2].endswith("| 0.217 [0.180, 0.254] **confirmed** | 0.30 [0.07, 0.53] **confirmed** |")
    assert "0.038 [-0.015, 0.060] undecided (5 seeds would decide)" in lines[3]
    assert "undecided (> 10000 seeds would decide)" in lines[3]

"""The map's Markdown summary (reporting.map_fragments) from a map table written by hand: the
simulated points' rows in the table's order, values to their significant figures, the claims with
interval and verdict, the points not run listed with their reason."""

import numpy as np
import pandas as pd

from suspension_fabric.evaluation.state_map import map_table
from suspension_fabric.reporting.map_fragments import map_claims_table, map_state_table, map_summary


def _row(phi, mu, eta_r, claim_mean):
    return {
        "point": f"phi{phi:.2f}_mu{mu:g}",
        "phi": phi,
        "mu": mu,
        "eta_r": eta_r,
        "Pi": 120.4,
        "Z": 4.36,
        "n12": -0.0802,
        "steady": "not resolved",
        "reference_model": "G-W (Eq. 1)",
        "reference_beta": 10.7906,
        "reference_beta_err": 0.2,
        "C3'_mean": claim_mean,
        "C3'_low": claim_mean - 0.0066,
        "C3'_high": claim_mean + 0.0066,
        "C3'_verdict": "refuted",
    }


def test_the_summary_lists_each_simulated_point_with_its_values_and_claims():
    table = map_table([_row(0.53, 0.5, 81.5276, -0.0457), _row(0.40, 0.0, 8.3, np.nan)], {"phi0.55_mu1": "too dear"})
    state = map_state_table(table).splitlines()
    assert state[0] == "| phi, mu | eta_r | Pi | Z | <nn>_12 | G-W (Eq. 1) β | steady state |"
    # sorted by mu, then phi; trailing zeros kept, no decimal point left alone
    assert state[2] == "| 0.40, 0 | 8.30 | 120 | 4.36 | -0.0802 | 10.79 | not resolved |"
    assert state[3] == "| 0.53, 0.5 | 81.5 | 120 | 4.36 | -0.0802 | 10.79 | not resolved |"
    assert len(state) == 4  # the point not run has no row
    claims = map_claims_table(table, claims=("C3'",)).splitlines()
    assert claims[2:] == ["| 0.40, 0 | — |", "| 0.53, 0.5 | -0.046 [-0.052, -0.039] refuted |"]
    summary = map_summary(table, 0.95)
    assert "seed mean [95% t-interval over seeds]" in summary
    assert summary.endswith("Not run: (0.55, 1): too dear.\n")


def test_a_map_without_points_not_run_ends_with_its_claims():
    summary = map_summary(pd.DataFrame([_row(0.45, 0.5, 15.2, -0.02)]), 0.9)
    assert "Not run" not in summary and "[90% t-interval" in summary


def test_holm_over_the_maps_cells_leaves_undecided_what_the_family_does_not_decide():
    """Three refuted cells with p = 0.01, 0.03, 0.04: Holm's adjusted p-values are 3 x 0.01 = 0.03,
    max(2 x 0.03, 0.03) = 0.06 and max(0.04, 0.06) = 0.06, so only the first stays refuted at 5%."""
    rows = []
    for phi, p in ((0.40, 0.01), (0.45, 0.03), (0.50, 0.04)):
        rows.append(_row(phi, 0.5, 10.0, -0.05) | {"C3'_p": p})
    table = map_table(rows, {})
    np.testing.assert_allclose(table["C3'_p_holm"], [0.03, 0.06, 0.06])
    assert list(table["C3'_verdict_holm"]) == ["refuted", "undecided", "undecided"]
    claims = map_claims_table(table, claims=("C3'",)).splitlines()
    assert claims[2].endswith("refuted |") and claims[3].endswith("refuted (Holm: undecided) |")
    assert "keeps 1 of the 3 decided verdicts" in map_summary(table, 0.95)

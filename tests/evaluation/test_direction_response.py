"""The response to a change of flow direction against its theta = 0 control
(suspension_fabric.evaluation.direction_response), on tables with known answers."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from suspension_fabric.evaluation import direction_response

STRAINS = np.round(np.arange(0.0, 2.0001, 0.25), 6)


def rotation_tables(eta_by_seed_theta, fraction=0.5, n12=-0.1):
    """Stress and fabric rotation tables: eta_r constant per (seed, theta) run, Z_touching 2, the
    frictional fraction and n12 as given (numbers, or callables of theta)."""
    stress, fabric = [], []
    for (seed, theta), eta in eta_by_seed_theta.items():
        f = fraction(theta) if callable(fraction) else fraction
        n = n12(theta) if callable(n12) else n12
        for strain in STRAINS:
            stress.append({"seed": seed, "theta": theta, "strain": strain, "eta_r": eta,
                           "Z_touching": 2.0, "Z_frictional": 2.0 * f})  # fmt: skip
            fabric.append({"seed": seed, "theta": float(theta), "strain": strain, "n12": n})
    return pd.DataFrame(stress), pd.DataFrame(fabric)


def test_each_rotated_run_is_compared_with_its_own_seeds_control():
    """eta_r 100 at theta = 0 and 50 at 180 for seed 1, 200 and 150 for seed 2: relative changes
    -0.5 and -0.25 in both windows; f 0.9 against 0.6 and n12 -0.1 against +0.05 give differences
    -0.3 and 0.15."""
    stress, fabric = rotation_tables(
        {(1, 0): 100.0, (1, 180): 50.0, (2, 0): 200.0, (2, 180): 150.0},
        fraction=lambda theta: 0.9 if theta == 0 else 0.6,
        n12=lambda theta: -0.1 if theta == 0 else 0.05,
    )
    per_seed = direction_response.per_seed_responses(stress, fabric)
    eta = per_seed[(per_seed["quantity"] == "eta_r") & (per_seed["window_low"] == 0.0)].set_index("seed")["response"]
    np.testing.assert_allclose(eta.loc[[1, 2]], [-0.5, -0.25], rtol=1e-12)
    fraction = per_seed[per_seed["quantity"] == "frictional_fraction"]["response"]
    np.testing.assert_allclose(fraction, -0.3, rtol=1e-12)
    np.testing.assert_allclose(per_seed[per_seed["quantity"] == "n12"]["response"], 0.15, rtol=1e-12)
    assert set(per_seed["theta"]) == {180.0} and len(per_seed) == 2 * 4 * 2  # seeds x quantities x windows


def test_a_seed_without_its_control_is_named():
    stress, fabric = rotation_tables({(1, 0): 100.0, (1, 90): 80.0, (2, 90): 70.0})
    with pytest.raises(ValueError, match="seed 2 has no run at theta = 0"):
        direction_response.per_seed_responses(stress, fabric)


def test_cells_get_t_intervals_and_holm_over_the_table():
    """Two cells: responses (-0.5, -0.4, -0.45) and (0.01, -0.02, 0.015). Each gets the t-interval of
    its three values; Holm multiplies the smaller p by 2 and keeps the larger, so the first reads
    "lower" and the second "not decided"."""
    per_seed = pd.DataFrame(
        [{"point": "p", "theta": 180.0, "quantity": q, "window_low": 0.0, "window_high": 0.5, "seed": s, "response": r}
         for q, values in (("eta_r", (-0.5, -0.4, -0.45)), ("n12", (0.01, -0.02, 0.015)))
         for s, r in zip((1, 2, 3), values)]
    )  # fmt: skip
    table = direction_response.response_table(per_seed, 0.95).set_index("quantity")
    values = np.array([-0.5, -0.4, -0.45])
    half = stats.t.ppf(0.975, 2) * values.std(ddof=1) / np.sqrt(3)
    assert table.loc["eta_r", "high"] == pytest.approx(-0.45 + half, rel=1e-9)
    p = stats.ttest_1samp(values, 0.0).pvalue
    p_other = stats.ttest_1samp([0.01, -0.02, 0.015], 0.0).pvalue
    assert table.loc["eta_r", "p_holm"] == pytest.approx(min(1.0, 2 * p), rel=1e-9)
    assert table.loc["n12", "p_holm"] == pytest.approx(max(2 * p, p_other), rel=1e-9)
    assert (table.loc["eta_r", "reading"], table.loc["n12", "reading"]) == ("lower", "not decided")


def test_two_points_are_compared_per_seed_when_they_share_their_seeds_and_by_welch_otherwise():
    """Responses a = (-0.5, -0.4), b = (-0.1, -0.2) on seeds 1, 2: paired, the differences are
    -0.4 and -0.2 (mean -0.3, s.e. 0.1); on other seeds for b, Welch's interval of the same means."""
    rows = [
        {"point": point, "theta": 90.0, "quantity": "eta_r", "window_low": 0.0, "window_high": 0.5, "seed": s,
         "response": r}
        for point, values in (("a", (-0.5, -0.4)), ("b", (-0.1, -0.2))) for s, r in zip((1, 2), values)
    ]  # fmt: skip
    cell = {"theta": 90.0, "quantity": "eta_r", "window": (0.0, 0.5)}
    interval, test = direction_response.between_points(pd.DataFrame(rows), "a", "b", **cell)
    assert test == "paired" and interval.mean == pytest.approx(-0.3) and interval.se == pytest.approx(0.1)
    others = pd.DataFrame([row | {"seed": row["seed"] + 10} if row["point"] == "b" else row for row in rows])
    interval, test = direction_response.between_points(others, "a", "b", **cell)
    assert test == "Welch" and interval.mean == pytest.approx(-0.3)
    assert interval.low < -0.3 < interval.high


def test_windows_are_half_open_so_no_frame_counts_twice_and_the_change_itself_in_none():
    """eta_r 100 everywhere in both runs but 1000 at the change (strain 0) and 400 at strain 0.5 of
    the rotated run: window (0, 0.5] holds 0.25 and 0.5, so its mean is (100 + 400) / 2 = 250 against
    100 (+1.5); window (0.5, 2] holds 0.75 to 2 only, so no change."""
    stress, fabric = rotation_tables({(1, 0): 100.0, (1, 90): 100.0, (2, 0): 100.0, (2, 90): 100.0})
    rotated = stress["theta"] == 90
    stress.loc[rotated & (stress["strain"] == 0.0), "eta_r"] = 1000.0
    stress.loc[rotated & (stress["strain"] == 0.5), "eta_r"] = 400.0
    per_seed = direction_response.per_seed_responses(stress, fabric)
    eta = per_seed[per_seed["quantity"] == "eta_r"].set_index(["seed", "window_low"])["response"]
    np.testing.assert_allclose(eta.loc[[(1, 0.0), (2, 0.0)]], 1.5, rtol=1e-12)
    np.testing.assert_allclose(eta.loc[[(1, 0.5), (2, 0.5)]], 0.0, atol=1e-12)

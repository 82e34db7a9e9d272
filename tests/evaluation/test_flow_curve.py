"""Flow curves under critical-load friction (suspension_fabric.evaluation.flow_curve) against known answers."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from suspension_fabric.evaluation import flow_curve
from suspension_fabric.reporting.flow_curve_fragments import flow_curve_summary

STRAINS = tuple(0.5 * k for k in range(9))  # 0 to 4


def startup_runs(values_by_seed: dict[int, dict[str, float]], strains=STRAINS) -> pd.DataFrame:
    """A startup stress table: per seed constant quantities over ``strains``, except eta_r = 1000 before
    strain 2 (outside the steady window)."""
    rows = []
    for seed, values in values_by_seed.items():
        for strain in strains:
            row = {"seed": seed, "strain": strain, **dict.fromkeys(flow_curve.FLOW_CURVE_QUANTITIES, 0.0), **values}
            if strain < 2.0:
                row["eta_r"] = 1000.0
            rows.append(row)
    return pd.DataFrame(rows)


def test_sigma_over_sigma0_is_eta_r_gamma_over_6_pi():
    """sigma / sigma_0 = eta_r Gamma / (6 pi): 1 at eta_r = 6 pi, Gamma = 1; 0.5 at eta_r = 30 pi, Gamma = 0.1."""
    assert flow_curve.stress_over_sigma0(6.0 * math.pi, 1.0) == pytest.approx(1.0, rel=1e-15)
    assert flow_curve.stress_over_sigma0(30.0 * math.pi, 0.1) == pytest.approx(0.5, rel=1e-14)
    with pytest.raises(ValueError, match="must be > 0"):
        flow_curve.stress_over_sigma0(1.0, 0.0)


def test_steady_means_use_the_window_only_and_name_a_seed_without_frames():
    runs = startup_runs({1: {"eta_r": 10.0}, 2: {"eta_r": 20.0}})
    means = flow_curve.seed_steady_means(runs, [2.0, 4.0])
    assert means.loc[1, "eta_r"] == 10.0 and means.loc[2, "eta_r"] == 20.0
    short = pd.concat([runs, startup_runs({3: {"eta_r": 5.0}}, strains=[0.0, 1.0])])
    with pytest.raises(ValueError, match=r"seeds \[3\] have no frame"):
        flow_curve.seed_steady_means(short, [2.0, 4.0])


def test_the_table_is_the_seed_mean_with_its_t_interval():
    """Two seeds with eta_r 10 and 20 at Gamma = 0.6 pi: sigma / sigma_0 = 1 and 2 per seed, mean 1.5, and the
    95% t-interval half-width t(0.975, 1) s / sqrt(2) = 12.706 x 0.5; frictional fractions 0.4/2 and 1.6/4,
    mean 0.3; a quantity no seed recorded is NaN."""
    runs = startup_runs(
        {
            1: {"eta_r": 10.0, "Z_touching": 2.0, "Z_frictional": 0.4},
            2: {"eta_r": 20.0, "Z_touching": 4.0, "Z_frictional": 1.6},
        }
    )
    runs["N1"] = np.nan
    points = {"p": {"phi": 0.54, "mu": 1.0, "rate_ratio": 0.6 * math.pi, "runs": runs}}
    per_seed = flow_curve.per_seed_table(points, [2.0, 4.0])
    np.testing.assert_allclose(per_seed["sigma"], [1.0, 2.0], rtol=1e-14)
    table = flow_curve.flow_curve_table(per_seed, 0.95)
    row = table.iloc[0]
    half = stats.t.ppf(0.975, 1) * 0.5
    assert row["sigma"] == pytest.approx(1.5) and row["n_seeds"] == 2
    assert row["sigma_high"] - row["sigma"] == pytest.approx(half, rel=1e-9)
    assert row["frictional_fraction"] == pytest.approx(0.3) and row["Z_touching"] == pytest.approx(3.0)
    assert np.isnan(row["N1"]) and np.isnan(row["N1_low"])


def test_a_point_at_controlled_stress_measures_its_rate_from_the_critical_load():
    """At stress control sigma / sigma_0 = S is imposed and the rate measured: gammadot / gammadot_0 =
    6 pi eta_f a^2 / <F_CL> over the steady window (a step of strain lasts a time proportional to F_CL).
    With eta_f = 223, a = 0.5 and F_CL = 223 pi / 2 (seed 1) and 223 pi (seed 2) the rates are 3 and
    1.5; sigma is S for both seeds, and eta_r stays the strain mean of the runs."""
    runs = startup_runs(
        {
            1: {"eta_r": 40.0, "Z_touching": 3.0, "Z_frictional": 1.5, "critical_load": 223.0 * math.pi / 2},
            2: {"eta_r": 80.0, "Z_touching": 3.0, "Z_frictional": 1.5, "critical_load": 223.0 * math.pi},
        }
    )
    points = {"s": {"phi": 0.56, "mu": 1.0, "stress_ratio": 0.2, "eta_f": 223.0, "d_small": 1.0, "runs": runs}}
    per_seed = flow_curve.per_seed_table(points, [2.0, 4.0])
    np.testing.assert_allclose(per_seed["rate_ratio"], [3.0, 1.5], rtol=1e-12)
    assert (per_seed["sigma"] == 0.2).all() and (per_seed["control"] == "stress").all()
    table = flow_curve.flow_curve_table(per_seed, 0.95)
    assert table.loc[0, "rate_ratio"] == pytest.approx(2.25) and table.loc[0, "target"] == 0.2
    with pytest.raises(ValueError, match="critical load its runs recorded"):
        flow_curve.measured_rate_ratio([0.0], 223.0, 1.0)


def test_onset_stress_recovers_the_wyart_cates_sigma_star_per_seed():
    """f = exp(-s*/sigma) exactly, with s* = 0.1 for one seed and 0.3 for the other: the per-seed slopes are
    0.1 and 0.3, their mean 0.2; points with f = 0 or 1 are left out (two of five per seed here), and
    every per-point estimate -ln f sigma lies in [0.1, 0.3]."""
    rows = []
    for seed, star in ((1, 0.1), (2, 0.3)):
        for sigma, fraction in ((0.05, 0.0), (0.2, None), (0.5, None), (1.0, None), (50.0, 1.0)):
            exact = math.exp(-star / sigma) if fraction is None else fraction
            rows.append({"seed": seed, "sigma": sigma, "frictional_fraction": exact})
    onset = flow_curve.onset_stress(pd.DataFrame(rows), 0.95)
    assert onset["sigma_star"] == pytest.approx(0.2, rel=1e-12)
    assert onset["points_per_seed"] == [3, 3]
    assert onset["estimate_min"] == pytest.approx(0.1) and onset["estimate_max"] == pytest.approx(0.3)
    assert onset["low"] < 0.1 < 0.3 < onset["high"]


def test_the_equal_weight_onset_is_the_geometric_mean_of_the_per_point_estimates():
    """The slope through the origin of -ln f against 1/sigma weights each point by (1/sigma)^2; with
    every point weighted alike the per-seed estimate is the geometric mean of -ln f sigma. For one seed
    with estimates 0.05 at sigma = 0.1 and 0.2 at sigma = 1: the slope is
    (10 * 0.5 + 1 * 0.2) / (100 + 1) = 0.0515 (the low stress dominates), the geometric mean 0.1."""
    rows = [
        {"seed": seed, "sigma": sigma, "frictional_fraction": math.exp(-estimate / sigma)}
        for seed in (1, 2)
        for sigma, estimate in ((0.1, 0.05), (1.0, 0.2))
    ]
    onset = flow_curve.onset_stress(pd.DataFrame(rows), 0.95)
    assert onset["sigma_star"] == pytest.approx(5.2 / 101, rel=1e-12)
    assert onset["sigma_star_equal_weights"] == pytest.approx(0.1, rel=1e-12)
    assert onset["weighting_difference"] == pytest.approx(0.1 - 5.2 / 101, rel=1e-12)


def test_onset_differences_are_welch_intervals_between_neighbouring_volume_fractions():
    """Per-seed sigma* (0.07, 0.08) at phi = 0.50 and (0.09, 0.10) at 0.54: the difference 0.02 with
    Welch's interval; a curve without per-seed values is skipped."""
    onsets = pd.DataFrame(
        [
            {"phi": 0.50, "mu": 1.0, "control": "rate", "per_seed": [0.07, 0.08]},
            {"phi": 0.54, "mu": 1.0, "control": "rate", "per_seed": [0.09, 0.10]},
            {"phi": 0.56, "mu": 1.0, "control": "rate", "per_seed": np.nan},
        ]
    )
    differences = flow_curve.onset_differences(onsets, 0.95)
    assert len(differences) == 1
    row = differences.iloc[0]
    assert (row["phi_low"], row["phi_high"]) == (0.50, 0.54) and row["difference"] == pytest.approx(0.02)
    se = math.sqrt(2 * np.var([0.07, 0.08], ddof=1) / 2)
    assert row["high"] - row["difference"] == pytest.approx(stats.t.ppf(0.975, 2) * se, rel=1e-9)


def test_onset_stress_is_nan_when_a_seed_has_no_partial_fraction():
    rows = [
        {"seed": 1, "sigma": 1.0, "frictional_fraction": 0.5},
        {"seed": 2, "sigma": 1.0, "frictional_fraction": 1.0},
    ]
    assert np.isnan(flow_curve.onset_stress(pd.DataFrame(rows))["sigma_star"])


def test_the_thickening_exponent_is_the_per_seed_secant_of_ln_eta_against_ln_sigma():
    """beta = (ln eta_2 - ln eta_1) / (ln sigma_2 - ln sigma_1) per seed: eta doubling while sigma grows
    4-fold gives 0.5, eta growing 8-fold with sigma 8-fold gives 1 (the stress no longer rises with the
    rate); the mean over the two seeds is 0.75 with the t-interval of (0.5, 1). A pair only one seed
    shares has no interval."""
    rows = [
        {"phi": 0.56, "mu": 1.0, "seed": 1, "control": "rate", "target": 0.01, "sigma": 1.0, "eta_r": 10.0},
        {"phi": 0.56, "mu": 1.0, "seed": 1, "control": "rate", "target": 0.02, "sigma": 4.0, "eta_r": 20.0},
        {"phi": 0.56, "mu": 1.0, "seed": 2, "control": "rate", "target": 0.01, "sigma": 1.0, "eta_r": 10.0},
        {"phi": 0.56, "mu": 1.0, "seed": 2, "control": "rate", "target": 0.02, "sigma": 8.0, "eta_r": 80.0},
        {"phi": 0.56, "mu": 1.0, "seed": 2, "control": "rate", "target": 0.05, "sigma": 16.0, "eta_r": 80.0},
    ]
    exponents = flow_curve.thickening_exponents(pd.DataFrame(rows), 0.95)
    first, second = exponents.iloc[0], exponents.iloc[1]
    assert (first["target_low"], first["target_high"], first["n_seeds"]) == (0.01, 0.02, 2)
    assert first["exponent"] == pytest.approx(0.75, rel=1e-12)
    half = stats.t.ppf(0.975, 1) * np.std([0.5, 1.0], ddof=1) / math.sqrt(2)
    assert first["high"] - first["exponent"] == pytest.approx(half, rel=1e-9)
    assert second["n_seeds"] == 1 and np.isnan(second["exponent"])


def test_the_summary_prints_each_point_and_the_onset_from_the_tables():
    """The fragment's numbers come from the table and the onset: one row per point with its rate and
    intervals, and the onset line with the per-seed counts; a curve without onset says so."""
    rows = []
    for seed, star in ((1, 0.1), (2, 0.3)):
        for rate, eta in ((0.01, 20.0), (0.1, 60.0)):
            sigma = eta * rate / (6 * math.pi)
            rows.append({"point": f"r{rate}", "phi": 0.54, "mu": 1.0, "control": "rate", "target": rate,
                         "rate_ratio": rate, "seed": seed, "eta_r": eta,
                         "N1": 0.0, "N2": 0.0, "Pi": 2 * eta, "Z_touching": 3.0 + seed, "Z_frictional": 1.0,
                         "frictional_fraction": math.exp(-star / sigma), "sigma": sigma})  # fmt: skip
    per_seed = pd.DataFrame(rows)
    table = flow_curve.flow_curve_table(per_seed, 0.95)
    onsets = pd.DataFrame([{"phi": 0.54, "mu": 1.0, "control": "rate", **flow_curve.onset_stress(per_seed, 0.95)}])
    fit = pd.DataFrame([{"mu": 1.0, "parameter": "phi_Jmu", "value": 0.58, "low": 0.57, "high": 0.59}])
    exponents = flow_curve.thickening_exponents(per_seed, 0.95)
    differences = pd.DataFrame(
        [
            {
                "mu": 1.0,
                "control": "rate",
                "phi_low": 0.5,
                "phi_high": 0.54,
                "difference": 0.01,
                "low": -0.02,
                "high": 0.04,
            }
        ]
    )
    text = flow_curve_summary(table, onsets, differences, exponents, fit, 0.95)
    assert "σ*/σ₀ at φ = 0.54 minus at φ = 0.50 (μ = 1, imposed rate): 0.010 [-0.020, 0.040]" in text
    assert "| 0.54, 1 | rate | 0.01 |" in text and "| 0.54, 1 | rate | 0.1 |" in text
    assert "95% t-interval" in text and "over [2, 2] points with 0 < f < 1 per seed" in text
    assert "σ*/σ₀ = 0.2" in text
    assert (
        "at μ = 1 with the measured f, fitted per seed over every point of the curves: φ_J^μ = 0.580 [0.570, 0.590]"
        in text
    )
    # eta 20 -> 60 while sigma grows 30-fold at both seeds: ln 3 / ln 30
    assert f"0.01 to 0.1: {math.log(3) / math.log(30):.3f}" in text
    none = flow_curve_summary(
        table, onsets.assign(sigma_star=np.nan), differences.iloc[:0], exponents, fit.iloc[:0], 0.95
    )
    assert "no onset stress" in none


def test_the_wyart_cates_fit_recovers_its_parameters_from_exact_viscosities():
    """Viscosities of the Wyart-Cates form exactly (A = 1.2, phi_J0 = 0.64, phi_Jmu = 0.58 for one seed,
    phi_Jmu = 0.585 for the other) at phi 0.50 and 0.54 and f in {0, 0.3, 0.9, 1} give back each seed's
    parameters (the mean of the two phi_Jmu, 0.5825) and a zero residual; a single volume fraction is
    not fitted."""
    rows = []
    for seed, phi_jmu in ((1, 0.58), (2, 0.585)):
        for phi in (0.50, 0.54):
            for fraction in (0.0, 0.3, 0.9, 1.0):
                eta = flow_curve.wyart_cates_viscosity(phi, fraction, 1.2, 0.64, phi_jmu)
                rows.append({"mu": 1.0, "seed": seed, "phi": phi, "frictional_fraction": fraction, "eta_r": eta})
    fit = flow_curve.wyart_cates_fit(pd.DataFrame(rows), 0.95).set_index("parameter")
    assert fit.loc["A", "value"] == pytest.approx(1.2, rel=1e-5)
    assert fit.loc["phi_J0", "value"] == pytest.approx(0.64, rel=1e-6)
    assert fit.loc["phi_Jmu", "value"] == pytest.approx(0.5825, rel=1e-6)
    assert fit.loc["phi_Jmu", "low"] < 0.58 < 0.585 < fit.loc["phi_Jmu", "high"]
    assert fit.loc["rms_log_residual", "value"] < 1e-6
    one_phi = pd.DataFrame(rows).query("phi == 0.54")
    assert flow_curve.wyart_cates_fit(one_phi).empty


def test_frictionless_points_join_each_seeds_fit_and_set_phi_j0():
    """A flow curve at one volume fraction (0.54, f from 0.05 to 1) cannot be fitted alone; with the
    frictionless viscosities A (1 - phi/phi_J0)^-2 at phi 0.40-0.55 (f = 0) joined per seed, the fit
    gives back A = 1.2, phi_J0 = 0.64 and phi_Jmu = 0.58 exactly; a seed the frictionless points lack
    is named."""
    curve, runs = [], {}
    for seed in (1, 2):
        for fraction in (0.05, 0.3, 0.9, 1.0):
            eta = flow_curve.wyart_cates_viscosity(0.54, fraction, 1.2, 0.64, 0.58)
            curve.append({"mu": 1.0, "seed": seed, "phi": 0.54, "frictional_fraction": fraction, "eta_r": eta})
    for phi in (0.40, 0.45, 0.50, 0.55):
        eta = float(flow_curve.wyart_cates_viscosity(phi, 0.0, 1.2, 0.64, 0.58))
        table = pd.DataFrame([{"seed": s, "strain": g, "eta_r": eta} for s in (1, 2) for g in (2.0, 3.0)])
        runs[f"phi{phi:.2f}_mu0"] = (phi, (2.0, 3.0), table)
    frictionless = flow_curve.frictionless_steady(runs)
    assert set(frictionless["frictional_fraction"]) == {0.0} and len(frictionless) == 8
    assert flow_curve.wyart_cates_fit(pd.DataFrame(curve)).empty
    fit = flow_curve.wyart_cates_fit(pd.DataFrame(curve), 0.95, frictionless).set_index("parameter")
    assert fit.loc["A", "value"] == pytest.approx(1.2, rel=1e-5)
    assert fit.loc["phi_J0", "value"] == pytest.approx(0.64, rel=1e-6)
    assert fit.loc["phi_Jmu", "value"] == pytest.approx(0.58, rel=1e-6)
    with pytest.raises(ValueError, match=r"no seed \[2\]"):
        flow_curve.wyart_cates_fit(pd.DataFrame(curve), 0.95, frictionless[frictionless["seed"] == 1])


def shape_rows(rates_by_seed: dict[int, dict[float, float]]) -> pd.DataFrame:
    """`per_seed_table` rows at controlled stress: per seed the measured rate at each stress."""
    return pd.DataFrame(
        [
            {"phi": 0.56, "mu": 1.0, "control": "stress", "seed": seed, "target": sigma}
            | {"sigma": sigma, "rate_ratio": rate}
            for seed, rates in rates_by_seed.items()
            for sigma, rate in rates.items()
        ]
    )


def test_the_shape_is_the_per_seed_slope_and_quadratic_coefficient_of_ln_rate_in_ln_sigma():
    """With x = ln sigma and y = ln rate: seed 1 has y = 0.5 x exactly (b = 0.5, c = 0); seed 2 has
    y = 0.5 x + 0.3 (x - ln 0.1)^2 (c = 0.3; b over three points equally spaced about ln 0.1 is 0.5,
    the symmetric quadratic adding no slope); for three points spaced by h, c = (y0 - 2 y1 + y2) / (2 h^2).
    Means over the two seeds: b = 0.5, c = 0.15 with the t-interval of (0, 0.3). A seed missing a point
    of the window is left out; the stress 0.5 outside the window is not used."""
    h = math.log(2.0)
    sigmas = (0.05, 0.1, 0.2)
    rates = {
        1: {s: math.exp(0.5 * math.log(s)) for s in (*sigmas, 0.5)},
        2: {s: math.exp(0.5 * math.log(s) + 0.3 * (math.log(s) - math.log(0.1)) ** 2) for s in sigmas},
        3: {0.05: 1.0, 0.2: 2.0},
    }
    shape = flow_curve.curve_shape(shape_rows(rates), [0.05, 0.2], 0.95).set_index("statistic")
    assert shape.loc["slope", "value"] == pytest.approx(0.5, abs=1e-12)
    assert shape.loc["curvature", "value"] == pytest.approx(0.15, abs=1e-12)
    y2 = [math.log(rates[2][s]) for s in sigmas]
    assert (y2[0] - 2 * y2[1] + y2[2]) / (2 * h * h) == pytest.approx(0.3, rel=1e-12)
    half = stats.t.ppf(0.975, 1) * np.std([0.0, 0.3], ddof=1) / math.sqrt(2)
    assert shape.loc["curvature", "high"] - 0.15 == pytest.approx(half, rel=1e-9)
    assert shape.loc["slope", "n_seeds"] == 2 and shape.loc["slope", "targets"] == "0.05 0.1 0.2"
    per_seed = dict(item.split("=") for item in shape.loc["curvature", "per_seed"].split("; "))
    assert per_seed.keys() == {"1", "2"} and float(per_seed["2"]) == pytest.approx(0.3, abs=1e-4)
    assert float(per_seed["1"]) == pytest.approx(0.0, abs=1e-4)


def test_the_shape_needs_three_points_and_is_empty_without_a_window():
    rows = shape_rows({1: {0.05: 1.0, 0.1: 1.0, 0.2: 1.0}, 2: {0.05: 1.0, 0.1: 1.0, 0.2: 1.0}})
    assert flow_curve.curve_shape(rows, None).empty
    with pytest.raises(ValueError, match=r"2 point\(s\) in the shape window \[0.06, 0.2\]"):
        flow_curve.curve_shape(rows, [0.06, 0.2])


def test_the_summary_reads_the_shape_against_zero_and_the_named_effect_size():
    """A slope interval inside +-SLOPE_EFFECT reads as vertical within it; the curvature's side of 0 is
    printed with its interval."""
    rates = {seed: {0.05: 1.0 + 0.01 * seed, 0.1: 0.9, 0.2: 1.0 - 0.005 * seed} for seed in (1, 2, 3, 4)}
    per_seed = shape_rows(rates)
    shape = flow_curve.curve_shape(per_seed, [0.05, 0.2], 0.95)
    empty = pd.DataFrame(columns=["phi", "mu", "control"])
    text = flow_curve_summary(pd.DataFrame(), empty, empty, empty, pd.DataFrame(columns=["mu"]), 0.95, shape=shape)
    slope = shape.set_index("statistic").loc["slope"]
    assert -flow_curve.SLOPE_EFFECT < slope["low"] and slope["high"] < flow_curve.SLOPE_EFFECT
    assert "shape over imposed σ/σ₀ = 0.05, 0.1, 0.2, per seed with every one of these points (4 seeds)" in text
    assert f"inside ±{flow_curve.SLOPE_EFFECT:g}: vertical within that" in text
    assert "quadratic coefficient c = " in text and "(interval above 0)" in text

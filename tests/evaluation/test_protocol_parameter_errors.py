"""The fits' own uncertainty in the protocol leaderboard's intervals
(protocol_benchmark.parameter_spread): each parameter moved by its standard error s_k, the seed-mean
score's response bounded by sum_k |S(p_k + s_k) - S(p_k - s_k)| / 2 and added in quadrature to the
seeds' standard error; a fit without errors keeps the seeds' interval and says so (NaN)."""

import numpy as np
import pytest
from scipy import stats
from test_provenance import PHI, _curves

from suspension_fabric.evaluation import protocol_benchmark as pb
from suspension_fabric.models.fabric_models import resolve_models

N12_SS = 0.1
BETA = 12.0  # away from the curves' own beta (11), so the score responds to beta at first order


def _board(errors):
    board, _ = pb.fabric_protocol_leaderboard(
        resolve_models(["gw"]),
        {"steady": {"gw": {"beta": BETA}}, "global": {"gw": {"beta": BETA + 1.0}}},
        {"reversal": _curves([101, 102, 103, 104])},
        PHI,
        N12_SS,
        seen={("gw", "steady"): set(), ("gw", "global"): set()},
        reference="gw",
        parameter_errors=errors,
    )
    return board.set_index(["mode", "component"])


def _seed_mean_score(beta):
    curves = _curves([101, 102, 103, 104])
    predicted = pb.model_protocol_predictions(resolve_models(["gw"])["gw"], {"beta": beta}, PHI, curves)
    per_seed = pb.fabric_protocol_scores(predicted, curves, N12_SS)
    return per_seed, per_seed.mean(axis=0)


def test_the_bound_is_the_central_difference_of_the_seed_mean_score_and_scales_with_the_error():
    gw = resolve_models(["gw"])["gw"]
    curves = _curves([101, 102, 103, 104])
    bound = pb.parameter_spread(gw, {"beta": BETA}, {"beta": 0.05}, PHI, curves, N12_SS)
    up, down = _seed_mean_score(BETA + 0.05)[1], _seed_mean_score(BETA - 0.05)[1]
    np.testing.assert_allclose(bound[:6], 0.5 * np.abs(up - down), rtol=1e-12)
    assert bound[3] > 0.0
    # first order in the error: S(b + s) - S(b - s) = 2 S'(b) s + O(s^3)
    doubled = pb.parameter_spread(gw, {"beta": BETA}, {"beta": 0.1}, PHI, curves, N12_SS)
    np.testing.assert_allclose(doubled[3] / bound[3], 2.0, rtol=1e-2)


def test_the_interval_adds_the_bound_in_quadrature_to_the_seeds_standard_error():
    board = _board({"steady": {"gw": {"beta": 0.05}}, "global": {"gw": {"beta": 0.05}}})
    row = board.loc[("steady", "n12")]
    per_seed = _seed_mean_score(BETA)[0][:, 3]
    se = np.hypot(per_seed.std(ddof=1) / 2.0, row["parameter_se"])
    half = stats.t.ppf(0.975, 3) * se
    assert row["parameter_se"] > 0.0
    assert (row["mse_low"], row["mse_high"]) == pytest.approx(
        (per_seed.mean() - half, per_seed.mean() + half), rel=1e-9
    )
    # the difference between the two modes carries both rows' bounds
    other = board.loc[("global", "n12")]
    difference_se = (other["difference_high_vs_gw"] - other["difference_low_vs_gw"]) / (2 * stats.t.ppf(0.975, 3))
    shift = _seed_mean_score(BETA + 1.0)[0][:, 3] - per_seed
    expected = np.hypot(shift.std(ddof=1) / 2.0, row["parameter_se"] + other["parameter_se"])
    assert difference_se == pytest.approx(expected, rel=1e-9)


def test_a_fit_without_errors_keeps_the_seeds_interval_and_says_so():
    board = _board({"steady": {"gw": {"beta": np.nan}}})
    row = board.loc[("steady", "n12")]
    assert np.isnan(row["parameter_se"]) and np.isnan(board.loc[("global", "n12"), "parameter_se"])
    per_seed = _seed_mean_score(BETA)[0][:, 3]
    half = stats.t.ppf(0.975, 3) * per_seed.std(ddof=1) / 2.0
    assert row["mse_high"] - row["mse_low"] == pytest.approx(2 * half, rel=1e-9)


def test_two_parameters_combine_by_their_correlation_and_are_bounded_without_it():
    """Modified G-W (beta, A): with h_k the half difference of the seed-mean score when parameter k
    moves by its error, the standard error is sqrt(h_b^2 + h_A^2 + 2 r h_b h_A) for correlation r,
    and |h_b| + |h_A| (the case r = +-1 at worst) when r is not known."""
    modified = resolve_models(["modified"])["modified"]
    curves = _curves([101, 102, 103, 104])
    params, errors = {"beta": 9.0, "A": 40.0}, {"beta": 0.05, "A": 0.3}

    def half_step(name):
        scores = []
        for sign in (1.0, -1.0):
            predicted = pb.model_protocol_predictions(
                modified, {**params, name: params[name] + sign * errors[name]}, PHI, curves
            )
            scores.append(pb.fabric_protocol_scores(predicted, curves, N12_SS).mean(axis=0))
        return 0.5 * (scores[0] - scores[1])

    h_b, h_a = half_step("beta"), half_step("A")
    for r in (-0.6, 0.0, 0.66):
        spread = pb.parameter_spread(modified, params, errors, PHI, curves, N12_SS, {"beta,A": r})
        np.testing.assert_allclose(spread[:6], np.sqrt(h_b**2 + h_a**2 + 2 * r * h_b * h_a), rtol=1e-9, atol=1e-15)
    bound = pb.parameter_spread(modified, params, errors, PHI, curves, N12_SS, None)
    np.testing.assert_allclose(bound[:6], np.abs(h_b) + np.abs(h_a), rtol=1e-12)


def test_the_committed_parameters_table_reads_per_mode_and_model():
    """data/models/reference_parameters.csv: the modified model's steady fit has beta, A with their
    errors and one correlation; G-W's single parameter has none."""
    import pandas as pd

    from workflow_helpers import REPO

    values, errors, correlations = pb.parameters_by_mode(pd.read_csv(REPO / "data/models/reference_parameters.csv"))
    assert set(values) == {"steady", "global"} and set(values["steady"]["modified"]) == {"beta", "A"}
    assert errors["steady"]["modified"]["A"] > 0 and set(correlations["steady"]["modified"]) == {"beta,A"}
    assert correlations["steady"]["gw"] == {} and values["global"]["gw"]["beta"] > values["steady"]["gw"]["beta"]

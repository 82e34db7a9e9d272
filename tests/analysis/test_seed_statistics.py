"""Known-answer tests of suspension_fabric.analysis.seed_statistics (docs/verdict_statistics.md, Secs. 1 and 4).

Every expected value is computed here independently of the module: means and standard deviations
by hand or by their formulas, Student quantiles from scipy.stats.t (and two from a printed table),
the number of seeds by brute force, bootstrap resamples by explicit enumeration.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from suspension_fabric.analysis import seed_statistics as ss
from suspension_fabric.analysis.seed_statistics import Interval


def _sd(values) -> float:
    """Sample standard deviation by its formula: sqrt(sum (x - mean)^2 / (n - 1))."""
    n = len(values)
    mean = sum(values) / n
    return math.sqrt(sum((x - mean) ** 2 for x in values) / (n - 1))


# ----------------------------------------------------------------------------- t_interval
# (values, mean by hand, sd(ddof=1) by hand)
HAND = [
    ([1.0, 2.0, 3.0, 4.0, 5.0], 3.0, math.sqrt(2.5)),  # sum of squares 4+1+0+1+4 = 10, /4
    ([0.3, -0.1, 0.5], 0.7 / 3, math.sqrt((0.3**2 + 0.1**2 + 0.5**2 - 0.7**2 / 3) / 2)),
    ([2.0, 4.0], 3.0, math.sqrt(2.0)),  # (1 + 1) / 1
    ([-1.5, -1.5, -1.5, -1.5], -1.5, 0.0),
]


@pytest.mark.parametrize("level", [0.95, 0.9])
@pytest.mark.parametrize("values, mean, sd", HAND)
def test_t_interval_known_values(values, mean, sd, level):
    """mean, se = sd(ddof=1)/sqrt(n), [low, high] = mean -+ t_{(1+level)/2, n-1} se."""
    n = len(values)
    assert sd == pytest.approx(_sd(values), abs=1e-15)
    se = sd / math.sqrt(n)
    half = stats.t.ppf(0.5 + level / 2.0, n - 1) * se
    got = ss.t_interval(values, level)
    assert got.n == n and got.level == level
    assert got.mean == pytest.approx(mean, rel=1e-13, abs=1e-15)
    assert got.se == pytest.approx(se, rel=1e-12, abs=1e-15)
    assert got.low == pytest.approx(mean - half, rel=1e-12, abs=1e-14)
    assert got.high == pytest.approx(mean + half, rel=1e-12, abs=1e-14)


def test_t_interval_against_printed_t_table():
    """t_{0.975, 4} = 2.776445 and t_{0.95, 4} = 2.131847 (standard t-table); values 1..5 have
    mean 3 and se = sqrt(2.5)/sqrt(5) = sqrt(0.5)."""
    se = math.sqrt(0.5)
    got95 = ss.t_interval([5.0, 3.0, 1.0, 4.0, 2.0])
    assert got95.level == 0.95
    assert got95.low == pytest.approx(3.0 - 2.776445 * se, abs=1e-6)
    assert got95.high == pytest.approx(3.0 + 2.776445 * se, abs=1e-6)
    got90 = ss.t_interval([5.0, 3.0, 1.0, 4.0, 2.0], level=0.9)
    assert got90.high == pytest.approx(3.0 + 2.131847 * se, abs=1e-6)


def test_t_interval_accepts_any_shape():
    """The values are flattened: a (2, 2) array is four seeds."""
    got = ss.t_interval(np.array([[1.0, 2.0], [3.0, 4.0]]))
    assert got.n == 4 and got.mean == pytest.approx(2.5)
    assert got.se == pytest.approx(_sd([1.0, 2.0, 3.0, 4.0]) / 2.0)


def test_t_interval_one_value_is_infinite():
    """One seed: no spread, the interval is (-inf, inf) around the value, se inf."""
    got = ss.t_interval([0.7])
    assert got.mean == 0.7 and got.n == 1
    assert got.low == -np.inf and got.high == np.inf and got.se == np.inf
    assert ss.decide(got) == ss.UNDECIDED


@pytest.mark.parametrize("bad", [[1.0, np.nan, 2.0], [1.0, np.inf], [-np.inf, 0.0], []])
def test_t_interval_rejects_non_finite_and_empty(bad):
    """A NaN or infinite per-seed value, or no value at all: ValueError (never silently dropped)."""
    with pytest.raises(ValueError):
        ss.t_interval(bad)


@pytest.mark.parametrize("level", [0.0, 1.0, -0.5, 1.5, 95.0])
def test_t_interval_rejects_level_outside_unit_interval(level):
    """The level must lie in the open interval (0, 1)."""
    with pytest.raises(ValueError, match="level"):
        ss.t_interval([1.0, 2.0, 3.0], level)


# ----------------------------------------------------------------------------- decide
@pytest.mark.parametrize(
    "low, high, verdict",
    [
        (0.1, 0.5, "confirmed"),  # entirely above 0
        (1e-300, 1.0, "confirmed"),
        (-0.5, -0.1, "refuted"),  # entirely below 0
        (-1.0, -1e-300, "refuted"),
        (-0.1, 0.2, "undecided"),  # straddles 0
        (0.0, 0.3, "undecided"),  # touches 0 from above: lo > 0 fails
        (-0.3, 0.0, "undecided"),  # touches 0 from below: hi < 0 fails
        (0.0, 0.0, "undecided"),
        (-np.inf, np.inf, "undecided"),
    ],
)
def test_decide(low, high, verdict):
    """confirmed iff low > 0, refuted iff high < 0, undecided otherwise."""
    interval = Interval(mean=0.0, se=1.0, low=low, high=high, n=3, level=0.95)  # only low, high matter
    assert ss.decide(interval) == verdict
    assert verdict == {"confirmed": ss.CONFIRMED, "refuted": ss.REFUTED, "undecided": ss.UNDECIDED}[verdict]


# ----------------------------------------------------------------------------- seeds_needed
def _brute_force_seeds(mean: float, sd: float, level: float, n_max: int = 5000) -> float:
    """Smallest n in 2..n_max with t_{(1+level)/2, n-1} sd / sqrt(n) < |mean| (inf if none)."""
    n = np.arange(2, n_max + 1)
    ok = stats.t.ppf(0.5 + level / 2.0, n - 1) * sd / np.sqrt(n) < abs(mean)
    return float(n[np.argmax(ok)]) if ok.any() else np.inf


@pytest.mark.parametrize(
    "values",
    [
        [0.1, -0.05, 0.3],  # undecided with 3 seeds
        [1.0, -0.8, 0.5, 0.2],
        [0.01, -0.2, 0.25, 0.05, -0.07],
        [-0.4, 0.1, -0.3],  # negative mean: |mean| counts
        [1.0, 1.1, 0.9],  # already decided: the answer may be below n
        [5.0, 5.1],
        [0.02, -0.3, 0.31, 0.1, -0.1, 0.02],  # needs thousands (2287 at 95 %)
    ],
)
@pytest.mark.parametrize("level", [0.95, 0.9])
def test_seeds_needed_brute_force(values, level):
    """seeds_needed = smallest n >= 2 with t_{(1+level)/2, n-1} sd / sqrt(n) < |mean| (mean, sd of the
    observed seeds, sd with ddof 1), found here by trying every n in 2..5000."""
    mean, sd = sum(values) / len(values), _sd(values)
    expected = _brute_force_seeds(mean, sd, level)
    assert np.isfinite(expected), "choose values needing fewer than 5000 seeds"
    assert ss.seeds_needed(ss.t_interval(values, level)) == expected


def test_seeds_needed_crosses_between_powers_of_two():
    """Hand-made intervals whose answers fall everywhere between 2 and 5000 (the code doubles then
    bisects): every answer equals the brute-force search."""
    for ratio in (0.05, 0.1, 0.3, 0.55, 0.9, 1.3, 3.0, 10.0):  # |mean| / sd
        for n in (2, 3, 7):
            sd = 1.0
            interval = Interval(mean=ratio * sd, se=sd / math.sqrt(n), low=np.nan, high=np.nan, n=n, level=0.95)
            assert ss.seeds_needed(interval) == _brute_force_seeds(ratio * sd, sd, 0.95), (ratio, n)


def test_seeds_needed_zero_mean_is_infinite():
    """t sd / sqrt(n) < |0| never holds."""
    assert ss.seeds_needed(ss.t_interval([-1.0, 0.0, 1.0])) == np.inf
    assert ss.seeds_needed(Interval(0.0, 0.0, 0.0, 0.0, 4, 0.95)) == np.inf


def test_seeds_needed_beyond_max_seeds_is_infinite():
    """|mean| / sd = 0.01 needs about (1.96 / 0.01)^2 ~ 38 000 seeds > max_seeds = 10 000."""
    assert ss.seeds_needed(Interval(0.01, 1.0 / math.sqrt(3), np.nan, np.nan, 3, 0.95)) == np.inf


def test_seeds_needed_one_seed_is_nan():
    """One seed: the spread is unknown, so no number of seeds can be given: NaN."""
    assert np.isnan(ss.seeds_needed(ss.t_interval([0.4])))


def test_seeds_needed_zero_spread_is_two():
    """With sd = 0 and mean != 0, t sd / sqrt(n) = 0 < |mean| already holds at n = 2, so the smallest
    n (docstring, and docs/verdict_statistics.md Sec. 4) is 2, as for any tiny positive spread."""
    tiny = ss.t_interval([1.0, 1.0 + 1e-12, 1.0, 1.0])
    assert ss.seeds_needed(tiny) == 2.0 == _brute_force_seeds(tiny.mean, tiny.se * 2.0, 0.95)
    assert ss.seeds_needed(ss.t_interval([1.0, 1.0, 1.0, 1.0])) == 2.0


# ----------------------------------------------------------------------------- jackknife
@pytest.mark.parametrize(
    "values",
    [
        [0.3, -0.1, 0.5],
        [1.0, 2.0, 3.0, 4.0, 5.0],
        [2.0, 2.5],
        [0.12, 0.08, 0.11, 0.3, -0.02, 0.07, 0.15],
    ],
)
def test_jackknife_of_mean_is_standard_error(values):
    """For the mean, the jackknife error sqrt((n-1)/n sum (m_(i) - m_(.))^2) equals sd(ddof=1)/sqrt(n)
    exactly (m_(i) - m_(.) = -(x_i - xbar)/(n - 1))."""
    per_seed = dict(zip([11, 23, 5, 42, 7, 8, 9][: len(values)], values))

    def statistic(seeds):
        return sum(per_seed[s] for s in seeds) / len(seeds)

    value, error = ss.jackknife(statistic, per_seed)
    assert value == pytest.approx(sum(values) / len(values), rel=1e-13, abs=1e-15)
    assert error == pytest.approx(_sd(values) / math.sqrt(len(values)), rel=1e-12)


def test_jackknife_of_a_nonlinear_statistic_by_hand():
    """statistic = max over the seeds: values (1, 2, 5): leave-one-out maxima (5, 5, 2), mean 4,
    error sqrt(2/3 (1 + 1 + 4)) = 2."""
    per_seed = {1: 1.0, 2: 2.0, 3: 5.0}
    value, error = ss.jackknife(lambda seeds: max(per_seed[s] for s in seeds), per_seed)
    assert value == 5.0
    assert error == pytest.approx(2.0, rel=1e-14)


def test_jackknife_one_seed_has_nan_error():
    """One seed: statistic([seed]) = 3 x 1 and no leave-one-out sample: NaN error."""
    value, error = ss.jackknife(lambda seeds: 3.0 * len(seeds), [4])
    assert value == 3.0 and np.isnan(error)


# ----------------------------------------------------------------------------- seed_bootstrap
@pytest.mark.parametrize("level", [0.95, 0.9, 0.5])
def test_seed_bootstrap_three_seeds_is_exhaustive(level):
    """3 seeds: 3^3 = 27 <= 20 000 resamples, so all 27 ordered triples (a, b, c) are taken; the
    interval is the (1 -+ level)/2 quantiles (numpy's linear rule) of their 27 means."""
    per_seed = {10: 0.2, 20: -0.4, 30: 1.3}
    labels = list(per_seed)
    means = [(per_seed[a] + per_seed[b] + per_seed[c]) / 3.0 for a in labels for b in labels for c in labels]
    assert len(means) == 27
    low, high = np.quantile(means, [(1.0 - level) / 2.0, (1.0 + level) / 2.0])

    value, got_low, got_high = ss.seed_bootstrap(lambda seeds: np.mean([per_seed[s] for s in seeds]), labels, level)
    assert value == pytest.approx((0.2 - 0.4 + 1.3) / 3.0)
    assert got_low == pytest.approx(low, abs=1e-14)
    assert got_high == pytest.approx(high, abs=1e-14)


def test_seed_bootstrap_three_seeds_by_hand():
    """Values (0, 0, 9): a triple's mean is 3k, k the number of draws of the third seed; k = 0..3 occurs
    8, 12, 6, 1 times out of 27, so the 27 sorted means are 0 x8, 3 x12, 6 x6, 9 x1. Level 0.5:
    quantile 0.25 sits at position 26 x 0.25 = 6.5 (0-based) -> 0; quantile 0.75 at position 19.5,
    halfway between sorted[19] = 3 and sorted[20] = 6 -> 4.5."""
    per_seed = {1: 0.0, 2: 0.0, 3: 9.0}
    value, low, high = ss.seed_bootstrap(lambda seeds: np.mean([per_seed[s] for s in seeds]), [1, 2, 3], 0.5)
    assert value == 3.0
    assert low == pytest.approx(0.0, abs=1e-14)
    assert high == pytest.approx(4.5, abs=1e-12)


def test_seed_bootstrap_eight_seeds_is_reproducible():
    """8 seeds: 8^8 > 20 000, so 20 000 random resamples from a fixed generator seed: the same result
    twice, an interval around the value inside the range of the data."""
    rng = np.random.default_rng(3)
    per_seed = dict(zip(range(100, 108), rng.normal(size=8)))

    def statistic(seeds):
        return float(np.mean([per_seed[int(s)] for s in seeds]))

    first = ss.seed_bootstrap(statistic, list(per_seed))
    second = ss.seed_bootstrap(statistic, list(per_seed))
    assert first == second
    value, low, high = first
    data = np.array(list(per_seed.values()))
    assert value == pytest.approx(data.mean())
    assert data.min() < low < value < high < data.max()
    # The percentile interval of a mean is close to mean -+ 1.96 sd(ddof=0)/sqrt(n) (20 000 draws).
    half = 1.959964 * data.std() / math.sqrt(8)
    assert low == pytest.approx(value - half, abs=0.1 * half)
    assert high == pytest.approx(value + half, abs=0.1 * half)


def test_seed_bootstrap_one_seed_is_nan():
    """One seed: the value, and NaN bounds."""
    value, low, high = ss.seed_bootstrap(lambda seeds: 2.0, [1])
    assert value == 2.0 and np.isnan(low) and np.isnan(high)


def test_seed_bootstrap_rejects_bad_level():
    """level = 1 is outside (0, 1): ValueError."""
    with pytest.raises(ValueError, match="level"):
        ss.seed_bootstrap(lambda seeds: 1.0, [1, 2, 3], level=1.0)


@pytest.mark.parametrize("n", [3, 7])
def test_bootstrap_of_the_mean_takes_the_same_resamples_as_seed_bootstrap(n):
    """seed_bootstrap_of_mean(f, curves) = seed_bootstrap(f(mean of the resample's curves)): every
    resample at n = 3 (27), 20 000 drawn at n = 7; vectorized or not."""
    from suspension_fabric.analysis.seed_statistics import seed_bootstrap, seed_bootstrap_of_mean

    curves = np.random.default_rng(n).normal(size=(n, 11))
    seeds = list(range(10, 10 + n))
    by_seed = dict(zip(seeds, curves))

    def first_above(mean):
        return float(np.argmax(mean > 0.1))

    expected = seed_bootstrap(lambda subset: first_above(np.mean([by_seed[s] for s in subset], axis=0)), seeds)
    assert seed_bootstrap_of_mean(first_above, curves) == pytest.approx(expected, rel=1e-12)
    expected = seed_bootstrap(lambda subset: float(np.mean([by_seed[s] for s in subset])), seeds)
    vectorized = seed_bootstrap_of_mean(lambda means: means.mean(axis=1), curves, vectorized=True)
    assert vectorized == pytest.approx(expected, rel=1e-12)


def test_the_interval_t_test_is_the_test_the_t_interval_inverts():
    """From a t-interval's mean, bounds, level and n, the two-sided p equals the t-test's on the values, and
    p < 0.05 exactly when the 95% interval excludes 0."""
    rng = np.random.default_rng(5)
    for shift in (0.0, 0.3, 1.0, 2.0):
        values = rng.normal(shift, 1.0, size=6)
        interval = ss.t_interval(values, 0.95)
        p = ss.interval_t_test_p(interval.mean, interval.low, interval.high, interval.n, 0.95)
        assert p == pytest.approx(ss.t_test_p(values), rel=1e-9)
        assert (p < 0.05) == (interval.low > 0 or interval.high < 0)
    assert np.isnan(ss.interval_t_test_p(0.1, 0.0, 0.2, 1))


def test_a_verdict_after_adjustment_is_decided_only_below_the_level():
    assert ss.decide_adjusted(0.2, 0.01) == ss.CONFIRMED and ss.decide_adjusted(-0.2, 0.049) == ss.REFUTED
    assert ss.decide_adjusted(0.2, 0.05) == ss.UNDECIDED and ss.decide_adjusted(0.2, np.nan) == ss.UNDECIDED


def test_variance_pseudo_values_average_to_the_variance_and_carry_its_error():
    """Pseudo-values n s^2 - (n - 1) s^2_(-i): their mean is s^2 (ddof 1) exactly; fewer than three
    seeds give s^2 to every seed (0 for one)."""
    x = np.random.default_rng(2).normal(size=(7, 4))
    q = ss.variance_pseudo_values(x)
    np.testing.assert_allclose(q.mean(axis=0), x.var(axis=0, ddof=1), rtol=1e-12)
    i = 3
    np.testing.assert_allclose(q[i], 7 * x.var(axis=0, ddof=1) - 6 * np.delete(x, i, axis=0).var(axis=0, ddof=1))
    np.testing.assert_allclose(ss.variance_pseudo_values(x[:2]), np.broadcast_to(x[:2].var(axis=0, ddof=1), (2, 4)))
    assert (ss.variance_pseudo_values(x[:1]) == 0.0).all()
    np.testing.assert_allclose(ss.variance_pseudo_values(x.T, axis=1), q.T)

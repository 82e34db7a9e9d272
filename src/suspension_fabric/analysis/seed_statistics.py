"""Statistics with the seeds as the independent units: t-intervals, the three-way decision rule,
the number of seeds a decision needs, and resampling over seeds (jackknife, bootstrap).

The decision rule (docs/verdict_statistics.md, Sec. 4): a decision statistic T is computed per
seed, with the claim's effect size built in so that T > 0 says what the claim says; with the
two-sided t-interval [lo, hi] of its seed mean at ``level``: "confirmed" if lo > 0, "refuted" if
hi < 0, "undecided" otherwise. When the true T is 0 each wrong verdict has probability
(1 - level) / 2.
"""

from __future__ import annotations

import functools
import itertools
from typing import NamedTuple

import numpy as np

__all__ = [
    "LEVEL",
    "CONFIRMED",
    "REFUTED",
    "UNDECIDED",
    "Interval",
    "t_interval",
    "welch_interval",
    "decide",
    "decide_adjusted",
    "interval_t_test_p",
    "seeds_needed",
    "jackknife",
    "variance_pseudo_values",
    "seed_bootstrap",
    "bootstrap_means",
    "seed_bootstrap_of_mean",
    "t_test_p",
    "adjusted_p",
]

#: Default confidence level of every interval (two-sided); config key ``verdicts.level``.
LEVEL = 0.95
CONFIRMED, REFUTED, UNDECIDED = "confirmed", "refuted", "undecided"
# Exhaustive bootstrap (every resample of n seeds with replacement) up to this many resamples;
# above it, this many random ones from a fixed generator seed (reproducible).
_BOOTSTRAP_EXHAUSTIVE = 20_000
_BOOTSTRAP_SEED = 20260


class Interval(NamedTuple):
    """Mean over n seeds, its standard error and the two-sided t-interval at ``level``."""

    mean: float
    se: float
    low: float
    high: float
    n: int
    level: float


def _check_level(level: float) -> float:
    level = float(level)
    if not 0.0 < level < 1.0:
        raise ValueError(f"confidence level must lie in (0, 1), got {level}")
    return level


def _student_quantile(level: float, dof: float) -> float:
    """The two-sided quantile t_{1-a/2, dof}, by scipy.special.stdtrit (what scipy.stats.t.ppf calls,
    without importing scipy.stats); imported here, as many table jobs import this module and never
    ask for one (scipy.special takes about 0.4 s to import)."""
    from scipy.special import stdtrit

    return float(stdtrit(dof, 0.5 + level / 2.0))


@functools.lru_cache(maxsize=4096)
def _t_quantile(level: float, dof: int) -> float:
    """`_student_quantile` for a whole number of degrees of freedom, cached (the same few are asked for)."""
    return _student_quantile(level, dof)


def t_interval(values, level: float = LEVEL, extra_se: float = 0.0) -> Interval:
    """Student t-interval of the mean of per-seed values (n - 1 degrees of freedom).

    ``extra_se``: a standard error from outside the seeds (e.g. of fitted parameters the values
    depend on), added in quadrature to the seeds' own. Non-finite values are an error (a seed whose
    statistic cannot be computed must be named by the caller, not silently dropped). One value gives
    an infinite interval.
    """
    level = _check_level(level)
    values = np.asarray(values, dtype=float).ravel()
    if values.size == 0:
        raise ValueError("t_interval needs at least one value")
    if not np.all(np.isfinite(values)):
        raise ValueError(f"t_interval: non-finite per-seed values {values.tolist()}")
    n, mean = values.size, float(values.mean())
    if n < 2:
        return Interval(mean, np.inf, -np.inf, np.inf, n, level)
    se = float(np.hypot(values.std(ddof=1) / np.sqrt(n), extra_se))
    half = _t_quantile(level, n - 1) * se
    return Interval(mean, se, mean - half, mean + half, n, level)


def decide(interval: Interval) -> str:
    """Three-way verdict on a decision statistic whose sign is the claim (T > 0: as the paper)."""
    if interval.low > 0.0:
        return CONFIRMED
    if interval.high < 0.0:
        return REFUTED
    return UNDECIDED


def decide_adjusted(mean: float, p_adjusted: float, level: float = LEVEL) -> str:
    """The three-way verdict after a multiplicity adjustment: decided (by the sign of ``mean``) only
    where the adjusted p-value is below 1 - ``level``."""
    if not np.isfinite(p_adjusted) or p_adjusted >= round(1.0 - _check_level(level), 12):
        return UNDECIDED
    return CONFIRMED if mean > 0.0 else REFUTED


def interval_t_test_p(mean: float, low: float, high: float, n: int, level: float = LEVEL) -> float:
    """Two-sided p-value of the t-test behind a t-interval [low, high] at ``level`` over ``n`` seeds
    with this seed mean (its standard error is the half-width over the t quantile): p < 1 - level
    exactly when the interval excludes 0. NaN below two seeds or for an infinite interval."""
    if not (n >= 2 and np.isfinite(mean) and np.isfinite(low) and np.isfinite(high)):
        return np.nan
    se = 0.5 * (high - low) / _t_quantile(_check_level(level), n - 1)
    if se == 0.0:
        return 1.0 if mean == 0.0 else 0.0
    from scipy import stats

    return float(2.0 * stats.t.sf(abs(mean) / se, n - 1))


def seeds_needed(interval: Interval, max_seeds: int = 10_000) -> float:
    r"""Smallest $n$ for which the interval would exclude 0 if the observed mean and spread held:
    $t_{1-\alpha/2,\,n-1}\,s/\sqrt{n} < |\bar x|$ ($\bar x$ the mean, $s$ the standard deviation
    over seeds, $t_{1-\alpha/2,\,n-1}$ Student's two-sided quantile at the interval's level
    $1 - \alpha$); inf if the mean is 0 or more than ``max_seeds`` are needed, nan if the spread
    is unknown (one seed)."""
    if interval.n < 2:
        return np.nan
    sd = interval.se * np.sqrt(interval.n)
    if sd == 0.0:
        return 2.0 if interval.mean != 0.0 else np.inf  # no spread: two seeds already decide
    if interval.mean == 0.0:
        return np.inf

    def decides(n: int) -> bool:
        return _t_quantile(interval.level, n - 1) * sd / np.sqrt(n) < abs(interval.mean)

    # The half-width falls with n: double until it decides, then bisect.
    high = 2
    while not decides(high):
        if high >= max_seeds:
            return np.inf
        high = min(2 * high, max_seeds)
    low = max(high // 2, 1)  # decides(low) is False unless low < 2
    while high - low > 1:
        middle = (low + high) // 2
        low, high = (low, middle) if decides(middle) else (middle, high)
    return float(high)


def jackknife(statistic, seeds) -> tuple[float, float]:
    """statistic(all seeds) and its jackknife standard error (leave one seed out).

    For smooth functions of the seeds' data only (a fit, a mean); never for a minimum or a
    first-crossing strain, whose leave-one-out values are not a sampling distribution.
    """
    seeds = list(seeds)
    value = float(statistic(seeds))
    if len(seeds) < 2:
        return value, np.nan
    leave_one_out = np.array([statistic([s for s in seeds if s != left]) for left in seeds], dtype=float)
    n = len(seeds)
    return value, float(np.sqrt((n - 1) / n * np.sum((leave_one_out - leave_one_out.mean()) ** 2)))


def variance_pseudo_values(values, axis: int = 0) -> np.ndarray:
    """Per seed (along ``axis``), the jackknife pseudo-values n s^2 - (n - 1) s^2_(-i) of the
    between-seed variance s^2 (ddof 1), elementwise over the other axes; the seeds' axis is kept.

    s^2 is an unbiased U-statistic, so the pseudo-values' mean over the seeds is s^2 itself to
    round-off; a noise floor subtracted seed by seed as its pseudo-value leaves every point
    estimate as it was, and a t-interval over seeds then carries the floor's own sampling error.
    With fewer than three seeds no seed can be left out of a variance: every seed gets s^2 (0 for
    one seed), the floor taken as known.
    """
    values = np.moveaxis(np.asarray(values, dtype=float), axis, 0)
    n = values.shape[0]
    if n < 2:
        return np.moveaxis(np.zeros_like(values), 0, axis)
    whole = np.var(values, axis=0, ddof=1)
    if n < 3:
        return np.moveaxis(np.broadcast_to(whole, values.shape).copy(), 0, axis)
    left_out = np.stack([np.var(np.delete(values, i, axis=0), axis=0, ddof=1) for i in range(n)])
    return np.moveaxis(n * whole - (n - 1) * left_out, 0, axis)


def seed_bootstrap(statistic, seeds, level: float = LEVEL) -> tuple[float, float, float]:
    """statistic(all seeds) and the percentile interval of statistic over resamples of the seeds
    with replacement: (value, low, high). Every resample is taken when there are at most 20 000
    (4 seeds: 256), else 20 000 drawn from a fixed generator seed, so the result is reproducible.
    Descriptive only: with a handful of seeds it is coarse and no verdict rests on it."""
    level = _check_level(level)
    seeds = list(seeds)
    value = float(statistic(seeds))
    n = len(seeds)
    if n < 2:
        return value, np.nan, np.nan
    if n**n <= _BOOTSTRAP_EXHAUSTIVE:
        resamples = itertools.product(seeds, repeat=n)
    else:
        generator = np.random.default_rng(_BOOTSTRAP_SEED)
        resamples = (list(generator.choice(seeds, size=n)) for _ in range(_BOOTSTRAP_EXHAUSTIVE))
    values = np.array([statistic(list(sample)) for sample in resamples], dtype=float)
    low, high = np.quantile(values, [0.5 - level / 2.0, 0.5 + level / 2.0])
    return value, float(low), float(high)


def _resample_indices(n: int) -> np.ndarray:
    """The resamples of [`seed_bootstrap`][suspension_fabric.analysis.seed_statistics.seed_bootstrap] as indices into
    its seeds, in its order: every resample when there are at most 20 000, else 20 000 from the same fixed generator
    seed."""
    if n**n <= _BOOTSTRAP_EXHAUSTIVE:
        return np.array(list(itertools.product(range(n), repeat=n)), dtype=np.intp)
    return np.random.default_rng(_BOOTSTRAP_SEED).choice(n, size=(_BOOTSTRAP_EXHAUSTIVE, n))


def bootstrap_means(per_seed) -> np.ndarray:
    """The mean over the seeds of every resample of
    [`seed_bootstrap`][suspension_fabric.analysis.seed_statistics.seed_bootstrap] at once: ``per_seed`` holds one array
    per seed along its first axis (n, ...); returns (resamples, ...)."""
    per_seed = np.asarray(per_seed, dtype=float)
    n = per_seed.shape[0]
    indices = _resample_indices(n)
    counts = np.zeros((len(indices), n))
    np.add.at(counts, (np.arange(len(indices))[:, None], indices), 1.0)
    return (counts @ per_seed.reshape(n, -1) / n).reshape((len(indices), *per_seed.shape[1:]))


def seed_bootstrap_of_mean(
    statistic, per_seed, level: float = LEVEL, *, vectorized: bool = False
) -> tuple[float, float, float]:
    """[`seed_bootstrap`][suspension_fabric.analysis.seed_statistics.seed_bootstrap] of a statistic of the seed mean,
    statistic(mean over seeds of ``per_seed``), with the resampled means computed at once (same resamples, same result
    up to the order of a floating-point sum): (value, low, high). ``vectorized``: the statistic takes
    the stacked means (resamples first) and returns one value per resample."""
    level = _check_level(level)
    per_seed = np.asarray(per_seed, dtype=float)
    whole = per_seed.mean(axis=0)
    value = float(statistic(whole[None])[0] if vectorized else statistic(whole))
    if per_seed.shape[0] < 2:
        return value, np.nan, np.nan
    means = bootstrap_means(per_seed)
    values = np.asarray(statistic(means) if vectorized else [statistic(mean) for mean in means], dtype=float)
    low, high = np.quantile(values, [0.5 - level / 2.0, 0.5 + level / 2.0])
    return value, float(low), float(high)


def welch_interval(first, second, level: float = LEVEL) -> Interval:
    """Interval of mean(first) - mean(second) for two independent sets of per-seed values with
    unequal spreads: Welch's t with the Welch-Satterthwaite degrees of freedom. ``n`` is the
    smaller set's size; each set needs at least two values."""
    level = _check_level(level)
    a, b = (np.asarray(values, dtype=float).ravel() for values in (first, second))
    if a.size < 2 or b.size < 2:
        raise ValueError(f"welch_interval needs at least two values per set, got {a.size} and {b.size}")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise ValueError("welch_interval: non-finite per-seed values")
    va, vb = a.var(ddof=1) / a.size, b.var(ddof=1) / b.size
    difference, se = float(a.mean() - b.mean()), float(np.sqrt(va + vb))
    if se == 0.0:
        return Interval(difference, 0.0, difference, difference, min(a.size, b.size), level)
    dof = (va + vb) ** 2 / (va**2 / (a.size - 1) + vb**2 / (b.size - 1))
    half = _student_quantile(level, dof) * se
    return Interval(difference, se, difference - half, difference + half, min(a.size, b.size), level)


def t_test_p(values, extra_se: float = 0.0) -> float:
    """Two-sided p-value of Student's t-test that the per-seed values have mean zero (the test the
    t-interval inverts, ``extra_se`` as there: p < 1 - level exactly when the interval excludes 0);
    1 for values all zero."""
    values = np.asarray(values, dtype=float).ravel()
    if values.size < 2:
        return 1.0
    se = float(np.hypot(values.std(ddof=1) / np.sqrt(values.size), extra_se))
    if se == 0.0:
        return 1.0 if values.mean() == 0.0 else 0.0
    from scipy import stats

    return float(2.0 * stats.t.sf(abs(values.mean()) / se, values.size - 1))


def adjusted_p(p_values, method: str = "holm") -> np.ndarray:
    """p-values adjusted for the number of cells read at once (statsmodels' multipletests: "holm",
    family-wise error; "fdr_bh", Benjamini-Hochberg false discovery rate); NaN stays NaN."""
    from statsmodels.stats.multitest import multipletests

    p_values = np.asarray(p_values, dtype=float)
    adjusted = np.full(p_values.shape, np.nan)
    finite = np.isfinite(p_values)
    if finite.any():
        adjusted[finite] = multipletests(p_values[finite], method=method)[1]
    return adjusted

"""A study against other datasets (suspension_fabric.evaluation.dataset_comparison): per-seed statistics and
Welch intervals of the differences, against answers worked out independently."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from suspension_fabric.analysis.seed_statistics import welch_interval
from suspension_fabric.evaluation.dataset_comparison import FABRIC_QUANTITIES, comparison_table, per_seed_statistics


def test_welch_interval_equals_scipy_welch_test():
    """Difference of means with the Welch-Satterthwaite dof: scipy's ttest_ind(equal_var=False)."""
    a, b = [1.0, 2.0, 3.5, 4.0], [2.0, 4.5, 6.0, 8.0, 7.0]
    interval = welch_interval(a, b, 0.9)
    reference = stats.ttest_ind(a, b, equal_var=False).confidence_interval(0.9)
    assert interval.mean == pytest.approx(np.mean(a) - np.mean(b), rel=1e-12)
    assert (interval.low, interval.high) == pytest.approx((reference.low, reference.high), rel=1e-10)
    with pytest.raises(ValueError, match="at least two"):
        welch_interval([1.0], b)


def _startup(values_by_seed):
    """Startup runs whose every quantity is constant per seed over strain [0, 5]."""
    strain = np.linspace(0.0, 5.0, 26)
    return pd.concat(
        [
            pd.DataFrame({"seed": seed, "strain": strain, **{q: value for q in FABRIC_QUANTITIES}})
            for seed, value in values_by_seed.items()
        ],
        ignore_index=True,
    )


def test_comparison_of_two_datasets_by_hand():
    """Per-seed window means of constant runs are the constants; the difference of two datasets is
    the difference of the seed means, 'differs' when Welch's interval excludes 0."""
    near = per_seed_statistics(_startup({1: 1.0, 2: 1.2, 3: 1.1}), None, None, (2.0, 5.0), 2.0)
    assert sorted(near[near["quantity"] == "Z"]["value"]) == pytest.approx([1.0, 1.1, 1.2])
    far = per_seed_statistics(_startup({1: 3.0, 2: 3.1, 3: 2.9, 4: 3.0}), None, None, (2.0, 5.0), 2.0)
    same = per_seed_statistics(_startup({1: 1.05, 2: 1.15}), None, None, (2.0, 5.0), 2.0)
    table = comparison_table({"study": (1000, near), "far": (500, far), "same": (2000, same)}, "study", 0.95)
    row = table[(table["dataset"] == "far") & (table["quantity"] == "n12")].iloc[0]
    assert row["N"] == 500 and row["seeds"] == 4 and row["mean"] == pytest.approx(3.0)
    assert row["difference"] == pytest.approx(3.0 - 1.1) and row["verdict"] == "differs"
    assert table[(table["dataset"] == "same") & (table["quantity"] == "Z")].iloc[0]["verdict"] == "agrees"
    own = table[table["dataset"] == "study"].iloc[0]
    assert np.isnan(own["difference"]) and own["mean"] == pytest.approx(1.1)
    assert set(table["quantity"]) == set(FABRIC_QUANTITIES)  # no stress given, no stress rows

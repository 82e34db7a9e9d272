"""The closures held against a measured fourth moment (suspension_fabric.evaluation.closure_tests),
on direction sets whose answers are known."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis.fabric import (
    COMPONENTS,
    FOURTH_MOMENT_COMPONENTS,
    HARMONIC_COLUMNS,
    direction_moments,
)
from suspension_fabric.evaluation import closure_tests


def table_of(normal_sets, n_particles=10, seed=1, theta=0.0) -> pd.DataFrame:
    """A fabric table (the columns the closure tests read), one frame per set of directions."""
    rows = []
    for frame, normals in enumerate(normal_sets):
        second, fourth, harmonics = direction_moments(normals, n_particles)
        row = {"seed": seed, "theta": theta, "strain": 0.1 * frame}
        row.update({name: second[i, j] for name, (i, j) in COMPONENTS.items()})
        row.update(dict(zip(FOURTH_MOMENT_COMPONENTS, fourth)))
        row.update(dict(zip(HARMONIC_COLUMNS, harmonics)))
        rows.append(row)
    return pd.DataFrame(rows)


def test_aligned_directions_are_closed_exactly_by_the_quadratic_closure_only():
    """Every contact along one direction: the quadratic and hybrid closures give the measured <nnnn>
    (both measures 0), the linear one does not (full > 0.4)."""
    e = np.array([2.0, 1.0, 2.0]) / 3.0
    errors = closure_tests.frame_errors(table_of([np.tile(e, (5, 1))])).set_index("closure")
    assert errors.loc["quadratic", "full"] < 1e-14 and errors.loc["quadratic", "drive"] < 1e-14
    assert errors.loc["hybrid", "full"] < 1e-14
    assert errors.loc["linear", "full"] > 0.4


def test_seed_means_and_the_paired_difference_from_the_papers_closure():
    """Per seed the mean over the window's frames; over seeds the mean and t-interval; the paired
    difference from the linear closure is the seed mean of the per-seed differences."""
    rng = np.random.default_rng(5)
    tables = []
    for seed in (1, 2, 3):
        sets = [rng.normal(size=(30, 3)) * np.array([1.5, 1.0, 0.7]) for _ in range(4)]
        tables.append(table_of([v / np.linalg.norm(v, axis=1)[:, None] for v in sets], seed=seed))
    errors = closure_tests.frame_errors(pd.concat(tables, ignore_index=True))
    per_seed = closure_tests.seed_window_errors(errors, (0.1, 0.3))
    assert set(per_seed["seed"]) == {1, 2, 3} and len(per_seed) == 3 * len(closure_tests.CLOSURES)
    inside = errors[errors["strain"].between(0.1, 0.3 + 1e-12)]
    expected = inside[inside["closure"] == "quadratic"].groupby("seed")["full"].mean()
    got = per_seed[per_seed["closure"] == "quadratic"].set_index("seed")["full"]
    np.testing.assert_allclose(got.sort_index(), expected.sort_index())
    table = closure_tests.closure_error_table(per_seed).set_index(["closure", "measure"])
    linear = per_seed[per_seed["closure"] == "linear"].set_index("seed")["full"]
    assert table.loc[("quadratic", "full"), "difference"] == pytest.approx((got - linear).mean())
    assert table.loc[("quadratic", "full"), "n_seeds"] == 3 and np.isnan(table.loc[("linear", "full"), "difference"])


def test_low_order_amplitudes_follow_from_the_fourth_moment():
    """a_lm of orders 0, 2, 4 from <nnnn> alone (amplitudes_from_moments) equal the amplitudes summed
    over the directions themselves (direction_moments), to round-off."""
    rng = np.random.default_rng(9)
    normals = rng.normal(size=(40, 3)) * np.array([1.2, 1.0, 0.6])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    _, fourth, harmonics = direction_moments(normals, 17)
    low = [HARMONIC_COLUMNS.index(name) for name in closure_tests.LOW_ORDER_COLUMNS]
    np.testing.assert_allclose(closure_tests.amplitudes_from_moments(fourth), harmonics[low], atol=1e-13)


def test_tables_made_before_the_fourth_moment_give_empty_results_with_their_columns():
    """A study on a dataset whose tables lack the moments: no frame, no row, the table's columns."""
    table = table_of([np.eye(3)])
    table[list(FOURTH_MOMENT_COMPONENTS)] = np.nan
    per_seed = closure_tests.seed_window_errors(closure_tests.frame_errors(table), (0.0, 1.0))
    result = closure_tests.closure_error_table(per_seed)
    assert result.empty and {"closure", "theta", "measure", "mean", "difference", "level"} <= set(result.columns)

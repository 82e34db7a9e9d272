"""Tidy fabric tables: CSV format, seed aggregation, steady-state estimator (suspension_fabric.analysis.tables)."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis.fabric import FabricAnalysis
from suspension_fabric.analysis.tables import (
    TABLE_COLUMNS,
    VALUE_COLUMNS,
    aggregate_seeds,
    fabric_table,
    integrated_autocorrelation_time,
    read_fabric_table,
    run_fabric_table,
    steady_state,
    write_fabric_table,
)
from suspension_fabric.io.dumpio import DumpFrame, TriclinicBox, write_lammps_dump


def make_table(seed, theta, strain, values, n_particles=500, phi=0.45):
    """A per-run table whose value columns are ``values`` (frames, 7) or one series for all."""
    strain = np.asarray(strain, dtype=float)
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:
        values = np.repeat(values[:, None], len(VALUE_COLUMNS), axis=1)
    table = pd.DataFrame(
        {
            "seed": seed,
            "theta": float(theta),
            "N": n_particles,
            "phi": phi,
            "step": np.arange(len(strain)) * 100,
            "strain": strain,
        }
    )
    for k, name in enumerate(VALUE_COLUMNS):
        table[name] = values[:, k]
    return table[list(TABLE_COLUMNS)]


def test_run_fabric_table_uses_the_runs_time_step_first_step_and_angle(tmp_path):
    """A rotation by -30 degrees that started at step 1000 with dt = 2e-4, rate 0.5 (from its
    completion marker): strains (step - 1000) dt rate, theta -30, the fabric in the rotated
    frame, i.e. the table FabricAnalysis gives with these parameters; eps is passed on."""
    box = TriclinicBox(8.0, 8.0, 8.0, xz=1.0)
    base = np.array([[1.0, 1.0, 1.0], [2.004, 1.3, 1.0], [5.0, 5.0, 5.0], [5.2, 5.0, 6.0]])
    frames = [DumpFrame(1000 + 50 * k, box, base + 0.001 * k, np.full(4, 0.5)) for k in range(3)]
    dump = write_lammps_dump(tmp_path / "trajectory.dump", frames)
    marker = tmp_path / "run_complete.json"
    marker.write_text(
        json.dumps(
            {"variables": {"dt": "0.0002", "rate": "0.5", "theta_deg": "-30.0"}, "results": {"first_step": 1000}}
        )
    )
    table = run_fabric_table(dump, marker, seed=4, eps=0.05)
    np.testing.assert_allclose(table["strain"], [0.0, 0.005, 0.01])
    assert (table["theta"] == -30.0).all() and (table["seed"] == 4).all()
    expected = fabric_table(
        FabricAnalysis.from_dump(
            dump, dt=2e-4, shear_rate=0.5, shear_start_step=1000, flow_angle_deg=-30.0, eps=0.05
        ).run(),
        seed=4,
    )
    pd.testing.assert_frame_equal(table, expected)
    assert (table["Z"] > 0).all() and (table["n13"].abs() > 1e-3).all()  # contacts, rotated frame
    assert (run_fabric_table(dump, marker, seed=4, eps=0.001)["Z"] == 0).all()


def ar1_series(rng, n, rho, sigma=1.0):
    """Stationary AR(1) x_t = rho x_{t-1} + noise with variance sigma^2; tau_int = (1+rho) / (2(1-rho))."""
    noise = rng.normal(scale=sigma * np.sqrt(1 - rho**2), size=n)
    x = np.empty(n)
    x[0] = rng.normal(scale=sigma)
    for t in range(1, n):
        x[t] = rho * x[t - 1] + noise[t]
    return x


def test_aggregate_seeds_mean_and_standard_error():
    """c_mean = (1/S) sum_s c_s and c_sem = std_{ddof=1}(c_s) / sqrt(S) per (theta, strain).

    Three seeds with values 1, 2, 4 (+ frame index) at theta = 30; one seed at theta = 0
    (sem undefined -> NaN). Rows are given shuffled to check sorting by strain.
    """
    strain = [0.0, 0.1, 0.2]
    tables = [
        make_table(s, 30, strain, np.array(strain) * 0 + base + np.arange(3))
        for s, base in zip((1, 2, 3), (1.0, 2.0, 4.0))
    ]
    tables.append(make_table(9, 0, strain, [5.0, 6.0, 7.0]))
    table = pd.concat(tables).sample(frac=1.0, random_state=0)
    result = aggregate_seeds(table)
    rotated = result[result["theta"] == 30].reset_index(drop=True)
    np.testing.assert_allclose(rotated["strain"], strain)
    assert (rotated["n_seeds"] == 3).all()
    expected_mean = 7.0 / 3.0 + np.arange(3)
    expected_sem = np.std([1.0, 2.0, 4.0], ddof=1) / np.sqrt(3)
    for name in VALUE_COLUMNS:
        np.testing.assert_allclose(rotated[f"{name}_mean"], expected_mean, rtol=1e-12)
        np.testing.assert_allclose(rotated[f"{name}_sem"], expected_sem, rtol=1e-12)
    single = result[result["theta"] == 0]
    np.testing.assert_allclose(single["n12_mean"], [5.0, 6.0, 7.0])
    assert single["n12_sem"].isna().all()


@pytest.mark.parametrize("other_strain", [[0.0, 0.1, 0.25], [0.0, 0.1]], ids=["shifted", "shorter"])
def test_aggregate_seeds_rejects_different_strain_grids(other_strain):
    """Seeds of one theta whose strain grids differ raise ValueError naming theta and the seeds."""
    table = pd.concat(
        [
            make_table(1, 45, [0.0, 0.1, 0.2], [1.0, 2.0, 3.0]),
            make_table(2, 45, other_strain, np.ones(len(other_strain))),
        ]
    )
    with pytest.raises(ValueError, match=r"theta=45.0: strain grid of seed 2 .* seed 1"):
        aggregate_seeds(table)


def test_csv_round_trip_and_missing_column(tmp_path):
    """write/read keeps every value exactly; a CSV without a required column is named in the error."""
    rng = np.random.default_rng(3)
    table = make_table(4, 90, np.linspace(0, 1, 11), rng.random((11, len(VALUE_COLUMNS))))
    path = write_fabric_table(table, tmp_path / "table.csv")
    pd.testing.assert_frame_equal(read_fabric_table(path), table)
    table.drop(columns=["n23"]).to_csv(tmp_path / "broken.csv", index=False)
    with pytest.raises(ValueError, match=r"broken\.csv.*'n23'"):
        read_fabric_table(tmp_path / "broken.csv")
    with pytest.raises(FileNotFoundError, match="absent.csv"):
        read_fabric_table(tmp_path / "absent.csv")


@pytest.mark.parametrize("rho", [0.0, 0.8])
def test_integrated_autocorrelation_time_of_ar1(rho):
    """AR(1) with coefficient rho has tau_int = (1 + rho) / (2 (1 - rho)) frames (0.5 and 4.5 here)."""
    rng = np.random.default_rng(21)
    tau = integrated_autocorrelation_time(ar1_series(rng, 40000, rho))
    assert tau == pytest.approx((1 + rho) / (2 * (1 - rho)), rel=0.1)


def test_steady_state_error_accounts_for_correlation():
    """sem of the seed-averaged window mean matches the true sqrt(sigma^2 2 tau / n / S).

    Eight seeds of AR(1) noise (rho = 0.9, tau = 9.5 frames, sigma = 0.02) around 0.3 in
    the window strain in [2, 10]; frames before strain 2 carry a large transient that
    must be excluded. A naive sigma / sqrt(n S) would be sqrt(19) = 4.4 times too small.
    Over 40 repetitions the mean sem is within 15% of the true value and the
    mean itself is within 4 true standard errors of 0.3.
    """
    rng = np.random.default_rng(8)
    strain = np.arange(0, 10.0001, 0.005)
    window = strain >= 2.0
    n_in = window.sum()
    rho, sigma, n_seeds = 0.9, 0.02, 8
    true_sem = sigma * np.sqrt(2 * (1 + rho) / (2 * (1 - rho)) / n_in / n_seeds)
    sems, deviations = [], []
    for _ in range(40):
        tables = []
        for seed in range(n_seeds):
            values = 0.3 + ar1_series(rng, len(strain), rho, sigma) + np.where(window, 0.0, 5.0)
            tables.append(make_table(seed, 0, strain, values))
        result = steady_state(pd.concat(tables), strain_min=2.0, strain_max=10.0)
        row = result[result["quantity"] == "n12"].iloc[0]
        assert row["n_frames"] == n_in and row["n_seeds"] == n_seeds
        sems.append(row["sem"])
        deviations.append(row["mean"] - 0.3)
    assert np.mean(sems) == pytest.approx(true_sem, rel=0.15)
    assert abs(np.mean(deviations)) < 4 * true_sem / np.sqrt(40)
    assert np.std(deviations) == pytest.approx(true_sem, rel=0.35)


def test_steady_state_window_needs_two_frames():
    """A strain window holding fewer than 2 frames of a seed raises ValueError naming theta and seed."""
    table = make_table(5, 60, [0.0, 1.0, 2.0, 3.0], [1.0, 2.0, 3.0, 4.0])
    with pytest.raises(ValueError, match=r"theta=60.0: seed 5 has 1 frame\(s\)"):
        steady_state(table, strain_min=2.5, strain_max=3.5)

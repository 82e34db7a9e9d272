"""The steady-state verdicts and the descriptive tables on synthetic curves with known answers.

Recovery: a curve <nn>'_12 / n12_ss = 1 - a exp(-g / tau) enters the 10% band for good at
g* = tau ln(10 a), the first grid strain at or after it. rms: a model offset from every seed by
c |n12_ss| has rms error c. Steady-state verdicts: beyond 2 errors on the paper's side ->
confirmed, on the other side -> refuted, otherwise undecided. (The shear-rotation claims:
tests/evaluation/test_claims.py and tests/evaluation/test_claims_montecarlo.py.)"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import verdicts
from suspension_fabric.evaluation.claims import Compared
from suspension_fabric.models.fabric_models import GW, MODIFIED

#: The compared models by role (config verdicts.models), as keys and as models
COMPARED = {"reference": "gw", "challenger": "modified"}
PAIR = Compared(GW, MODIFIED)

N12_SS = -0.1
STRAIN = np.round(np.arange(0.0, 2.0 + 1e-9, 0.02), 10)
THETAS = (0.0, 45.0, 90.0, 135.0, 180.0)
SEEDS = (1, 2, 3, 4)


def relaxation(tau: float, amplitude: float = 1.0) -> np.ndarray:
    return N12_SS * (1.0 - amplitude * np.exp(-STRAIN / tau))


def runs(tau_sim: float, noise: float = 1e-4, n23_tau: float = 0.3) -> pd.DataFrame:
    rng = np.random.default_rng(5)
    rows = []
    for seed in SEEDS:
        for theta in THETAS:
            amplitude = 0.0 if theta == 0.0 else 1.0
            n12 = relaxation(tau_sim, amplitude) + noise * rng.standard_normal(len(STRAIN))
            n23 = -N12_SS * np.sin(np.radians(theta)) * np.exp(-STRAIN / n23_tau)
            rows.append(pd.DataFrame({"seed": seed, "theta": theta, "strain": STRAIN, "n12": n12, "n23": n23}))
    return pd.concat(rows, ignore_index=True)


def predictions(tau_gw: float, tau_modified: float, bump: float = 0.0, n23_tau: float = 0.3) -> pd.DataFrame:
    rows = []
    for model, tau in (("gw", tau_gw), ("modified", tau_modified)):
        for theta in THETAS:
            amplitude = 0.0 if theta == 0.0 else 1.0
            n12 = relaxation(tau, amplitude)
            if model == "modified" and theta == 90.0:
                n12 = n12 + N12_SS * bump * np.exp(-(((STRAIN - 0.8) / 0.15) ** 2))
            n23 = -N12_SS * np.sin(np.radians(theta)) * np.exp(-STRAIN / n23_tau)
            rows.append(
                pd.DataFrame(
                    {"model": model, "protocol": "rotation", "theta": theta, "strain": STRAIN, "n12": n12, "n23": n23}
                )
            )
    return pd.concat(rows, ignore_index=True)


def first_grid_strain_after(value: float) -> float:
    return float(STRAIN[np.searchsorted(STRAIN, value - 1e-12)])


def test_settle_strain_and_censoring():
    deviation = np.array([0.5, 0.05, 0.2, 0.05, 0.0])
    assert tables.settle_strain(np.arange(5.0), deviation) == (3.0, True)
    assert tables.settle_strain(np.arange(3.0), np.array([0.0, 0.0, 0.3])) == (2.0, False)
    with pytest.raises(ValueError, match="lengths"):
        tables.settle_strain(np.arange(5.0), np.zeros(3))
    assert tables.settle_strain(np.arange(3.0), np.zeros(3)) == (0.0, True)


def test_settle_strains_of_stacked_series_are_each_series_settle_strain():
    """The bootstraps' form: each row of a stack gets the first strain from which it stays inside
    the band, found by walking back from its end (settled inside, never outside, censored at the
    end, one point)."""

    def walked_back(row):
        if abs(row[-1]) > 0.1:
            return float(strain[-1]), False
        k = len(row) - 1
        while k > 0 and abs(row[k - 1]) <= 0.1:
            k -= 1
        return float(strain[k]), True

    strain = np.linspace(0.0, 3.0, 31)
    rows = np.random.default_rng(3).normal(scale=0.1, size=(200, 31))
    rows[0], rows[1], rows[2, -1] = 0.0, 1.0, 0.5
    settled_at, settled = tables.settle_strains(strain, rows, tolerance=0.1)
    assert [(float(a), bool(b)) for a, b in zip(settled_at, settled)] == [walked_back(row) for row in rows]
    assert [tables.settle_strain(strain, row, 0.1) for row in rows] == [walked_back(row) for row in rows]
    assert settled[0] and settled_at[0] == 0.0 and not settled[1] and settled_at[1] == 3.0
    stacked = tables.settle_strains(strain, rows.reshape(20, 10, 31), tolerance=0.1)[0]
    np.testing.assert_array_equal(stacked.ravel(), settled_at)
    assert tables.settle_strain(np.zeros(1), np.array([0.2]), 0.1) == (0.0, False)
    with pytest.raises(ValueError, match="lengths"):
        tables.settle_strains(strain, rows[:, :30])


def test_recovery_strains_follow_tau_ln_10a():
    table = verdicts.recovery_table(runs(0.2), predictions(0.5, 0.25), N12_SS, COMPARED).set_index("theta")
    for theta in (45.0, 90.0, 135.0):
        assert table.loc[theta, "reference_steady"] == first_grid_strain_after(0.5 * np.log(10))
        assert table.loc[theta, "challenger_steady"] == first_grid_strain_after(0.25 * np.log(10))
        assert table.loc[theta, "sim_steady"] == pytest.approx(first_grid_strain_after(0.2 * np.log(10)), abs=0.021)
        assert table.loc[theta, "sim_continuation"] == pytest.approx(table.loc[theta, "sim_steady"], abs=0.021)
    # <nn>'_23 = sin(theta) |n12_ss| exp(-g / 0.3): within 0.1 |n12_ss| from 0.3 ln(10 sin theta)
    assert table.loc[90.0, "reference_n23"] == first_grid_strain_after(0.3 * np.log(10))
    assert table.loc[0.0, "reference_steady"] == 0.0 and bool(table.loc[90.0, "reference_steady_settled"])


def test_rms_error_of_an_offset_model():
    simulation = runs(0.2, noise=0.0)
    model = predictions(0.2, 0.2)
    model.loc[model["model"] == "gw", "n12"] += 0.3 * abs(N12_SS)
    model.loc[model["model"] == "modified", "n12"] += 0.1 * abs(N12_SS)
    table = verdicts.rms_error_table(simulation, model, N12_SS, COMPARED)
    n12 = table[table["component"] == "n12"]
    np.testing.assert_allclose(n12["reference_rms"], 0.3, rtol=1e-9)
    np.testing.assert_allclose(n12["ratio"], 3.0, rtol=1e-9)
    np.testing.assert_allclose(n12["ratio_high"] - n12["ratio_low"], 0.0, atol=1e-9)  # identical seeds: no spread


def test_descriptive_intervals_are_seed_bootstrap_percentiles():
    """The bootstrap interval of a seed-mean quantity contains its value; identical seeds give a
    zero-width interval, and different seeds one that spans the per-seed values' range at most."""
    identical = verdicts.rms_error_table(runs(0.2, noise=0.0), predictions(0.3, 0.2), N12_SS, COMPARED)
    np.testing.assert_allclose(identical["reference_rms_high"] - identical["reference_rms_low"], 0.0, atol=1e-12)
    simulation = runs(0.2, noise=0.0)
    for k, seed in enumerate(SEEDS):  # seed k sits k * 0.05 |n12_ss| away from the model
        simulation.loc[simulation["seed"] == seed, "n12"] += k * 0.05 * abs(N12_SS)
    table = verdicts.rms_error_table(simulation, predictions(0.2, 0.2), N12_SS, COMPARED)
    n12 = table[(table["component"] == "n12") & (table["theta"] == 90.0)].iloc[0]
    # rms of the seed mean = the mean offset; a resample's mean offset lies within [0, 0.15]
    assert n12["reference_rms"] == pytest.approx(0.075)
    assert 0.0 <= n12["reference_rms_low"] < 0.075 < n12["reference_rms_high"] <= 0.15 + 1e-12
    overshoot = verdicts.overshoot_table(runs(0.2, noise=2e-3), predictions(0.5, 0.2, bump=0.3), N12_SS, COMPARED)
    row = overshoot.set_index("theta").loc[90.0]
    # the modified r12 - 1 = 0.3 exp(-((g - 0.8)/0.15)^2) - exp(-g/0.2): near 0.3 - exp(-4) at g ~ 0.8
    assert row["challenger"] == pytest.approx(0.3 - np.exp(-0.8 / 0.2), abs=0.003)
    assert row["sim_steady_low"] <= row["sim_steady"] <= row["sim_steady_high"]


def test_steady_state_verdicts():
    targets = {c: {"mean": m, "sem": 0.002} for c, m in (("n11", 0.55), ("n22", 0.60), ("n33", 0.59), ("n12", -0.10))}
    fits = {
        "targets": targets,
        "models": {
            "gw": {
                "fitted_to": ["n12"],
                "parameters": {"beta": 10.7},
                "errors": {"beta": 0.2},
                "steady_state": {"n11": 0.2, "n22": 0.3, "n33": 0.25},
            },
            "modified": {
                "fitted_to": ["n11", "n12"],
                "parameters": {"beta": 9.3, "A": 44.8},
                "errors": {"beta": 0.1, "A": 0.3},
                "steady_state": {"n11": 0.55, "n22": 0.62, "n33": 1.0},
            },
        },
    }
    rows = {row["text"]: row for row in verdicts.steady_state_verdicts(fits, PAIR)}
    assert rows["G-W (Eq. 1) underestimates the diagonal components"]["verdict"] == verdicts.CONFIRMED
    assert rows["modified G-W (Eq. 2) captures <nn>_22"]["verdict"] == verdicts.CONFIRMED  # 3.3% off
    assert rows["modified G-W (Eq. 2) overestimates <nn>_33"]["verdict"] == verdicts.CONFIRMED
    # the fitted parameters beside the ones the paper printed, each model by its label
    fitted = rows["modified G-W (Eq. 2) fitted on <nn>_11, <nn>_12 (paper A ~ 42.4)"]
    assert (fitted["mean"], fitted["low"], fitted["high"]) == (44.8, 44.8 - 0.6, 44.8 + 0.6)
    fits["models"]["gw"]["steady_state"]["n22"] = 0.65
    fits["models"]["modified"]["steady_state"]["n22"] = 0.75
    rows = {row["text"]: row for row in verdicts.steady_state_verdicts(fits, PAIR)}
    assert rows["G-W (Eq. 1) underestimates the diagonal components"]["verdict"] == verdicts.REFUTED
    assert rows["modified G-W (Eq. 2) captures <nn>_22"]["verdict"] == verdicts.REFUTED  # 25% off

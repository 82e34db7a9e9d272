"""The verdict machinery on synthetic curves with known answers.

Recovery: a curve <nn>'_12 / n12_ss = 1 - a exp(-g / tau) enters the 10% band for good at
g* = tau ln(10 a), the first grid strain at or after it. rms: a model offset from every seed by
c |n12_ss| has rms error c. Verdicts: beyond 2 errors on the paper's side -> confirmed, on the
other side -> refuted, otherwise not resolved."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from suspension_fabric import verdicts

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
                n12 = n12 + N12_SS * bump * np.exp(-((STRAIN - 0.8) / 0.15) ** 2)
            n23 = -N12_SS * np.sin(np.radians(theta)) * np.exp(-STRAIN / n23_tau)
            rows.append(pd.DataFrame({"model": model, "protocol": "rotation", "theta": theta, "strain": STRAIN,
                                      "n12": n12, "n23": n23}))
    return pd.concat(rows, ignore_index=True)


def first_grid_strain_after(value: float) -> float:
    return float(STRAIN[np.searchsorted(STRAIN, value - 1e-12)])


def test_settle_strain_and_censoring():
    deviation = np.array([0.5, 0.05, 0.2, 0.05, 0.0])
    assert verdicts.settle_strain(np.arange(5.0), deviation) == (3.0, True)
    assert verdicts.settle_strain(np.arange(3.0), np.array([0.0, 0.0, 0.3])) == (2.0, False)
    with pytest.raises(ValueError, match="lengths"):
        verdicts.settle_strain(np.arange(5.0), np.zeros(3))
    assert verdicts.settle_strain(np.arange(3.0), np.zeros(3)) == (0.0, True)


def test_recovery_strains_follow_tau_ln_10a():
    table = verdicts.recovery_table(runs(0.2), predictions(0.5, 0.25), N12_SS).set_index("theta")
    for theta in (45.0, 90.0, 135.0):
        assert table.loc[theta, "gw_steady"] == first_grid_strain_after(0.5 * np.log(10))
        assert table.loc[theta, "modified_steady"] == first_grid_strain_after(0.25 * np.log(10))
        assert table.loc[theta, "sim_steady"] == pytest.approx(first_grid_strain_after(0.2 * np.log(10)), abs=0.021)
        assert table.loc[theta, "sim_continuation"] == pytest.approx(table.loc[theta, "sim_steady"], abs=0.021)
    # <nn>'_23 = sin(theta) |n12_ss| exp(-g / 0.3): within 0.1 |n12_ss| from 0.3 ln(10 sin theta)
    assert table.loc[90.0, "gw_n23"] == first_grid_strain_after(0.3 * np.log(10))
    assert table.loc[0.0, "gw_steady"] == 0.0 and bool(table.loc[90.0, "gw_steady_settled"])


def test_rms_error_of_an_offset_model():
    simulation = runs(0.2, noise=0.0)
    model = predictions(0.2, 0.2)
    model.loc[model["model"] == "gw", "n12"] += 0.3 * abs(N12_SS)
    model.loc[model["model"] == "modified", "n12"] += 0.1 * abs(N12_SS)
    table = verdicts.rms_error_table(simulation, model, N12_SS)
    n12 = table[table["component"] == "n12"]
    np.testing.assert_allclose(n12["gw_rms"], 0.3, rtol=1e-9)
    np.testing.assert_allclose(n12["ratio"], 3.0, rtol=1e-9)
    np.testing.assert_allclose(n12["ratio_err"], 0.0, atol=1e-9)  # identical seeds: no spread


def test_rotation_verdicts_follow_the_sign_of_the_deciding_number():
    """G-W slower than the simulation (tau 0.5 vs 0.2): 'G-W overestimates the effect on
    <nn>_12' is confirmed, and the modified model (tau = the simulation's) is 'significantly
    better' on <nn>'_12; G-W faster (0.02): refuted. A modified bump of 30% at 90 deg over a
    simulation without one: the overshoot claim is confirmed; without the bump, refuted."""
    def decide(tau_gw, bump):
        simulation, model = runs(0.2, noise=2e-3), predictions(tau_gw, 0.2, bump=bump)
        recovery = verdicts.recovery_table(simulation, model, N12_SS)
        rms = verdicts.rms_error_table(simulation, model, N12_SS)
        overshoot = verdicts.overshoot_table(simulation, model, N12_SS)
        return {row["claim"]: row["verdict"] for row in verdicts.rotation_verdicts(recovery, rms, overshoot)}

    slow = decide(0.5, bump=0.3)
    assert slow["G-W overestimates the effect on <nn>_12 for pi/4 <~ |theta| <~ 3pi/4 (baseline: steady <nn>_12)"] \
        == verdicts.CONFIRMED
    assert slow["modified significantly better than G-W on <nn>'_12"] == verdicts.CONFIRMED
    assert slow["modified overshoots <nn>_12 near pi/2, the simulations do not (baseline: steady <nn>_12)"] \
        == verdicts.CONFIRMED
    fast = decide(0.02, bump=0.0)
    assert fast["G-W overestimates the effect on <nn>_12 for pi/4 <~ |theta| <~ 3pi/4 (baseline: steady <nn>_12)"] \
        == verdicts.REFUTED
    assert fast["modified overshoots <nn>_12 near pi/2, the simulations do not (baseline: steady <nn>_12)"] \
        == verdicts.REFUTED


def test_steady_state_verdicts():
    targets = {c: {"mean": m, "sem": 0.002} for c, m in (("n11", 0.55), ("n22", 0.60), ("n33", 0.59), ("n12", -0.10))}
    fits = {"targets": targets, "gw": {"beta": 10.7, "beta_err": 0.2},
            "modified": {"beta": 9.3, "beta_err": 0.1, "A": 44.8, "A_err": 0.3},
            "model_steady_state": {"gw": {"n11": 0.2, "n22": 0.3, "n33": 0.25},
                                   "modified": {"n11": 0.55, "n22": 0.62, "n33": 1.0}}}
    rows = {row["claim"]: row for row in verdicts.steady_state_verdicts(fits)}
    assert rows["G-W underestimates the diagonal components"]["verdict"] == verdicts.CONFIRMED
    assert rows["modified captures <nn>_22"]["verdict"] == verdicts.CONFIRMED  # 3.3% off
    assert rows["modified overestimates <nn>_33"]["verdict"] == verdicts.CONFIRMED
    fits["model_steady_state"]["gw"]["n22"] = 0.65
    fits["model_steady_state"]["modified"]["n22"] = 0.75
    rows = {row["claim"]: row for row in verdicts.steady_state_verdicts(fits)}
    assert rows["G-W underestimates the diagonal components"]["verdict"] == verdicts.REFUTED
    assert rows["modified captures <nn>_22"]["verdict"] == verdicts.REFUTED  # 25% off

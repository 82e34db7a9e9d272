"""Uncertainties and error summaries of models versus simulation (suspension_fabric.evaluation.model_vs_simulation).

propagated_fit_errors gives 1-sigma parameter errors by linear propagation of the standard
errors of the steady-state targets (fits.json's errors_propagated; its errors are a jackknife over
seeds, tests/evaluation/test_fit_errors.py); here they are compared with the actual spread of the
fitted parameters over noisy targets (Monte Carlo). summarise_errors is checked on a
hand-built error table with exactly representable numbers.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.analysis.tables import VALUE_COLUMNS
from suspension_fabric.evaluation import model_vs_simulation
from suspension_fabric.models import fabric_models
from suspension_fabric.models import gillissen_wilson as model

BETA, A, PHI = 9.4, 42.4, 0.45
N_DRAWS = 200


def steady_table(fabric, sems):
    """Steady-state table (tables.steady_state format, theta = 0) with means from ``fabric``
    and standard errors ``sems`` {quantity: sem} (0.003 for the others)."""
    rows = []
    for quantity in VALUE_COLUMNS:
        mean = 2.0 * np.trace(fabric) if quantity == "Z" else fabric[COMPONENTS[quantity]]
        rows.append(
            {
                "theta": 0.0,
                "quantity": quantity,
                "mean": float(mean),
                "sem": sems.get(quantity, 0.003),
                "sem_between_seeds": np.nan,
                "tau_strain": 0.1,
                "n_frames": 100,
                "n_seeds": 3,
                "strain_min": 10.0,
                "strain_max": 20.0,
            }
        )
    return pd.DataFrame(rows)


@pytest.mark.parametrize(
    "sem_11, sem_12", [(0.005, 0.002), (0.005, 0.0), (0.0, 0.002)], ids=["both", "n11-only", "n12-only"]
)
def test_propagated_fit_errors_match_monte_carlo_spread(sem_11, sem_12):
    """sigma_p = sqrt(sum_k (dp/dx_k sigma_k)^2) (p = G-W beta from x = <nn>_12; modified beta
    and A from x = (<nn>_11, <nn>_12)) equals the standard deviation of p fitted to
    x + N(0, sigma_k^2) noise, 200 draws around the modified model's steady state at
    (beta, A) = (9.4, 42.4), phi = 0.45, within 20% (the sampling error of a 200-draw std is
    5%); with one sigma_k = 0 only the other target's derivative is tested."""
    exact = model.steady_state_ode(BETA, A, PHI)
    steady = steady_table(exact, {"n11": sem_11, "n12": sem_12})
    targets = {name[1:]: float(exact[index]) for name, index in COMPONENTS.items()}
    fitted = fabric_models.fit_steady(fabric_models.MODIFIED, targets, PHI)
    assert fitted["beta"] == pytest.approx(BETA, rel=1e-8)
    assert fitted["A"] == pytest.approx(A, rel=1e-8)
    gw_errors = model_vs_simulation.propagated_fit_errors(fabric_models.GW, steady, PHI)
    modified_errors = model_vs_simulation.propagated_fit_errors(fabric_models.MODIFIED, steady, PHI)

    rng = np.random.default_rng(2024)
    draws = []
    for _ in range(N_DRAWS):
        n11 = exact[0, 0] + sem_11 * rng.normal()
        n12 = exact[0, 1] + sem_12 * rng.normal()
        modified = model.fit_modified(n11, n12, PHI)
        draws.append((model.fit_gw(n12, PHI), modified.beta, modified.A))
    spread = np.std(np.array(draws), axis=0, ddof=1)
    propagated = np.array([gw_errors["beta"], modified_errors["beta"], modified_errors["A"]])
    # atol: a parameter that does not depend on the noisy target (G-W beta when only
    # <nn>_11 is noisy) has sigma = 0 and a round-off spread
    np.testing.assert_allclose(propagated, spread, rtol=0.2, atol=1e-9)
    assert (gw_errors["beta"] == 0.0) == (sem_12 == 0.0)
    assert spread[1] > 0.0 and spread[2] > 0.0


def test_summarise_errors_averages_over_angles_per_protocol_and_component():
    """rms_<model> = unweighted mean over theta of rms_error (not weighted by n_strains) per
    (protocol, component), gw_over_modified = rms_gw / rms_modified (the ratio asked for); one row per
    (protocol, component), whatever the row order of the input."""
    rows = []

    def add(protocol, component, model_key, values, thetas):
        for k, (theta, value) in enumerate(zip(thetas, values)):
            rows.append(
                {
                    "protocol": protocol,
                    "model": model_key,
                    "theta": theta,
                    "component": component,
                    "rms_error": value,
                    "max_abs_error": 10.0 * value,
                    "n_strains": 5 + 20 * k,
                }
            )

    rotation_thetas = (45.0, 90.0, 135.0)
    add("rotation", "n12", "gw", (0.25, 0.5, 0.75), rotation_thetas)  # mean 0.5
    add("rotation", "n12", "modified", (0.125, 0.125, 0.5), rotation_thetas)  # mean 0.25
    add("rotation", "n23", "gw", (0.5, 1.0, 1.5), rotation_thetas)  # mean 1.0
    add("rotation", "n23", "modified", (0.25, 0.25, 0.25), rotation_thetas)  # mean 0.25
    add("startup", "n12", "gw", (0.75,), (0.0,))
    add("startup", "n12", "modified", (0.375,), (0.0,))
    add("startup", "n11", "gw", (0.125,), (0.0,))
    add("startup", "n11", "modified", (0.5,), (0.0,))
    errors = pd.DataFrame(rows).sample(frac=1.0, random_state=3)

    summary = model_vs_simulation.summarise_errors(errors, ratio=("gw", "modified"))
    assert list(summary.columns) == ["protocol", "component", "rms_gw", "rms_modified", "gw_over_modified"]
    assert len(summary) == 4
    got = {
        (row.protocol, row.component): (row.rms_gw, row.rms_modified, row.gw_over_modified)
        for row in summary.itertuples()
    }
    assert got == {
        ("rotation", "n12"): (0.5, 0.25, 2.0),
        ("rotation", "n23"): (1.0, 0.25, 4.0),
        ("startup", "n12"): (0.75, 0.375, 2.0),
        ("startup", "n11"): (0.125, 0.5, 0.25),
    }

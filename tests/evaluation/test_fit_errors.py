"""Errors of the fitted parameters (suspension_fabric.evaluation.model_vs_simulation.fit_steady_state): a
jackknife over seeds of the whole fit, next to the linear propagation of the targets' errors.

Synthetic per-seed startup run tables are built from a KNOWN model steady state (the modified
model at beta = 9.4, A = 42.4, phi = 0.45) plus a per-seed offset of every component and a
frame pattern inside the steady window, and pushed through the real tables.steady_state and fits.
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis import tables
from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.evaluation import model_vs_simulation
from suspension_fabric.models import gillissen_wilson as model
from suspension_fabric.models.fabric_models import GW, MODIFIED
from suspension_fabric.models.fits_file import FITS_FORMAT, write_fits

BETA, A, PHI = 9.4, 42.4, 0.45
WINDOW = (2.0, 5.0)
#: The steady state all seeds scatter around.
EXACT = model.steady_state_ode(BETA, A, PHI)
#: Frames: a few before the window (ignored by the fits) and an even number inside it.
STRAINS = np.concatenate([[0.0, 0.5, 1.0, 1.5], np.linspace(*WINDOW, 150)])
INSIDE = STRAINS >= WINDOW[0]
PARAMETERS = (("gw", "beta"), ("modified", "beta"), ("modified", "A"))
PAPER_MODELS = {"gw": GW, "modified": MODIFIED}
#: fits.json's entry of each error kind, by the suffix the tests use
SECTIONS = {"": "parameters", "_err": "errors", "_err_propagated": "errors_propagated"}


def seed_table(seed, offset, frames) -> pd.DataFrame:
    """One seed's startup run table (tables format): EXACT + ``offset`` (3x3) at every frame,
    plus ``frames`` (len(STRAINS), 3, 3) symmetrised."""
    tensors = EXACT + offset + frames
    tensors = 0.5 * (tensors + np.swapaxes(tensors, -1, -2))
    frame = pd.DataFrame(
        {
            "seed": seed,
            "theta": 0.0,
            "N": 1000,
            "phi": PHI,
            "step": np.round(STRAINS * 1e5).astype(int),
            "strain": STRAINS,
        }
    )
    for name, (i, j) in COMPONENTS.items():
        frame[name] = tensors[:, i, j]
    frame["Z"] = 2.0 * np.trace(tensors, axis1=-2, axis2=-1)
    return frame


def offset_tensor(d11=0.0, d12=0.0, rest=0.0) -> np.ndarray:
    offset = np.full((3, 3), rest)
    offset[0, 0], offset[0, 1], offset[1, 0] = d11, d12, d12
    return offset


def noisy_runs(n_seeds, seed=11) -> pd.DataFrame:
    """n seeds with random per-seed offsets (sd 0.004 in every component) and frame noise (sd 0.01)."""
    rng = np.random.default_rng(seed)
    return pd.concat(
        [
            seed_table(s, 0.004 * rng.normal(size=(3, 3)), 0.01 * rng.normal(size=(len(STRAINS), 3, 3)))
            for s in range(1, n_seeds + 1)
        ],
        ignore_index=True,
    )


def fit(runs) -> dict:
    return model_vs_simulation.fit_steady_state(tables.steady_state(runs, *WINDOW), PHI, runs, *WINDOW, PAPER_MODELS)


def seed_means(runs) -> pd.DataFrame:
    """Per-seed means of n11 and n12 over the steady window, computed here by hand."""
    inside = runs[(runs["strain"] >= WINDOW[0]) & (runs["strain"] <= WINDOW[1])]
    return inside.groupby("seed")[["n11", "n12"]].mean()


def fit_by_hand(n11, n12) -> np.ndarray:
    """(G-W beta, modified beta, A) straight from the model's fit functions."""
    return np.array([model.fit_gw(n12, PHI), *model.fit_modified(n11, n12, PHI)])


def values(fits, suffix="") -> np.ndarray:
    return np.array([fits["models"][key][SECTIONS[suffix]][name] for key, name in PARAMETERS], dtype=float)


def correlation(fits) -> float:
    value = fits["models"]["modified"]["correlations"]["beta,A"]
    return np.nan if value is None else value


@pytest.fixture(scope="module")
def five_seeds():
    runs = noisy_runs(5)
    return runs, fit(runs)


def test_fitted_values_are_those_of_the_seed_mean_fit(five_seeds):
    """(1) The fitted parameters are the fits to the seed mean of the per-seed window means."""
    runs, fits = five_seeds
    means = seed_means(runs).mean()
    np.testing.assert_allclose(values(fits), fit_by_hand(means["n11"], means["n12"]), rtol=1e-12)
    assert fits["targets"]["n12"]["mean"] == pytest.approx(means["n12"], rel=1e-12)
    assert fits["n_seeds"] == 5 and fits["steady_window"] == list(WINDOW)
    assert fits["fit_errors"] == model_vs_simulation.FIT_ERRORS
    assert fits["fit_errors"].startswith("errors: jackknife over seeds of the whole fit (leave one seed out)")
    # the generating parameters are recovered within a few jackknife errors
    modified = fits["models"]["modified"]
    assert abs(modified["parameters"]["beta"] - BETA) < 4 * modified["errors"]["beta"]
    assert abs(modified["parameters"]["A"] - A) < 4 * modified["errors"]["A"]


def test_jackknife_error_is_that_of_the_leave_one_out_fits(five_seeds):
    """(2) errors = sqrt((n - 1)/n sum_i (p_i - p_mean)^2), p_i fitted (model.fit_gw, model.fit_modified)
    to the seed means without seed i; correlations "beta,A" = Pearson correlation of the p_i of
    beta and A. The propagated errors are kept as errors_propagated."""
    runs, fits = five_seeds
    means = seed_means(runs)
    n = len(means)
    leave_one_out = np.array([fit_by_hand(*means.drop(index=seed).mean()[["n11", "n12"]]) for seed in means.index])
    expected = np.sqrt((n - 1) / n * np.sum((leave_one_out - leave_one_out.mean(axis=0)) ** 2, axis=0))
    np.testing.assert_allclose(values(fits, "_err"), expected, rtol=1e-9)
    assert correlation(fits) == pytest.approx(np.corrcoef(leave_one_out[:, 1], leave_one_out[:, 2])[0, 1], rel=1e-9)
    steady = tables.steady_state(runs, *WINDOW)
    propagated = [
        model_vs_simulation.propagated_fit_errors(PAPER_MODELS[key], steady, PHI)[name] for key, name in PARAMETERS
    ]
    np.testing.assert_allclose(values(fits, "_err_propagated"), propagated, rtol=1e-12)
    assert np.all(values(fits, "_err") > 0.0) and np.all(values(fits, "_err_propagated") > 0.0)


def correlated_runs(rho, n_seeds=6, sd11=0.004, sd12=0.002) -> pd.DataFrame:
    """Seed offsets of <nn>_11 and <nn>_12 with sample standard deviations sd11, sd12 and sample
    correlation exactly ``rho``; inside the window every seed alternates +-a_k about its mean, with
    a_k = sd_k sqrt(m) (m frames in the window), so that the correlation-aware standard error of the
    targets (tau = 1/2: sqrt(n a_k^2 / m) / n = sd_k / sqrt(n)) equals the between-seed one."""
    rng = np.random.default_rng(5)
    basis = rng.normal(size=(n_seeds, 2))
    basis -= basis.mean(axis=0)
    u, _ = np.linalg.qr(basis)  # orthonormal, zero-mean columns
    u *= np.sqrt(n_seeds - 1)  # sample variance (ddof=1) 1
    d11 = sd11 * u[:, 0]
    d12 = sd12 * (rho * u[:, 0] + np.sqrt(1.0 - rho**2) * u[:, 1])
    m = int(INSIDE.sum())
    sign = np.where(INSIDE, (-1.0) ** np.arange(len(STRAINS)), 0.0)[:, None, None]
    frames = sign * offset_tensor(sd11 * np.sqrt(m), sd12 * np.sqrt(m))
    return pd.concat(
        [seed_table(s + 1, offset_tensor(d11[s], d12[s]), frames) for s in range(n_seeds)], ignore_index=True
    )


def gradient(n11, n12, h=1e-6) -> np.ndarray:
    """d(G-W beta, modified beta, A) / d(n11, n12), central differences: shape (3, 2)."""
    return np.stack(
        [
            (fit_by_hand(n11 + h, n12) - fit_by_hand(n11 - h, n12)) / (2 * h),
            (fit_by_hand(n11, n12 + h) - fit_by_hand(n11, n12 - h)) / (2 * h),
        ],
        axis=1,
    )


@pytest.mark.parametrize("rho", [-0.95, 0.0], ids=["anticorrelated", "uncorrelated"])
def test_jackknife_includes_the_covariance_that_propagation_ignores(rho):
    """(3) To first order in the seed scatter, the jackknife error of a fitted p(<nn>_11, <nn>_12) is

        sigma_jack^2 = g^T C g / n = g11^2 s11^2 + g12^2 s12^2 + 2 rho g11 g12 s11 s12

    (g = gradient of p, C the sample covariance of the n per-seed means, s_k = sqrt(C_kk / n)), while
    the propagated error is sigma_prop^2 = g11^2 sigma11^2 + g12^2 sigma12^2 with the targets'
    standard errors sigma_k, i.e. without the covariance term. Here sigma_k = s_k by construction, so
    the two differ only by the covariance: for A (g11 > 0 > g12) anticorrelated <nn>_11 and <nn>_12
    (rho = -0.95, as in the simulations) raise the jackknife error by
    sqrt(1 + 2 rho g11 g12 s11 s12 / (g11^2 s11^2 + g12^2 s12^2)) ~ 1.37; uncorrelated ones leave it
    equal to the propagated error."""
    runs = correlated_runs(rho)
    steady = tables.steady_state(runs, *WINDOW)
    fits = model_vs_simulation.fit_steady_state(steady, PHI, runs, *WINDOW, PAPER_MODELS)
    n = 6
    means = seed_means(runs)
    s = np.sqrt(means.var(ddof=1).to_numpy() / n)
    sigma = np.array([fits["targets"]["n11"]["sem"], fits["targets"]["n12"]["sem"]])
    np.testing.assert_allclose(sigma, s, rtol=1e-6)  # the construction: sigma_k = s_k
    assert np.corrcoef(means["n11"], means["n12"])[0, 1] == pytest.approx(rho, abs=1e-9)

    g = gradient(fits["targets"]["n11"]["mean"], fits["targets"]["n12"]["mean"])
    covariance = np.cov(means[["n11", "n12"]].to_numpy(), rowvar=False, ddof=1) / n
    first_order = np.sqrt(np.einsum("pk,kl,pl->p", g, covariance, g))
    without_covariance = np.sqrt((g**2 * sigma**2).sum(axis=1))
    jack, propagated = values(fits, "_err"), values(fits, "_err_propagated")
    np.testing.assert_allclose(jack, first_order, rtol=0.03)
    np.testing.assert_allclose(propagated, without_covariance, rtol=0.01)
    ratio = jack[2] / propagated[2]
    if rho == 0.0:
        assert ratio == pytest.approx(1.0, abs=0.03)
    else:
        assert g[2, 0] > 0.0 > g[2, 1]
        assert ratio > 1.3 and ratio == pytest.approx(first_order[2] / without_covariance[2], rel=0.03)
        # G-W beta depends on <nn>_12 only: no covariance term, the two errors agree
        assert jack[0] == pytest.approx(propagated[0], rel=0.03)


def test_one_seed_gives_null_jackknife_errors(tmp_path):
    """(4) One seed: no jackknife (NaN, written null); the propagated errors remain; two seeds: the
    jackknife exists but the beta-A correlation of two leave-one-out fits does not (null)."""
    one = noisy_runs(1)
    fits = fit(one)
    assert np.all(np.isnan(values(fits, "_err"))) and np.isnan(correlation(fits))
    assert np.all(np.isfinite(values(fits, "_err_propagated")))
    written = json.loads(write_fits(fits, tmp_path / "fits.json").read_text())
    for key, name in PARAMETERS:
        entry = written["models"][key]
        assert entry["errors"][name] is None and entry["errors_propagated"][name] > 0.0
    assert written["models"]["modified"]["correlations"]["beta,A"] is None
    assert written["n_seeds"] == 1

    two = fit(noisy_runs(2))
    assert np.all(values(two, "_err") > 0.0) and np.isnan(correlation(two))


def test_fits_json_keys(five_seeds):
    """Every key other code reads is there, each model once under ``models`` (format 2)."""
    fits = five_seeds[1]
    assert list(fits) == ["format", "phi", "steady_window", "n_seeds", "fit_errors", "targets", "models"]
    assert fits["format"] == FITS_FORMAT == 2
    assert list(fits["models"]) == ["gw", "modified"]
    for key, entry in fits["models"].items():
        assert list(entry) == [
            "label",
            "fitted_to",
            "parameters",
            "errors",
            "errors_propagated",
            "correlations",
            "steady_state",
        ]
        assert list(entry["parameters"]) == list(entry["errors"]) == list(entry["errors_propagated"])
        assert entry["label"] == PAPER_MODELS[key].label
    assert fits["models"]["gw"]["correlations"] == {}
    assert -1.0 <= correlation(fits) <= 1.0


def test_steady_table_must_be_that_of_the_runs():
    """The jackknife errors belong to the fit only if the steady table is that of the runs and window."""
    runs = noisy_runs(3)
    steady = tables.steady_state(runs, *WINDOW)
    with pytest.raises(ValueError, match="window"):
        model_vs_simulation.fit_steady_state(steady, PHI, runs, 2.5, 5.0, PAPER_MODELS)
    with pytest.raises(ValueError, match="3 seeds, the run table 2"):
        model_vs_simulation.fit_steady_state(steady, PHI, runs[runs["seed"] != 3], *WINDOW, PAPER_MODELS)
    other = noisy_runs(3, seed=12)
    with pytest.raises(ValueError, match="is not that of the run table"):
        model_vs_simulation.fit_steady_state(steady, PHI, other, *WINDOW, PAPER_MODELS)


def test_any_model_is_fitted_to_its_own_steady_targets():
    """A model with three parameters (separate rates, suspension_fabric.models.fabric_models) reproduces
    its three steady targets, with finite jackknife errors."""
    from suspension_fabric.models import fabric_models

    runs = noisy_runs(5)
    listed = model_vs_simulation.fit_steady_state(
        tables.steady_state(runs, *WINDOW), PHI, runs, *WINDOW, models=fabric_models.resolve_models(["separate_rates"])
    )
    entry = listed["models"]["separate_rates"]
    assert list(listed["models"]) == ["separate_rates"] and entry["fitted_to"] == ["n11", "n33", "n12"]
    for component in ("n11", "n33", "n12"):
        assert entry["steady_state"][component] == pytest.approx(listed["targets"][component]["mean"], rel=1e-7)
    assert all(np.isfinite(error) and error > 0 for error in entry["errors"].values())

"""Models versus simulation: fits to the simulated steady state, predictions, model errors.

Inputs are the seed-aggregated simulation tables of :mod:`suspension_fabric.analysis.tables`
(columns ``theta, strain, n11_mean, n11_sem, ...``) and the steady-state table of
:func:`suspension_fabric.analysis.tables.steady_state`. Everything is in the paper frame of
the current shear (rotated frame (e1', e2, e3') after a rotation by theta).

Protocol of the model predictions (paper Sec. 4)
    Both models start from the simulated seed-mean fabric at strain 0 of startup
    shear (the random packing is not contact-free), are sheared to the startup
    strain of the simulations, then rotated by theta and sheared again. G-W uses the
    beta fitted to the steady <nn>_12; the modified model the (beta, A) fitted to
    the steady <nn>_11 and <nn>_12 (paper Sec. 4.1).

Fit uncertainties (:func:`fit_steady_state`)
    Fit uncertainties are a jackknife over seeds of the whole fit: the steady state is
    recomputed from the per-seed startup runs with each seed left out in turn
    (:func:`suspension_fabric.analysis.tables.steady_state`), both models are fitted to it
    (:func:`fit_both_models`), and the standard error is
    sqrt((n - 1)/n sum_i (p_i - p_mean)^2) over the n leave-one-out parameters
    (:func:`suspension_fabric.analysis.seed_statistics.jackknife`; NaN, written null, for one seed).
    It includes the covariance of the steady <nn>_11 and <nn>_12 across seeds (strongly
    negative in the simulations) and the seed-to-seed scatter. The linear propagation
    of the targets' standard errors, which ignores that covariance
    (:func:`propagated_fit_errors`), is kept alongside as ``*_err_propagated``.
"""

from __future__ import annotations

import json
import os
import warnings
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.analysis.seed_statistics import jackknife

from . import fabric_models
from . import gillissen_wilson as model

__all__ = [
    "fit_steady_state",
    "error_sizes",
    "fit_both_models",
    "fit_listed_models",
    "propagated_fit_errors",
    "FittedParameters",
    "FIT_ERRORS",
    "write_fits",
    "read_fits",
    "initial_fabric",
    "predict",
    "PredictionGrids",
    "prediction_grids",
    "predict_on_simulation_grids",
    "fitted_models",
    "model_labels",
    "PAPER_MODELS",
    "model_errors",
    "summarise_errors",
    "error_tables",
    "MODEL_NAMES",
]

#: The paper's two models (its claims compare them), by key.
PAPER_MODELS = {"gw": fabric_models.GW, "modified": fabric_models.MODIFIED}

#: Model keys used in tables and fits.json, with their display names.
MODEL_NAMES = {"gw": "G-W (Eq. 1)", "modified": "modified G-W (Eq. 2)"}

#: fits.json's ``fit_errors``: what its parameter errors are.
FIT_ERRORS = (
    "jackknife over seeds of the whole fit (leave one seed out); *_propagated: linear propagation "
    "of the targets' standard errors, ignoring their covariance"
)


class FittedParameters(NamedTuple):
    """The three fitted parameters (or their errors): G-W beta, modified beta and A."""

    gw_beta: float
    beta: float
    A: float


def _steady_value(steady: pd.DataFrame, quantity: str, theta: float = 0.0):
    rows = steady[(steady["quantity"] == quantity) & np.isclose(steady["theta"], theta)]
    if len(rows) != 1:
        raise ValueError(f"steady-state table has {len(rows)} rows for {quantity} at theta={theta}, expected 1")
    row = rows.iloc[0]
    return float(row["mean"]), float(row["sem"])


def fit_both_models(steady: pd.DataFrame, phi: float) -> FittedParameters:
    """Both models fitted to the startup (theta = 0) steady state of a steady-state table:
    G-W beta to <nn>_12, modified (beta, A) to <nn>_11 and <nn>_12 (the one fit of the
    steady state, used for all seeds and for each leave-one-out subset)."""
    n11, _ = _steady_value(steady, "n11")
    n12, _ = _steady_value(steady, "n12")
    modified = model.fit_modified(n11, n12, phi)
    return FittedParameters(model.fit_gw(n12, phi), modified.beta, modified.A)


def _propagated(func, values, errors):
    """sqrt(sum_k (df/dx_k sigma_k)^2) with central differences of a tenth of sigma."""
    total = np.zeros_like(np.atleast_1d(func(*values)), dtype=float)
    for k, sigma in enumerate(errors):
        if not np.isfinite(sigma) or sigma == 0.0:
            continue
        step = 0.1 * sigma
        plus, minus = list(values), list(values)
        plus[k] += step
        minus[k] -= step
        try:
            derivative = (np.atleast_1d(func(*plus)) - np.atleast_1d(func(*minus))) / (2 * step)
        except ValueError:  # the target +- sigma/10 leaves the fittable range
            return np.full_like(total, np.nan)
        total += (derivative * sigma) ** 2
    return np.sqrt(total)


def propagated_fit_errors(steady: pd.DataFrame, phi: float) -> FittedParameters:
    """1-sigma errors of :func:`fit_both_models` by linear propagation of the standard errors of
    the targets (finite-difference Jacobian of the fits), ignoring the covariance of <nn>_11 and
    <nn>_12; NaN where a target +- sigma/10 leaves the fittable range."""
    n11, n11_err = _steady_value(steady, "n11")
    n12, n12_err = _steady_value(steady, "n12")
    gw_err = _propagated(lambda a: model.fit_gw(a, phi), [n12], [n12_err])[0]
    mod_err = _propagated(lambda a, b: np.array(model.fit_modified(a, b, phi)), [n11, n12], [n11_err, n12_err])
    return FittedParameters(float(gw_err), float(mod_err[0]), float(mod_err[1]))


def _startup_seeds(runs: pd.DataFrame) -> tuple[pd.DataFrame, list[int]]:
    startup = runs[np.isclose(runs["theta"].to_numpy(dtype=float), 0.0)]
    if startup.empty:
        raise ValueError("startup run table has no theta = 0 rows")
    return startup, sorted(int(seed) for seed in startup["seed"].unique())


def _check_steady_matches_runs(steady: pd.DataFrame, startup: pd.DataFrame, seeds, strain_min, strain_max):
    """The steady-state table must be that of these runs over this window (else the jackknife
    errors would belong to another fit)."""
    window = steady[np.isclose(steady["theta"], 0.0)].iloc[0]
    if not (np.isclose(window["strain_min"], strain_min) and np.isclose(window["strain_max"], strain_max)):
        raise ValueError(
            f"steady-state table window [{window['strain_min']}, {window['strain_max']}] differs "
            f"from the jackknife window [{strain_min}, {strain_max}]"
        )
    if int(window["n_seeds"]) != len(seeds):
        raise ValueError(f"steady-state table has {int(window['n_seeds'])} seeds, the run table {len(seeds)} ({seeds})")
    recomputed = tables.steady_state(startup, strain_min, strain_max)
    for quantity in ("n11", "n12"):
        given, again = _steady_value(steady, quantity)[0], _steady_value(recomputed, quantity)[0]
        if not np.isclose(given, again, rtol=1e-9, atol=1e-12):
            raise ValueError(
                f"steady-state table {quantity} = {given!r} is not that of the run table "
                f"({again!r}) over [{strain_min}, {strain_max}]"
            )


def _subset_steady(startup: pd.DataFrame, strain_min, strain_max):
    """subset of seeds -> the steady-state table of those seeds' startup runs, each computed once
    (the jackknifes of every model share the leave-one-out tables)."""
    computed = {}

    def steady_of(subset) -> pd.DataFrame:
        key = tuple(subset)
        if key not in computed:
            computed[key] = tables.steady_state(startup[startup["seed"].isin(key)], strain_min, strain_max)
        return computed[key]

    return steady_of


def _jackknife_errors(steady_of, seeds, phi):
    """Jackknife standard errors of :func:`fit_both_models` over seeds and the correlation of the
    leave-one-out modified beta and A (NaN for fewer than 3 seeds). A leave-one-out fit that fails
    (a target outside the fittable range) gives NaN errors, with a warning naming the seed."""
    fitted = {}

    def parameters(subset) -> np.ndarray:
        key = tuple(subset)
        if key not in fitted:
            steady = steady_of(key)
            try:
                fitted[key] = np.array(fit_both_models(steady, phi), dtype=float)
            except ValueError as error:
                left_out = sorted(set(seeds) - set(key))
                warnings.warn(
                    f"fit without seed(s) {left_out} failed ({error}); its jackknife errors are NaN", stacklevel=3
                )
                fitted[key] = np.full(3, np.nan)
        return fitted[key]

    errors = FittedParameters(*(jackknife(lambda subset, k=k: parameters(subset)[k], seeds)[1] for k in range(3)))
    correlation = np.nan
    if len(seeds) >= 3:
        leave_one_out = np.array([parameters([s for s in seeds if s != left]) for left in seeds])
        beta, A = leave_one_out[:, 1], leave_one_out[:, 2]
        if np.all(np.isfinite(leave_one_out)) and beta.std() > 0.0 and A.std() > 0.0:
            correlation = float(np.corrcoef(beta, A)[0, 1])
    return errors, correlation


def _steady_targets(steady: pd.DataFrame) -> dict[str, float]:
    """Every steady component (a model fits its ``steady_targets``; the others may break ties)."""
    return {name[1:]: _steady_value(steady, name)[0] for name in COMPONENTS}


def fit_listed_models(
    steady: pd.DataFrame,
    startup: pd.DataFrame,
    seeds,
    strain_min: float,
    strain_max: float,
    phi: float,
    models: dict,
    steady_of=None,
) -> dict:
    """Every model of ``models`` ({key: FabricModel}) fitted to the steady components it names
    (``steady_targets``; :func:`suspension_fabric.models.fabric_models.fit_steady`), with jackknife
    standard errors over seeds of the whole fit (NaN, with a warning naming the seed, where a
    leave-one-out fit fails); a failing fit to all seeds raises ``ValueError`` naming the model.
    ``steady_of`` (subset of seeds -> steady table) shares leave-one-out tables with other fits."""
    steady_of = steady_of or _subset_steady(startup, strain_min, strain_max)
    entries = {}
    for key, fabric_model in models.items():
        try:
            fitted = fabric_models.fit_steady(fabric_model, _steady_targets(steady), phi)
        except ValueError as error:
            raise ValueError(f"model {key}: the fit to the steady state failed: {error}") from error
        subsets = {}

        def parameter(subset, name, fabric_model=fabric_model, subsets=subsets):
            key_ = tuple(subset)
            if key_ not in subsets:
                try:
                    subsets[key_] = fabric_models.fit_steady(fabric_model, _steady_targets(steady_of(key_)), phi)
                except ValueError as error:
                    warnings.warn(
                        f"model {fabric_model.key}: fit without seed(s) {sorted(set(seeds) - set(key_))} "
                        f"failed ({error}); its jackknife errors are NaN",
                        stacklevel=2,
                    )
                    subsets[key_] = dict.fromkeys(fabric_model.names, np.nan)
            return subsets[key_][name]

        errors = {
            name: jackknife(lambda subset, name=name: parameter(subset, name), seeds)[1] for name in fabric_model.names
        }
        entries[key] = {
            "label": fabric_model.label,
            "fitted_to": [f"n{c}" for c in fabric_model.steady_targets],
            "parameters": fitted,
            "errors": errors,
            "steady_state": _as_components(fabric_models.steady_state(fabric_model, fitted, phi)),
        }
    return entries


def fit_steady_state(
    steady: pd.DataFrame,
    phi: float,
    runs: pd.DataFrame,
    strain_min: float,
    strain_max: float,
    models: dict | None = None,
) -> dict:
    """Fit both models to the startup (theta = 0) steady state; returns the fits.json content.

    ``steady`` is :func:`suspension_fabric.analysis.tables.steady_state` of the per-seed startup run
    table ``runs`` (columns seed, theta, ..., strain, n11 ... n23, Z; startup_runs.csv) over
    strain_min <= strain <= strain_max (checked: window, seeds and the fitted <nn>_11,
    <nn>_12). ``gw.beta`` from <nn>_12, ``modified.beta`` and ``modified.A`` from <nn>_11 and
    <nn>_12 (:func:`fit_both_models`). Their ``*_err`` are jackknife standard errors over seeds
    of the whole fit (null for one seed), ``*_err_propagated`` the linear propagation of the
    targets' standard errors (:func:`propagated_fit_errors`), and ``modified.beta_A_correlation``
    the correlation of the leave-one-out beta and A (null for fewer than 3 seeds). ``targets``
    holds every steady component with its error; ``fit_errors`` says what the errors are.
    ``models`` holds the same steady fit of every model of ``models`` ({key: FabricModel}; default
    the paper's two) by the generic interface (:func:`fit_listed_models`): the predictions and
    model errors read it, the paper's claims the ``gw`` and ``modified`` entries above.
    """
    startup, seeds = _startup_seeds(runs)
    _check_steady_matches_runs(steady, startup, seeds, strain_min, strain_max)
    fitted = fit_both_models(steady, phi)
    propagated = propagated_fit_errors(steady, phi)
    steady_of = _subset_steady(startup, strain_min, strain_max)
    jackknifed, correlation = _jackknife_errors(steady_of, seeds, phi)
    targets = {}
    for quantity in (*COMPONENTS, "Z"):
        mean, sem = _steady_value(steady, quantity)
        targets[quantity] = {"mean": mean, "sem": sem}
    window = steady[np.isclose(steady["theta"], 0.0)].iloc[0]
    return {
        "phi": float(phi),
        "steady_window": [float(window["strain_min"]), float(window["strain_max"])],
        "n_seeds": int(window["n_seeds"]),
        "fit_errors": FIT_ERRORS,
        "targets": targets,
        "gw": {
            "beta": fitted.gw_beta,
            "beta_err": jackknifed.gw_beta,
            "beta_err_propagated": propagated.gw_beta,
            "fitted_to": ["n12"],
        },
        "modified": {
            "beta": fitted.beta,
            "beta_err": jackknifed.beta,
            "beta_err_propagated": propagated.beta,
            "A": fitted.A,
            "A_err": jackknifed.A,
            "A_err_propagated": propagated.A,
            "beta_A_correlation": correlation,
            "fitted_to": ["n11", "n12"],
        },
        "model_steady_state": {
            "gw": _as_components(model.steady_state_ode(fitted.gw_beta, None, phi)),
            "modified": _as_components(model.steady_state_ode(fitted.beta, fitted.A, phi)),
        },
        "models": fit_listed_models(
            steady,
            startup,
            seeds,
            strain_min,
            strain_max,
            phi,
            models if models is not None else PAPER_MODELS,
            steady_of,
        ),
    }


def _as_components(tensor) -> dict:
    return {name: float(tensor[i, j]) for name, (i, j) in COMPONENTS.items()}


def write_fits(fits: dict, path: str | os.PathLike) -> Path:
    """Write fits as indented JSON (NaN errors become null)."""
    path = Path(path)
    text = json.dumps(fits, indent=2, sort_keys=False, allow_nan=True).replace("NaN", "null")
    path.write_text(text + "\n")
    return path


def read_fits(path: str | os.PathLike) -> dict:
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"fits file not found: {path}")
    fits = json.loads(path.read_text())
    for key in ("phi", "gw", "modified"):
        if key not in fits:
            raise ValueError(f"{path}: missing key {key!r}")
    return fits


def initial_fabric(startup_aggregate: pd.DataFrame) -> np.ndarray:
    """Seed-mean simulated fabric at the first frame (strain 0) of startup shear, 3x3 paper frame."""
    rows = startup_aggregate[np.isclose(startup_aggregate["theta"], 0.0)].sort_values("strain")
    if rows.empty:
        raise ValueError("startup aggregate table has no theta = 0 rows")
    first = rows.iloc[0]
    tensor = np.zeros((3, 3))
    for name, (i, j) in COMPONENTS.items():
        tensor[i, j] = tensor[j, i] = first[f"{name}_mean"]
    return tensor


def model_labels(fits: dict, keys=None) -> dict[str, str]:
    """{key: display name} for ``keys`` (default every model of fits.json's ``models``): the label
    fits.json records, else the paper's name (:data:`MODEL_NAMES`), else the key."""
    keys = fits.get("models", {}) if keys is None else keys
    return {key: fits.get("models", {}).get(key, {}).get("label", MODEL_NAMES.get(key, key)) for key in keys}


def fitted_models(fits: dict, models: dict) -> dict:
    """{key: (FabricModel, parameters)} of ``models`` ({key: FabricModel}) with the parameters that
    fits.json's ``models`` section holds for each; a model missing there is an error naming it."""
    fitted = {}
    for key, fabric_model in models.items():
        if key not in fits.get("models", {}):
            raise ValueError(
                f"fits have no entry for model {key!r} (fitted: {sorted(fits.get('models', {}))}); "
                "rerun the fit_models rule with this model in models.fabric"
            )
        fitted[key] = (fabric_model, fits["models"][key]["parameters"])
    return fitted


def _tidy(key, protocol, theta_deg, strains, tensors) -> pd.DataFrame:
    frame = pd.DataFrame({"model": key, "protocol": protocol, "theta": theta_deg, "strain": strains})
    for name, (i, j) in COMPONENTS.items():
        frame[name] = tensors[:, i, j]
    frame["Z"] = 2.0 * np.trace(tensors, axis1=-2, axis2=-1)
    return frame


def predict(
    fits: dict,
    models: dict,
    fabric0,
    startup_strains,
    startup_strain: float,
    thetas_deg,
    rotation_strains,
    extra_thetas_deg=(),
) -> pd.DataFrame:
    """Tidy predictions of every model of ``models`` ({key: FabricModel}, parameters from fits.json's
    ``models``): startup shear and shear rotations.

    Rotations are predicted at ``thetas_deg`` (the simulated angles) and at
    ``extra_thetas_deg`` (e.g. a fine grid for the polar maps). Columns: model (its key),
    protocol (startup | rotation), theta (degrees; 0 for startup), strain (since the start of
    the current shear), n11 ... n23, Z.
    """
    phi = fits["phi"]
    startup_strains = np.asarray(startup_strains, dtype=float)
    rotation_strains = np.asarray(rotation_strains, dtype=float)
    thetas_deg = np.union1d(np.asarray(thetas_deg, dtype=float), np.asarray(extra_thetas_deg, dtype=float))
    blocks = []
    for key, (fabric_model, params) in fitted_models(fits, models).items():
        blocks.append(
            _tidy(
                key,
                "startup",
                0.0,
                startup_strains,
                fabric_models.startup_shear(fabric_model, startup_strains, params, phi, fabric0),
            )
        )
        rotated = fabric_models.shear_rotation(
            fabric_model,
            np.radians(thetas_deg),
            rotation_strains,
            params,
            phi,
            startup_strain=startup_strain,
            fabric0=fabric0,
        )
        for theta, tensors in zip(thetas_deg, rotated):
            blocks.append(_tidy(key, "rotation", theta, rotation_strains, tensors))
    return pd.concat(blocks, ignore_index=True)


class PredictionGrids(NamedTuple):
    """Where the models are evaluated (see :func:`prediction_grids`); angles in degrees."""

    startup_strains: np.ndarray
    thetas_deg: np.ndarray
    rotation_strains: np.ndarray
    polar_thetas_deg: np.ndarray


def prediction_grids(
    startup_aggregate: pd.DataFrame, rotation_aggregate: pd.DataFrame, polar_step_deg: float
) -> PredictionGrids:
    """The strains and angles of the simulations, and a polar grid of angles for the figures.

    ``startup_strains``: the strains of the startup seed aggregate; ``thetas_deg``: the
    simulated rotation angles; ``rotation_strains``: the post-rotation strains, which all
    angles must share (to 1e-9, as :func:`model_errors` compares them; else ``ValueError``);
    ``polar_thetas_deg``: 0 to 180 degrees every ``polar_step_deg``, from -180 if a
    simulated angle is negative. All sorted ascending.
    """
    if not np.isfinite(polar_step_deg) or polar_step_deg <= 0:
        raise ValueError(f"polar_step_deg must be positive, got {polar_step_deg}")
    if startup_aggregate.empty or rotation_aggregate.empty:
        raise ValueError("prediction grids need non-empty startup and rotation aggregate tables")
    thetas = np.unique(rotation_aggregate["theta"].to_numpy(dtype=float))
    strains = {
        theta: np.unique(rows["strain"].to_numpy(dtype=float))
        for theta, rows in rotation_aggregate.groupby("theta", sort=True)
    }
    rotation_strains = strains[thetas[0]]
    for theta, grid in strains.items():
        if len(grid) != len(rotation_strains) or not np.allclose(grid, rotation_strains, rtol=1e-9, atol=1e-9):
            raise ValueError(
                f"rotation aggregate: the strains at theta={theta} ({len(grid)} frames) differ from "
                f"those at theta={thetas[0]} ({len(rotation_strains)} frames)"
            )
    low = -180.0 if thetas.min() < 0 else 0.0
    return PredictionGrids(
        startup_strains=np.unique(startup_aggregate["strain"].to_numpy(dtype=float)),
        thetas_deg=thetas,
        rotation_strains=rotation_strains,
        polar_thetas_deg=np.arange(low, 180.0 + 1e-9, polar_step_deg),
    )


def predict_on_simulation_grids(
    fits: dict,
    models: dict,
    startup_aggregate: pd.DataFrame,
    rotation_aggregate: pd.DataFrame,
    startup_strain: float,
    polar_step_deg: float,
) -> pd.DataFrame:
    """:func:`predict` from the simulated initial fabric (:func:`initial_fabric`) on the
    :func:`prediction_grids` of the seed aggregates: at every simulated strain and angle,
    and at the polar grid of angles (rotation after ``startup_strain`` of startup shear)."""
    grids = prediction_grids(startup_aggregate, rotation_aggregate, polar_step_deg)
    return predict(
        fits,
        models,
        initial_fabric(startup_aggregate),
        grids.startup_strains,
        startup_strain,
        grids.thetas_deg,
        grids.rotation_strains,
        extra_thetas_deg=grids.polar_thetas_deg,
    )


def model_errors(simulation: pd.DataFrame, predictions: pd.DataFrame, n12_ss: float, protocol: str) -> pd.DataFrame:
    """Model-versus-simulation error per angle and component, normalised by |<nn>_12^ss|.

    ``simulation`` is a seed aggregate (``<c>_mean`` columns) and ``predictions``
    the output of :func:`predict`, evaluated at the simulation's strains (matched by
    theta and strain to 1e-9). Returns one row per (model, theta, component) with
    rms_error = sqrt(mean_strain (model - sim)^2) / |n12_ss|, max_abs_error and the
    number of strain points; the paper only says the modified model is
    "significantly better", this table says by how much.
    """
    rows = []
    preds = predictions[predictions["protocol"] == protocol]
    for key in predictions["model"].unique():
        mine = preds[preds["model"] == key]
        for theta, sim in simulation.groupby("theta", sort=True):
            pred = mine[np.isclose(mine["theta"], theta)].sort_values("strain")
            sim = sim.sort_values("strain")
            if len(pred) != len(sim) or not np.allclose(
                pred["strain"].to_numpy(), sim["strain"].to_numpy(), rtol=1e-9, atol=1e-9
            ):
                raise ValueError(f"{protocol}: model {key} at theta={theta} is not on the simulation's strain grid")
            for name in (*COMPONENTS, "Z"):
                diff = (pred[name].to_numpy() - sim[f"{name}_mean"].to_numpy()) / abs(n12_ss)
                rows.append(
                    {"protocol": protocol, "model": key, "theta": float(theta), "component": name, **error_sizes(diff)}
                )
    return pd.DataFrame(rows)


def error_sizes(difference) -> dict:
    """rms_error, max_abs_error and n_strains of a model-minus-simulation curve (already scaled)."""
    difference = np.asarray(difference, dtype=float)
    return {
        "rms_error": float(np.sqrt(np.mean(difference**2))),
        "max_abs_error": float(np.abs(difference).max()),
        "n_strains": len(difference),
    }


def summarise_errors(errors: pd.DataFrame) -> pd.DataFrame:
    """Angle-averaged rms error per protocol and component for every model, and the paper's ratio.

    One row per (protocol, component): rms_<model> (means over angles of :func:`model_errors`'
    rms_error) for each model, and gw_over_modified (> 1: the modified model is closer to the
    simulation) when both of the paper's models are present.
    """
    mean = errors.groupby(["protocol", "component", "model"], sort=False)["rms_error"].mean().unstack("model")
    keys = list(dict.fromkeys(errors["model"]))
    summary = pd.DataFrame({f"rms_{key}": mean[key] for key in keys})
    if {"gw", "modified"} <= set(keys):
        summary["gw_over_modified"] = mean["gw"] / mean["modified"]
    return summary.reset_index()


def error_tables(
    fits: dict, predictions: pd.DataFrame, startup_aggregate: pd.DataFrame, rotation_aggregate: pd.DataFrame
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """:func:`model_errors` of startup shear and of the rotations (normalised by the fitted
    steady <nn>_12 of ``fits``), concatenated, and their :func:`summarise_errors`."""
    n12_ss = fits["targets"]["n12"]["mean"]
    errors = pd.concat(
        [
            model_errors(startup_aggregate, predictions, n12_ss, "startup"),
            model_errors(rotation_aggregate, predictions, n12_ss, "rotation"),
        ],
        ignore_index=True,
    )
    return errors, summarise_errors(errors)

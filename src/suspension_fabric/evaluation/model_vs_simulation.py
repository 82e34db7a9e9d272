"""Models versus simulation: fits to the simulated steady state, predictions, model errors.

Inputs are the seed-aggregated simulation tables of
[`suspension_fabric.analysis.tables`][suspension_fabric.analysis.tables] (columns
``theta, strain, n11_mean, n11_sem, ...``) and the steady-state table of
[`suspension_fabric.analysis.tables.steady_state`][suspension_fabric.analysis.tables.steady_state]. Everything is in the
paper frame of the current shear (rotated frame (e1', e2, e3') after a rotation by theta).

Protocol of the model predictions (paper Sec. 4)
    Every model of the config (models.fabric) starts from the simulated seed-mean fabric at
    strain 0 of startup shear (the random packing is not contact-free), is sheared to the startup
    strain of the simulations, then rotated by theta and sheared again, with the parameters
    fitted to the steady components it names (its ``steady_targets``: <nn>_12 for G-W, <nn>_11
    and <nn>_12 for the modified model, as in the paper's Sec. 4.1).

Fit uncertainties ([`fit_steady_state`][suspension_fabric.evaluation.model_vs_simulation.fit_steady_state])
    Fit uncertainties are a jackknife over seeds of the whole fit: the steady state is
    recomputed from the per-seed startup runs with each seed left out in turn
    ([`suspension_fabric.analysis.tables.steady_state`][suspension_fabric.analysis.tables.steady_state]), every model is
    fitted to it, and the standard error is
    sqrt((n - 1)/n sum_i (p_i - p_mean)^2) over the n leave-one-out parameters
    ([`suspension_fabric.analysis.seed_statistics.jackknife`][suspension_fabric.analysis.seed_statistics.jackknife];
    NaN, written null, for one seed). It includes the covariance of the steady <nn>_11 and <nn>_12 across seeds
    (strongly negative in the simulations) and the seed-to-seed scatter. The linear propagation
    of the targets' standard errors, which ignores that covariance
    ([`propagated_fit_errors`][suspension_fabric.evaluation.model_vs_simulation.propagated_fit_errors]), is kept
    alongside as ``errors_propagated``.
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np
import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.analysis.components import COMPONENTS
from suspension_fabric.analysis.seed_statistics import jackknife
from suspension_fabric.models import fabric_models
from suspension_fabric.models.fits_file import FITS_FORMAT

__all__ = [
    "fit_steady_state",
    "error_sizes",
    "fit_listed_models",
    "propagated_fit_errors",
    "FIT_ERRORS",
    "initial_fabric",
    "predict",
    "PredictionGrids",
    "prediction_grids",
    "predict_on_simulation_grids",
    "fitted_models",
    "model_labels",
    "model_errors",
    "summarise_errors",
    "error_tables",
]

#: fits.json's ``fit_errors``: what its parameter errors are.
FIT_ERRORS = (
    "errors: jackknife over seeds of the whole fit (leave one seed out); errors_propagated: linear "
    "propagation of the targets' standard errors, ignoring their covariance; correlations: of the "
    "leave-one-out parameters"
)


def _steady_value(steady: pd.DataFrame, quantity: str, theta: float = 0.0):
    rows = steady[(steady["quantity"] == quantity) & np.isclose(steady["theta"], theta)]
    if len(rows) != 1:
        raise ValueError(f"steady-state table has {len(rows)} rows for {quantity} at theta={theta}, expected 1")
    row = rows.iloc[0]
    return float(row["mean"]), float(row["sem"])


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


def propagated_fit_errors(fabric_model, steady: pd.DataFrame, phi: float) -> dict[str, float]:
    """1-sigma errors of a model's steady fit by linear propagation of the standard errors of its
    targets (finite-difference Jacobian of
    [`suspension_fabric.models.fabric_models.fit_steady`][suspension_fabric.models.fabric_models.fit_steady]), ignoring
    their covariance; NaN where a target +- sigma/10 leaves the fittable range."""
    components = fabric_model.steady_targets
    means, sems = zip(*(_steady_value(steady, f"n{c}") for c in components))
    others = _steady_targets(steady)

    def fitted(*values):
        parameters = fabric_models.fit_steady(fabric_model, {**others, **dict(zip(components, values))}, phi)
        return np.array([parameters[name] for name in fabric_model.names])

    return dict(zip(fabric_model.names, map(float, _propagated(fitted, list(means), list(sems)))))


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


def _steady_targets(steady: pd.DataFrame) -> dict[str, float]:
    """Every steady component (a model fits its ``steady_targets``; the others may break ties)."""
    return {name[1:]: _steady_value(steady, name)[0] for name in COMPONENTS}


def leave_one_out_correlations(leave_one_out: list[dict], names: list[str]) -> dict[str, float]:
    """{"a,b": r} of the leave-one-out values of every pair of parameters (NaN for fewer than 3
    subsets, a failed subset or a parameter that does not vary)."""
    values = np.array([[fit.get(name, np.nan) for name in names] for fit in leave_one_out], dtype=float)
    values = values.reshape(-1, len(names))
    out = {}
    for i, first in enumerate(names):
        for j in range(i + 1, len(names)):
            x, y = values[:, i], values[:, j]
            usable = len(values) >= 3 and np.all(np.isfinite(values)) and x.std() > 0.0 and y.std() > 0.0
            out[f"{first},{names[j]}"] = float(np.corrcoef(x, y)[0, 1]) if usable else np.nan
    return out


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
    (``steady_targets``;
    [`suspension_fabric.models.fabric_models.fit_steady`][suspension_fabric.models.fabric_models.fit_steady]), as
    fits.json's ``models`` entries: label, fitted_to, parameters, their jackknife standard errors over seeds of the
    whole fit (NaN, with a warning naming the seed, where a leave-one-out fit fails), their propagated errors
    ([`propagated_fit_errors`][suspension_fabric.evaluation.model_vs_simulation.propagated_fit_errors]), the
    correlations of the leave-one-out parameters (NaN for fewer than 3 seeds) and the model's own steady state. A
    failing fit to all seeds raises ``ValueError`` naming the model. ``steady_of`` (subset of seeds -> steady table)
    shares the leave-one-out tables between models."""
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
        leave_one_out = [subsets.get(tuple(x for x in seeds if x != left), {}) for left in seeds]
        entries[key] = {
            "label": fabric_model.label,
            "fitted_to": [f"n{c}" for c in fabric_model.steady_targets],
            "parameters": fitted,
            "errors": errors,
            "errors_propagated": propagated_fit_errors(fabric_model, steady, phi),
            "correlations": leave_one_out_correlations(leave_one_out, list(fabric_model.names)),
            "steady_state": _as_components(fabric_models.steady_state(fabric_model, fitted, phi)),
        }
    return entries


def fit_steady_state(
    steady: pd.DataFrame,
    phi: float,
    runs: pd.DataFrame,
    strain_min: float,
    strain_max: float,
    models: dict,
) -> dict:
    """Every model of ``models`` ({key: FabricModel}, the config's models.fabric) fitted to the
    startup (theta = 0) steady state; returns the fits.json content
    ([`suspension_fabric.models.fits_file`][suspension_fabric.models.fits_file], format 2).

    ``steady`` is [`suspension_fabric.analysis.tables.steady_state`][suspension_fabric.analysis.tables.steady_state] of
    the per-seed startup run table ``runs`` (columns seed, theta, ..., strain, n11 ... n23, Z; startup_runs.csv) over
    strain_min <= strain <= strain_max (checked: window, seeds and the steady <nn>_11, <nn>_12).
    ``targets`` holds every steady component with its error, ``models`` each model's entry
    ([`fit_listed_models`][suspension_fabric.evaluation.model_vs_simulation.fit_listed_models]), ``fit_errors`` says
    what the errors are.
    """
    startup, seeds = _startup_seeds(runs)
    _check_steady_matches_runs(steady, startup, seeds, strain_min, strain_max)
    targets = {}
    for quantity in (*COMPONENTS, "Z"):
        mean, sem = _steady_value(steady, quantity)
        targets[quantity] = {"mean": mean, "sem": sem}
    window = steady[np.isclose(steady["theta"], 0.0)].iloc[0]
    return {
        "format": FITS_FORMAT,
        "phi": float(phi),
        "steady_window": [float(window["strain_min"]), float(window["strain_max"])],
        "n_seeds": int(window["n_seeds"]),
        "fit_errors": FIT_ERRORS,
        "targets": targets,
        "models": fit_listed_models(
            steady, startup, seeds, strain_min, strain_max, phi, models, _subset_steady(startup, strain_min, strain_max)
        ),
    }


def _as_components(tensor) -> dict:
    return {name: float(tensor[i, j]) for name, (i, j) in COMPONENTS.items()}


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
    fits.json records, else the key."""
    keys = fits["models"] if keys is None else keys
    return {key: fits["models"].get(key, {}).get("label", key) for key in keys}


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
    """Where the models are evaluated (see
    [`prediction_grids`][suspension_fabric.evaluation.model_vs_simulation.prediction_grids]); angles in degrees."""

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
    angles must share (to 1e-9, as [`model_errors`][suspension_fabric.evaluation.model_vs_simulation.model_errors]
    compares them; else ``ValueError``); ``polar_thetas_deg``: 0 to 180 degrees every ``polar_step_deg``, from -180 if a
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
    """[`predict`][suspension_fabric.evaluation.model_vs_simulation.predict] from the simulated initial fabric
    ([`initial_fabric`][suspension_fabric.evaluation.model_vs_simulation.initial_fabric]) on the
    [`prediction_grids`][suspension_fabric.evaluation.model_vs_simulation.prediction_grids] of the seed aggregates: at
    every simulated strain and angle, and at the polar grid of angles (rotation after ``startup_strain`` of startup
    shear)."""
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
    the output of [`predict`][suspension_fabric.evaluation.model_vs_simulation.predict], evaluated at the simulation's
    strains (matched by theta and strain to 1e-9). Returns one row per (model, theta, component) with
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


def summarise_errors(errors: pd.DataFrame, ratio: tuple[str, str] | None = None) -> pd.DataFrame:
    """Angle-averaged rms error per protocol and component for every model.

    One row per (protocol, component): ``rms_<model>`` (means over angles of
    [`model_errors`][suspension_fabric.evaluation.model_vs_simulation.model_errors]' rms_error) for each model, and, for
    ``ratio`` = (a, b) with both models present, ``<a>_over_<b>`` = rms_a / rms_b (> 1: b is closer to the simulation).
    """
    mean = errors.groupby(["protocol", "component", "model"], sort=False)["rms_error"].mean().unstack("model")
    keys = list(dict.fromkeys(errors["model"]))
    summary = pd.DataFrame({f"rms_{key}": mean[key] for key in keys})
    if ratio is not None and set(ratio) <= set(keys):
        summary[f"{ratio[0]}_over_{ratio[1]}"] = mean[ratio[0]] / mean[ratio[1]]
    return summary.reset_index()


def error_tables(
    fits: dict,
    predictions: pd.DataFrame,
    startup_aggregate: pd.DataFrame,
    rotation_aggregate: pd.DataFrame,
    ratio: tuple[str, str] | None = None,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """[`model_errors`][suspension_fabric.evaluation.model_vs_simulation.model_errors] of startup shear and of the
    rotations (normalised by the fitted steady <nn>_12 of ``fits``), concatenated, and their
    [`summarise_errors`][suspension_fabric.evaluation.model_vs_simulation.summarise_errors] (with ``ratio``)."""
    n12_ss = fits["targets"]["n12"]["mean"]
    errors = pd.concat(
        [
            model_errors(startup_aggregate, predictions, n12_ss, "startup"),
            model_errors(rotation_aggregate, predictions, n12_ss, "rotation"),
        ],
        ignore_index=True,
    )
    return errors, summarise_errors(errors, ratio)

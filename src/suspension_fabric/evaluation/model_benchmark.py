"""The study as a benchmark for fabric models: global fits, held-out angles and the leaderboard.

Any [`suspension_fabric.models.fabric_models.FabricModel`][suspension_fabric.models.fabric_models.FabricModel] is scored
the same way on the per-seed run tables of a study (startup and every rotation angle, paper frame of the current shear).

Curves ([`seed_curves`][suspension_fabric.evaluation.model_benchmark.seed_curves]): each seed's fabric along startup and
after each rotation up to the strain window W; the models start from the seed-mean fabric at strain 0 of startup, shear
to the startup strain, turn by theta and shear on ("own" state, as the paper's predictions).

Fitting modes
    ``steady``: the paper's, the parameters reproduce the steady components the model names
    (fits.json's ``models``). ``global``: weighted least squares over the seed-mean startup curve
    and the seed-mean transients of the training angles, every fabric component, each point
    weighted by 1/s.e.^2 of its seed mean (floored at a tenth of the median s.e., so that frames
    where all seeds agree, such as strain 0 after a rotation, do not dominate); parameter errors
    are a jackknife over seeds of the whole fit.

Scores ([`seed_errors`][suspension_fabric.evaluation.model_benchmark.seed_errors]): per seed and component, the mean
over the scored angles and the strains of (0, W] of (model - seed curve)^2 / (<nn>_12^ss)^2, the claims' mean square;
the seeds are the independent units (t-interval). The paired difference of two models' scores per seed
cancels the seed noise both share. Held-out
([`held_out_errors`][suspension_fabric.evaluation.model_benchmark.held_out_errors]): the angles are split into k folds;
a global fit on the startup and the other folds predicts each fold; a model fitted only on the steady state has every
angle held out by construction. In-sample fits also report the weighted chi^2 and AIC = chi^2 + 2 k (k parameters; the
frames along a curve are correlated, so the AIC ranks models but its absolute value overstates the evidence).
"""

from __future__ import annotations

import json
from typing import NamedTuple

import numpy as np
import pandas as pd

from suspension_fabric.analysis.components import COMPONENTS
from suspension_fabric.analysis.seed_statistics import LEVEL, jackknife, t_interval
from suspension_fabric.analysis.tables import fabric_tensors
from suspension_fabric.io.fit_provenance import seeds_text
from suspension_fabric.io.protocols import PAPER_STARTUP, paper_rotation_name
from suspension_fabric.models import fabric_models

from .model_vs_simulation import leave_one_out_correlations

__all__ = [
    "by_seed",
    "angle_mask",
    "mean_square",
    "SeedCurves",
    "seed_curves",
    "model_curves",
    "fit_global",
    "global_fit_with_errors",
    "seed_errors",
    "angle_folds",
    "held_out_errors",
    "held_out_predictions",
    "HeldOut",
    "Leaderboard",
    "leaderboard",
]

_ROWS, _COLS = (np.array(index) for index in zip(*COMPONENTS.values()))
#: Relative finite-difference step of the global fit's Jacobian for models without an exact
#: propagator (their curves come from an ODE solver).
NUMERICAL_DIFF_STEP = 1e-6


def mean_square(predicted, observed, strain) -> np.ndarray:
    """Mean over the strains of (0, W] of (predicted - observed)^2 (the rotation frame itself,
    strain 0, left out)."""
    after = np.asarray(strain) > 0.0
    difference = np.asarray(predicted, dtype=float) - np.asarray(observed, dtype=float)
    return np.mean(difference[..., after] ** 2, axis=-1)


class SeedCurves(NamedTuple):
    """Per-seed fabric curves: ``startup`` (seeds, S, 3, 3) at ``startup_strains``, ``rotation``
    (seeds, angles, R, 3, 3) at ``thetas`` (degrees) and ``rotation_strains`` (0 to W), the
    seed-mean initial fabric and each seed's steady <nn>_12 (for the normalisation)."""

    seeds: np.ndarray
    startup_strains: np.ndarray
    startup: np.ndarray
    thetas: np.ndarray
    rotation_strains: np.ndarray
    rotation: np.ndarray
    fabric0: np.ndarray
    n12_ss: float


def by_seed(runs: pd.DataFrame, seeds, what: str, values=fabric_tensors) -> tuple[np.ndarray, np.ndarray]:
    """(strains, values of each seed stacked) of a run table: ``values(rows)`` of each seed's rows
    sorted by strain (the fabric tensors by default); every seed must share one strain grid."""
    strains, stacked = None, []
    for seed in seeds:
        rows = runs[runs["seed"] == seed].sort_values("strain")
        grid = rows["strain"].to_numpy(dtype=float)
        if strains is None:
            strains = grid
        elif len(grid) != len(strains) or not np.allclose(grid, strains, rtol=1e-9, atol=1e-9):
            raise ValueError(f"{what}: seed {seed} has other strains than seed {seeds[0]}")
        stacked.append(values(rows))
    return strains, np.stack(stacked)


def seed_curves(startup_runs: pd.DataFrame, rotation_runs: pd.DataFrame, window: float, steady_window) -> SeedCurves:
    """[`SeedCurves`][suspension_fabric.evaluation.model_benchmark.SeedCurves] from the per-seed run tables
    (startup_runs.csv, rotation_runs.csv), the rotation curves cut at strain ``window``; every seed must have every
    angle on one grid."""
    seeds = np.array(sorted(set(startup_runs["seed"])), dtype=int)
    if set(rotation_runs["seed"]) != set(seeds):
        raise ValueError(f"seeds differ: startup {sorted(seeds)}, rotation {sorted(set(rotation_runs['seed']))}")
    startup_strains, startup = by_seed(startup_runs, seeds, "startup")
    thetas = np.array(sorted(rotation_runs["theta"].unique()), dtype=float)
    per_angle = [
        by_seed(rotation_runs[np.isclose(rotation_runs["theta"], t)], seeds, f"rotation theta = {t:g}") for t in thetas
    ]
    rotation_strains = per_angle[0][0]
    for theta, (grid, _) in zip(thetas, per_angle):
        if len(grid) != len(rotation_strains) or not np.allclose(grid, rotation_strains, rtol=1e-9, atol=1e-9):
            raise ValueError(f"rotation theta = {theta:g}: other strains than theta = {thetas[0]:g}")
    if rotation_strains[-1] < window - 1e-9:
        raise ValueError(f"the rotation runs reach strain {rotation_strains[-1]:g}, below the window {window:g}")
    keep = rotation_strains <= window + 1e-9
    rotation = np.stack([tensors for _, tensors in per_angle], axis=1)[:, :, keep]
    low, high = steady_window
    inside = (startup_strains >= low - 1e-9) & (startup_strains <= high + 1e-9)
    return SeedCurves(
        seeds,
        startup_strains,
        startup,
        thetas,
        rotation_strains[keep],
        rotation,
        startup[:, 0].mean(axis=0),
        float(startup[:, inside, 0, 1].mean()),
    )


def model_curves(
    fabric_model, params, phi: float, curves: SeedCurves, startup_strain: float, thetas=None
) -> tuple[np.ndarray, np.ndarray]:
    """The model's startup (S, 3, 3) and rotation curves (angles, R, 3, 3) on the curves' grids,
    at ``thetas`` (degrees; default all of the curves' angles)."""
    thetas = curves.thetas if thetas is None else np.asarray(thetas, dtype=float)
    startup = fabric_models.startup_shear(fabric_model, curves.startup_strains, params, phi, curves.fabric0)
    if not fabric_model.affine and abs(curves.startup_strains[-1] - startup_strain) < 1e-12:
        # the startup curve already ends where the rotation starts: the solver's last step lands
        # on the end of the interval whatever the output grid, so this is the same fabric as a
        # second integration would give, at half the cost of a numerically integrated model
        return startup, fabric_models.rotated_shear(
            fabric_model, startup[-1], np.radians(thetas), curves.rotation_strains, params, phi
        )
    rotation = fabric_models.shear_rotation(
        fabric_model, np.radians(thetas), curves.rotation_strains, params, phi, startup_strain, curves.fabric0
    )
    return startup, rotation


def _components(tensors) -> np.ndarray:
    return tensors[..., _ROWS, _COLS]


def angle_mask(curves, thetas=None) -> np.ndarray:
    """Which of the curves' angles are among ``thetas`` (degrees; default all)."""
    if thetas is None:
        return np.ones(len(curves.thetas), dtype=bool)
    return np.array([np.any(np.isclose(t, np.asarray(thetas, dtype=float))) for t in curves.thetas])


def _weights(values) -> np.ndarray:
    """1 / s.e. of the seed mean over the first axis, floored at a tenth of the median s.e."""
    sem = values.std(axis=0, ddof=1) / np.sqrt(values.shape[0])
    floor = 0.1 * np.median(sem[sem > 0]) if np.any(sem > 0) else 1.0
    return 1.0 / np.maximum(sem, floor)


def fit_global(
    fabric_model, curves: SeedCurves, phi: float, startup_strain: float, start: dict, train_thetas=None, seeds=None
) -> dict:
    """Weighted least squares of the model on the seed-mean startup curve and the seed-mean
    transients at ``train_thetas`` (default all), over ``seeds`` (default all), from ``start``.
    Returns {"parameters", "chi2", "n_points"}; a failing solver raises ``ValueError``."""
    select = np.isin(curves.seeds, curves.seeds if seeds is None else seeds)
    if select.sum() < 2:
        raise ValueError("a global fit needs at least two seeds (the weights are their standard errors)")
    angle = angle_mask(curves, train_thetas)
    startup = _components(curves.startup[select])
    rotation = _components(curves.rotation[select][:, angle])
    targets = (startup.mean(axis=0), rotation.mean(axis=0))
    weights = (_weights(startup), _weights(rotation))
    bounds = ([p.lower for p in fabric_model.parameters], [p.upper for p in fabric_model.parameters])
    x0 = np.clip([start[name] for name in fabric_model.names], *bounds)
    n_residuals = sum(t.size for t in targets)

    def residual(x):
        params = dict(zip(fabric_model.names, x))
        try:
            predicted = model_curves(fabric_model, params, phi, curves, startup_strain, curves.thetas[angle])
        except (ValueError, np.linalg.LinAlgError):
            return np.full(n_residuals, 1e6)
        return np.concatenate([((_components(p) - t) * w).ravel() for p, t, w in zip(predicted, targets, weights)])

    # a model integrated numerically (rtol 1e-10) has residuals noisy at ~1e-10: the default
    # finite-difference step (~1e-8) would turn that into ~1% noise in the Jacobian
    step = None if fabric_model.affine else NUMERICAL_DIFF_STEP
    from scipy.optimize import least_squares  # scipy where used: table-only jobs start without it

    result = least_squares(residual, x0, bounds=bounds, x_scale="jac", xtol=1e-10, ftol=1e-10, diff_step=step)
    if not result.success:
        raise ValueError(f"model {fabric_model.key}: global fit failed ({result.message})")
    return {
        "parameters": fabric_model.check(dict(zip(fabric_model.names, result.x))),
        "chi2": float(np.sum(result.fun**2)),
        "n_points": int(result.fun.size),
    }


def global_fit_with_errors(fabric_model, curves: SeedCurves, phi: float, startup_strain: float, start: dict) -> dict:
    """[`fit_global`][suspension_fabric.evaluation.model_benchmark.fit_global] on every angle with jackknife errors over
    seeds of the whole fit and the correlations of the leave-one-out parameters (NaN for fewer than 3 seeds: a
    leave-one-out fit needs two seeds for its weights)."""
    fitted = fit_global(fabric_model, curves, phi, startup_strain, start)
    if len(curves.seeds) < 3:
        fitted["errors"] = dict.fromkeys(fabric_model.names, np.nan)
        fitted["correlations"] = {}
        return fitted
    cache = {}

    def parameter(subset, name):
        key = tuple(subset)
        if key not in cache:
            cache[key] = fit_global(fabric_model, curves, phi, startup_strain, fitted["parameters"], seeds=list(key))[
                "parameters"
            ]
        return cache[key][name]

    fitted["errors"] = {
        name: jackknife(lambda subset, name=name: parameter(subset, name), curves.seeds)[1]
        for name in fabric_model.names
    }
    seeds = list(curves.seeds)
    left_out = [cache[tuple(s for s in seeds if s != left)] for left in seeds]
    fitted["correlations"] = leave_one_out_correlations(left_out, list(fabric_model.names))
    return fitted


def seed_errors(predicted_rotation, curves: SeedCurves, thetas=None) -> np.ndarray:
    """Per seed and component (seeds, 6): mean over the angles ``thetas`` (default all) and the
    strains of (0, W] of (model - seed curve)^2 / (<nn>_12^ss)^2; ``predicted_rotation`` is
    (angles, R, 3, 3) at those angles."""
    observed = _components(curves.rotation[:, angle_mask(curves, thetas)])  # (seeds, angles, R, 6)
    predicted = _components(predicted_rotation)[None]
    # mean_square averages over the strains on the last axis: put the components before them
    per_angle = mean_square(np.moveaxis(predicted, -1, -2), np.moveaxis(observed, -1, -2), curves.rotation_strains)
    return per_angle.mean(axis=1) / curves.n12_ss**2


def angle_folds(thetas, k: int) -> list[np.ndarray]:
    """The angles split into ``k`` folds by stride (fold j: every k-th angle from the j-th), so each
    fold spans the range; k is capped at the number of angles."""
    thetas = np.sort(np.asarray(thetas, dtype=float))
    k = min(int(k), len(thetas))
    if k < 2:
        raise ValueError(f"held-out evaluation needs at least two folds of angles, got {k} from {thetas.tolist()}")
    return [thetas[j::k] for j in range(k)]


def held_out_predictions(
    fabric_model, curves: SeedCurves, phi: float, startup_strain: float, start: dict, folds: int
) -> tuple[np.ndarray, np.ndarray]:
    """Each angle predicted by a global fit on the startup and the other folds: the per seed and
    component (seeds, 6) mean square errors averaged over all angles, and the predictions
    (angles, R, 3, 3) on the curves' angles."""
    total = np.zeros((len(curves.seeds), len(COMPONENTS)))
    predicted = np.empty((len(curves.thetas), len(curves.rotation_strains), 3, 3))
    for held in angle_folds(curves.thetas, folds):
        train = curves.thetas[~np.isin(curves.thetas, held)]
        params = fit_global(fabric_model, curves, phi, startup_strain, start, train_thetas=train)["parameters"]
        _, rotation = model_curves(fabric_model, params, phi, curves, startup_strain, held)
        total += seed_errors(rotation, curves, held) * len(held)
        predicted[angle_mask(curves, held)] = rotation  # both in ascending order of angle
    return total / len(curves.thetas), predicted


def held_out_errors(
    fabric_model, curves: SeedCurves, phi: float, startup_strain: float, start: dict, folds: int
) -> np.ndarray:
    """Per seed and component (seeds, 6): the mean square error of each angle predicted by a
    global fit on the startup and the other folds, averaged over all angles."""
    return held_out_predictions(fabric_model, curves, phi, startup_strain, start, folds)[0]


class HeldOut(NamedTuple):
    """One model and fitting mode's held-out scores: ``errors`` (seeds, 6), ``predicted`` (angles,
    R, 3, 3) and the ``parameters`` of the fit on every angle (the steady fit's for mode steady,
    whose every angle is held out by construction)."""

    errors: np.ndarray
    predicted: np.ndarray
    parameters: dict


class Leaderboard(NamedTuple):
    """[`leaderboard`][suspension_fabric.evaluation.model_benchmark.leaderboard]'s table, the fitted parameters and the
    held-out scores by (model, mode)."""

    table: pd.DataFrame
    parameters: pd.DataFrame
    held_out: dict


def leaderboard(
    models: dict,
    steady_fits: dict,
    curves: SeedCurves,
    phi: float,
    startup_strain: float,
    folds: int,
    *,
    reference: str,
    level: float = LEVEL,
    study: str = "",
) -> Leaderboard:
    """The leaderboard (one row per model, fitting mode and component: in-sample and held-out
    mean square errors with t-intervals over seeds, the paired difference from ``reference`` on
    the held-out errors, the number of parameters, chi^2 and AIC of the in-sample fit) and the
    fitted parameters per model and mode with their errors.

    ``steady_fits`` is fits.json's ``models`` section (parameters of the steady fits). Each parameter
    row records what its fit saw (suspension_fabric.io.fit_provenance): ``study``, the seeds
    and the runs (the startup; and every rotation for the global fit)."""
    rows, parameters, held_by_model = [], [], {}
    for key, fabric_model in models.items():
        steady = steady_fits[key]["parameters"]
        fitted = global_fit_with_errors(fabric_model, curves, phi, startup_strain, steady)
        modes = {
            "steady": (steady, steady_fits[key]["errors"], None),
            "global": (fitted["parameters"], fitted["errors"], fitted),
        }
        correlations = {"steady": steady_fits[key].get("correlations", {}), "global": fitted["correlations"]}
        for mode, (params, errors, fit) in modes.items():
            rotations = [paper_rotation_name(theta) for theta in curves.thetas] if mode == "global" else []
            for name, value in params.items():
                parameters.append(
                    {
                        "model": key,
                        "label": fabric_model.label,
                        "mode": mode,
                        "parameter": name,
                        "value": value,
                        "error": errors[name],
                        "correlations": json.dumps(correlations[mode], sort_keys=True),
                        "fitted_on": study,
                        "fitted_seeds": seeds_text(curves.seeds),
                        "fitted_runs": " ".join([PAPER_STARTUP, *rotations]),
                    }
                )
            _, rotation = model_curves(fabric_model, params, phi, curves, startup_strain)
            in_sample = seed_errors(rotation, curves)
            held, predicted = (
                (in_sample, rotation)
                if mode == "steady"
                else held_out_predictions(fabric_model, curves, phi, startup_strain, params, folds)
            )
            held_by_model[(key, mode)] = HeldOut(held, predicted, params)
            chi2 = np.nan if fit is None else fit["chi2"]
            for c, component in enumerate(COMPONENTS):
                inside, outside = t_interval(in_sample[:, c], level), t_interval(held[:, c], level)
                rows.append(
                    {
                        "model": key,
                        "label": fabric_model.label,
                        "mode": mode,
                        "component": component,
                        "n_parameters": len(fabric_model.parameters),
                        "in_sample_mse": inside.mean,
                        "in_sample_low": inside.low,
                        "in_sample_high": inside.high,
                        "held_out_mse": outside.mean,
                        "held_out_low": outside.low,
                        "held_out_high": outside.high,
                        "chi2": chi2,
                        "aic": chi2 + 2 * len(fabric_model.parameters),
                    }
                )
    table = pd.DataFrame(rows)
    for field in ("difference", "difference_low", "difference_high"):
        table[f"held_out_{field}_vs_{reference}"] = np.nan
    if (reference, "steady") in held_by_model:
        base = held_by_model[(reference, "steady")].errors
        for index, row in table.iterrows():
            c = list(COMPONENTS).index(row["component"])
            paired = t_interval(held_by_model[(row["model"], row["mode"])].errors[:, c] - base[:, c], level)
            table.loc[
                index, [f"held_out_{f}_vs_{reference}" for f in ("difference", "difference_low", "difference_high")]
            ] = (paired.mean, paired.low, paired.high)
    return Leaderboard(table, pd.DataFrame(parameters), held_by_model)

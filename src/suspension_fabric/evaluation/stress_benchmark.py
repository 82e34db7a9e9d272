"""The study as a benchmark for stress relations: steady normal stresses and held-out viscosity transients.

Any [`suspension_fabric.models.stress_relations.StressRelation`][] is scored on the per-seed run tables
of a study, on each seed's own simulated fabric (so the score is the relation's, not a fabric
model's): the relation evaluated on seed s's <nn>(gamma) is compared with seed s's stress.

Data ([`stress_curves`][suspension_fabric.evaluation.stress_benchmark.stress_curves]): per seed, the fabric and eta_r
along startup and after each rotation up to strain W (the frames of the fabric and stress tables are the same steps),
and the seed's steady state (means over the steady window of startup: <nn>, lubrication and contact sigma_12,
eta_r, N1, N2, Pi).

Fitting modes
    ``steady``: a_H, a_C from the seed-mean steady lubrication and contact sigma_12
    ([`suspension_fabric.models.stress_relations.coefficients`][]), shape parameters at their start
    values; the mode of a relation without shape parameters. ``global``: the shape parameters
    minimise the mean over seeds and curves (startup and the training angles' transients) of the
    mean square error of eta_r, with a_H, a_C refitted to the steady state at each trial value;
    parameter errors are a jackknife over seeds of the whole fit.

Scores, per seed (the independent units; t-intervals at the verdicts' level), in units of the
seed-mean steady eta_r: the mean over strains (0, W] and angles of (relation - seed)^2 of eta_r
after rotation (``eta_r rotation``), the same over startup (``eta_r startup``), and the squared
error of the seed's steady N1, N2 and Pi; with each its signed mean (bias). Held out
(``eta_r rotation`` only): the angles in k folds, each predicted by a global fit on the startup
and the other folds. The paired per-seed difference from the G-W relation cancels the noise the
two share.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import LEVEL, jackknife, t_interval
from suspension_fabric.analysis.tables import read_fabric_table
from suspension_fabric.models.stress_relations import RelationError, StressRelation, coefficients, relation_stress

from .model_benchmark import angle_folds, angle_mask, by_seed

__all__ = [
    "StressCurves",
    "stress_curves",
    "read_stress_curves",
    "relation_predictions",
    "seed_scores",
    "fit_shape",
    "held_out_scores",
    "relation_leaderboard",
    "STEADY_QUANTITIES",
    "SCORED",
]

STEADY_QUANTITIES = ("N1", "N2", "Pi")
#: The scored quantities, in the leaderboard's order.
SCORED = ("eta_r rotation", "eta_r startup", *(f"{q} steady" for q in STEADY_QUANTITIES))
_STEADY_COLUMNS = ("lubrication_12", "contact_12", "eta_r", *STEADY_QUANTITIES)


class StressCurves(NamedTuple):
    """Per-seed fabric and eta_r curves and steady states (module docstring): ``startup_fabric``
    (seeds, S, 3, 3), ``startup_eta`` (seeds, S), ``rotation_fabric`` (seeds, angles, R, 3, 3),
    ``rotation_eta`` (seeds, angles, R), ``steady_fabric`` (seeds, 3, 3), ``steady`` (seeds x
    lubrication_12, contact_12, eta_r, N1, N2, Pi)."""

    seeds: np.ndarray
    phi: float
    startup_strains: np.ndarray
    startup_fabric: np.ndarray
    startup_eta: np.ndarray
    thetas: np.ndarray
    rotation_strains: np.ndarray
    rotation_fabric: np.ndarray
    rotation_eta: np.ndarray
    steady_fabric: np.ndarray
    steady: pd.DataFrame

    @property
    def eta_ss(self) -> float:
        return float(self.steady["eta_r"].mean())


def _joined(fabric: pd.DataFrame, stress: pd.DataFrame, what: str) -> pd.DataFrame:
    keys = ["seed", "theta", "step"]
    joined = fabric.merge(stress[[*keys, *_STEADY_COLUMNS]], on=keys, how="inner", validate="one_to_one")
    if len(joined) != len(fabric) or len(joined) != len(stress):
        raise ValueError(
            f"{what}: the fabric ({len(fabric)} frames) and stress ({len(stress)} frames) tables "
            f"share only {len(joined)} (seed, theta, step) frames"
        )
    return joined


def _per_seed(rows: pd.DataFrame, seeds, what: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    strains, fabrics = by_seed(rows, seeds, what)
    _, etas = by_seed(rows, seeds, what, lambda mine: mine["eta_r"].to_numpy(dtype=float))
    return strains, fabrics, etas


def stress_curves(
    startup_fabric: pd.DataFrame,
    rotation_fabric: pd.DataFrame,
    startup_stress: pd.DataFrame,
    rotation_stress: pd.DataFrame,
    window: float,
    steady_window,
) -> StressCurves:
    """[`StressCurves`][suspension_fabric.evaluation.stress_benchmark.StressCurves] from the study's per-seed run tables
    (startup_runs.csv, rotation_runs.csv, stress_startup_runs.csv, stress_rotation_runs.csv), the rotations cut at
    strain ``window``."""
    startup = _joined(startup_fabric, startup_stress, "startup")
    rotation = _joined(rotation_fabric, rotation_stress, "rotation")
    seeds = np.array(sorted(set(startup["seed"])), dtype=int)
    if set(rotation["seed"]) != set(seeds):
        raise ValueError(f"seeds differ: startup {seeds.tolist()}, rotation {sorted(set(rotation['seed']))}")
    if len(seeds) < 2:
        raise ValueError("the stress-relation benchmark needs at least two seeds (its intervals are over seeds)")
    startup_strains, startup_fab, startup_eta = _per_seed(startup, seeds, "startup")
    thetas = np.array(sorted(rotation["theta"].unique()), dtype=float)
    per_angle = [
        _per_seed(rotation[np.isclose(rotation["theta"], t)], seeds, f"rotation theta = {t:g}") for t in thetas
    ]
    strains = per_angle[0][0]
    for theta, (grid, _, _) in zip(thetas, per_angle):
        if len(grid) != len(strains) or not np.allclose(grid, strains, rtol=1e-9, atol=1e-9):
            raise ValueError(f"rotation theta = {theta:g}: other strains than theta = {thetas[0]:g}")
    if strains[-1] < window - 1e-9:
        raise ValueError(f"the rotation runs reach strain {strains[-1]:g}, below the window {window:g}")
    keep = strains <= window + 1e-9
    low, high = steady_window
    inside = (startup_strains >= low - 1e-9) & (startup_strains <= high + 1e-9)
    if inside.sum() < 2:
        raise ValueError(f"the steady window {steady_window} holds {inside.sum()} startup frame(s), need 2")
    window_rows = startup[(startup["strain"] >= low - 1e-9) & (startup["strain"] <= high + 1e-9)]
    steady = window_rows.groupby("seed")[list(_STEADY_COLUMNS)].mean().loc[seeds]
    return StressCurves(
        seeds,
        float(startup["phi"].mean()),
        startup_strains,
        startup_fab,
        startup_eta,
        thetas,
        strains[keep],
        np.stack([p[1] for p in per_angle], axis=1)[:, :, keep],
        np.stack([p[2] for p in per_angle], axis=1)[:, :, keep],
        startup_fab[:, inside].mean(axis=1),
        steady,
    )


def read_stress_curves(
    startup_runs, rotation_runs, stress_startup_runs, stress_rotation_runs, window: float, steady_window
) -> StressCurves:
    """[`stress_curves`][suspension_fabric.evaluation.stress_benchmark.stress_curves] from the study's run-table files
    (startup_runs.csv, rotation_runs.csv, stress_startup_runs.csv, stress_rotation_runs.csv)."""
    return stress_curves(
        read_fabric_table(startup_runs),
        read_fabric_table(rotation_runs),
        pd.read_csv(stress_startup_runs),
        pd.read_csv(stress_rotation_runs),
        window,
        steady_window,
    )


def _select(curves: StressCurves, seeds=None) -> np.ndarray:
    return np.isin(curves.seeds, curves.seeds if seeds is None else seeds)


def relation_predictions(relation: StressRelation, params, curves: StressCurves, seeds=None) -> dict:
    """a_H, a_C from the seed-mean steady state of ``seeds`` (default all), and the relation on
    every seed's fabric: eta_r along startup (seeds, S) and the rotations (seeds, angles, R), and
    the steady N1, N2, Pi (seeds,)."""
    select = _select(curves, seeds)
    steady = curves.steady.loc[curves.seeds[select]]
    coefficient = coefficients(
        relation,
        curves.steady_fabric[select].mean(axis=0),
        steady["lubrication_12"].mean(),
        steady["contact_12"].mean(),
        params,
    )

    def stress(fabric):
        return relation_stress(relation, fabric, coefficient, params, curves.phi)

    at_steady = stress(curves.steady_fabric)
    return {
        "coefficients": coefficient,
        "eta_r startup": stress(curves.startup_fabric)["eta_r"],
        "eta_r rotation": stress(curves.rotation_fabric)["eta_r"],
        **{f"{q} steady": at_steady[q] for q in STEADY_QUANTITIES},
    }


def seed_scores(predicted: dict, curves: StressCurves, thetas=None) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Per scored quantity, (mean square error, mean signed error) per seed (module docstring), the
    rotation over ``thetas`` (default all)."""
    scale = curves.eta_ss
    angle = angle_mask(curves, thetas)
    after_rotation = curves.rotation_strains > 0.0
    after_start = curves.startup_strains > 0.0
    rotation = (
        predicted["eta_r rotation"][:, angle][..., after_rotation] - curves.rotation_eta[:, angle][..., after_rotation]
    ) / scale
    startup = (predicted["eta_r startup"][:, after_start] - curves.startup_eta[:, after_start]) / scale
    scores = {
        "eta_r rotation": ((rotation**2).mean(axis=(1, 2)), rotation.mean(axis=(1, 2))),
        "eta_r startup": ((startup**2).mean(axis=1), startup.mean(axis=1)),
    }
    for q in STEADY_QUANTITIES:
        error = (predicted[f"{q} steady"] - curves.steady[q].to_numpy()) / scale
        scores[f"{q} steady"] = (error**2, error)
    return scores


def _objective(relation: StressRelation, curves: StressCurves, train_thetas, seeds):
    """Mean over the selected seeds and curves (startup and each training angle) of eta_r's mean
    square error ([`seed_scores`][suspension_fabric.evaluation.stress_benchmark.seed_scores])."""
    select = _select(curves, seeds)
    n_angles = int(angle_mask(curves, train_thetas).sum())

    def value(x) -> float:
        params = dict(zip(relation.names, np.atleast_1d(x)))
        # beyond a divergence (e.g. Z >= Z_J) the relation is infinite: not a candidate
        with np.errstate(invalid="ignore", over="ignore"):
            try:
                predicted = relation_predictions(relation, params, curves, curves.seeds[select])
            except RelationError:
                return np.inf
            scores = seed_scores(predicted, curves, train_thetas)
            per_seed = (n_angles * scores["eta_r rotation"][0] + scores["eta_r startup"][0]) / (n_angles + 1)
            total = float(per_seed[select].mean())
        return total if np.isfinite(total) else np.inf

    return value


def fit_shape(relation: StressRelation, curves: StressCurves, train_thetas=None, seeds=None) -> dict[str, float]:
    """The shape parameters of the ``global`` mode on the startup and the transients at
    ``train_thetas`` (default all) of ``seeds`` (default all); {} for a relation without any."""
    if not relation.parameters:
        return {}
    from scipy.optimize import minimize, minimize_scalar  # scipy where used: table-only jobs start without it

    objective = _objective(relation, curves, train_thetas, seeds)
    bounds = [(p.lower, p.upper) for p in relation.parameters]
    if len(bounds) == 1:
        result = minimize_scalar(objective, bounds=bounds[0], method="bounded", options={"xatol": 1e-6})
        x = [result.x]
    else:
        result = minimize(objective, [p.start for p in relation.parameters], method="Powell", bounds=bounds)
        x = result.x
    if not np.isfinite(objective(x)):
        raise RelationError(
            f"stress relation {relation.key}: no finite fit of {list(relation.names)} within their bounds"
        )
    return relation.check(dict(zip(relation.names, np.atleast_1d(x))))


def held_out_scores(relation: StressRelation, curves: StressCurves, folds: int) -> tuple[np.ndarray, np.ndarray]:
    """Per seed, (mean square, mean signed) error of eta_r after rotation, each fold of angles
    predicted by a global fit on the startup and the other folds, averaged over all angles."""
    squares, signed = np.zeros(len(curves.seeds)), np.zeros(len(curves.seeds))
    for held in angle_folds(curves.thetas, folds):
        train = curves.thetas[~np.isin(curves.thetas, held)]
        params = fit_shape(relation, curves, train)
        square, bias = seed_scores(relation_predictions(relation, params, curves), curves, held)["eta_r rotation"]
        squares += square * len(held)
        signed += bias * len(held)
    return squares / len(curves.thetas), signed / len(curves.thetas)


def relation_leaderboard(
    relations: dict, curves: StressCurves, folds: int, *, reference: str, level: float = LEVEL
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The stress-relation leaderboard (one row per relation, mode and scored quantity: in-sample
    and, for eta_r after rotation, held-out mean square errors and signed biases with t-intervals
    over seeds, the paired held-out difference from ``reference``, the number of fitted values)
    and the fitted values (a_H, a_C and the shape parameters, with jackknife errors for the
    global mode)."""
    rows, parameters, held_by = [], [], {}
    for key, relation in relations.items():
        modes = {"steady": relation.start()}
        if relation.parameters:
            modes = {"global": fit_shape(relation, curves)}
        for mode, params in modes.items():
            predicted = relation_predictions(relation, params, curves)
            errors = dict.fromkeys(relation.names, np.nan)
            if mode == "global" and len(curves.seeds) >= 3:
                errors = {
                    name: jackknife(
                        lambda subset, name=name: fit_shape(relation, curves, seeds=subset)[name], curves.seeds
                    )[1]
                    for name in relation.names
                }
            fitted = {name: predicted["coefficients"][name] for name in ("a_H", "a_C")}
            for name, value in {**fitted, **params}.items():
                parameters.append(
                    {
                        "relation": key,
                        "label": relation.label,
                        "mode": mode,
                        "parameter": name,
                        "value": value,
                        "error": errors.get(name, np.nan),
                    }
                )
            scores = seed_scores(predicted, curves)
            held = scores["eta_r rotation"] if mode == "steady" else held_out_scores(relation, curves, folds)
            held_by[key] = held[0]
            for quantity in SCORED:
                square, bias = scores[quantity]
                inside, drift = t_interval(square, level), t_interval(bias, level)
                row = {
                    "relation": key,
                    "label": relation.label,
                    "mode": mode,
                    "quantity": quantity,
                    "n_fitted": 2 + len(relation.parameters),
                    "in_sample_mse": inside.mean,
                    "in_sample_low": inside.low,
                    "in_sample_high": inside.high,
                    "bias": drift.mean,
                    "bias_low": drift.low,
                    "bias_high": drift.high,
                }
                outside = t_interval(held[0], level) if quantity == "eta_r rotation" else None
                for field in ("mse", "low", "high"):
                    row[f"held_out_{field}"] = (
                        np.nan if outside is None else getattr(outside, "mean" if field == "mse" else field)
                    )
                rows.append(row)
    table = pd.DataFrame(rows)
    names = [f"held_out_difference{suffix}_vs_{reference}" for suffix in ("", "_low", "_high")]
    table[names] = np.nan
    if reference in held_by:
        for index, row in table[table["quantity"] == "eta_r rotation"].iterrows():
            paired = t_interval(held_by[row["relation"]] - held_by[reference], level)
            table.loc[index, names] = (paired.mean, paired.low, paired.high)
    return table, pd.DataFrame(parameters)

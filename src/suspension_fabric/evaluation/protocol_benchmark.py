"""Every fabric model and stress relation on every protocol: predicted from the same flow history,
scored per seed, each score labelled held out only if no fit behind it saw its seed
([`suspension_fabric.io.fit_provenance`][suspension_fabric.io.fit_provenance]).

Fabric models. Each model keeps the parameters of its two fitting modes in the rotation benchmark
([`suspension_fabric.evaluation.model_benchmark`][suspension_fabric.evaluation.model_benchmark]): ``steady``, fitted on
the startup's steady state (fits.json), and ``global``, fitted on the startup and every rotation's transient
(model_parameters.csv). From the seed-mean fabric at rest it predicts <nn> along each protocol
([`suspension_fabric.models.fabric_models.protocol_fabric`][suspension_fabric.models.fabric_models.protocol_fabric]), in
the frame of the current flow, on the frames of the simulations. Scored: the frames after the first segment (the
startup, which both modes saw), without the first frame of each segment (the last frame of the segment
before, seen in the new flow's frame): per seed and component the mean of
(model - seed)^2 / (<nn>_12^ss)^2, and ``all``, the mean over the six components.

Stress relations. Each relation, with its coefficients a_H, a_C from the steady state and its
shape parameters as fitted in the stress benchmark (stress_relation_parameters.csv), is evaluated
on each seed's own fabric along the protocol and compared with the seed's eta_r, N1 and N2 on the
same frames: per seed the mean of (relation - seed)^2 / (eta_r^ss)^2.

The seeds are the independent units: every score has its t-interval over seeds at the verdicts'
level, and the named effect is the paired per-seed difference of a model's (relation's) score
from G-W's (the G-W relation's) in the steady mode, with its t-interval and its p-value adjusted
by Holm's method over every difference of the table, since all are read at once; a difference
below zero whose adjusted p-value is under 1 - level means the model beats G-W on that protocol.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np
import pandas as pd

from suspension_fabric.analysis.components import COMPONENTS
from suspension_fabric.analysis.seed_statistics import LEVEL, adjusted_p, t_interval, t_test_p, variance_pseudo_values
from suspension_fabric.io.protocols import Protocol
from suspension_fabric.models import fabric_models
from suspension_fabric.models.stress_relations import coefficients, relation_stress

from .model_benchmark import by_seed

__all__ = [
    "ProtocolCurves",
    "protocol_curves",
    "model_protocol_predictions",
    "fabric_protocol_scores",
    "fabric_protocol_floor",
    "parameter_spread",
    "parameters_by_mode",
    "fabric_protocol_leaderboard",
    "stress_protocol_leaderboard",
    "STRESS_SCORED",
    "ALL_COMPONENTS",
]

#: The stress quantities scored along a protocol.
STRESS_SCORED = ("eta_r", "N1", "N2")
#: The ``component`` of the score averaged over the six fabric components.
ALL_COMPONENTS = "all"
_ROWS, _COLS = (np.array(index) for index in zip(*COMPONENTS.values()))


class ProtocolCurves(NamedTuple):
    """One protocol's per-seed data, per segment k: ``segment_strains[k]`` (F_k,), ``strains[k]``
    (total strain), ``fabric[k]`` (seeds, F_k, 3, 3) and, where the stress was given, ``stress[k]``
    {quantity: (seeds, F_k)}."""

    protocol: Protocol
    seeds: np.ndarray
    segment_strains: list
    strains: list
    fabric: list
    stress: list | None


def protocol_curves(
    protocol: Protocol, runs: pd.DataFrame, stress_runs: pd.DataFrame | None = None, seeds=None
) -> ProtocolCurves:
    """[`ProtocolCurves`][suspension_fabric.evaluation.protocol_benchmark.ProtocolCurves] from a protocol table
    (protocol_runs.csv; and stress_protocol_runs.csv)."""
    mine = runs[runs["protocol"] == protocol.name]
    if mine.empty:
        raise ValueError(f"protocol {protocol.name}: no rows in the protocol table")
    seeds = np.array(sorted(set(mine["seed"])) if seeds is None else seeds, dtype=int)
    stressed = None if stress_runs is None else stress_runs[stress_runs["protocol"] == protocol.name]
    segment_strains, strains, fabric, stress = [], [], [], []
    for index in range(len(protocol.segments)):
        rows = mine[mine["segment"] == index]
        what = f"protocol {protocol.name}, segment {index}"
        grid, tensors = by_seed(rows, seeds, what)
        segment_grid, _ = by_seed(
            rows.assign(strain=rows["segment_strain"]), seeds, what, lambda r: r["segment_strain"].to_numpy()
        )
        segment_strains.append(segment_grid)
        strains.append(grid)
        fabric.append(tensors)
        if stressed is not None:
            rows_s = stressed[stressed["segment"] == index]
            values = {}
            for quantity in STRESS_SCORED:
                stress_grid, values[quantity] = by_seed(
                    rows_s, seeds, what, lambda r, q=quantity: r[q].to_numpy(dtype=float)
                )
                if len(stress_grid) != len(grid) or not np.allclose(stress_grid, grid, atol=1e-9):
                    raise ValueError(f"{what}: the stress and fabric tables have other frames")
            stress.append(values)
    return ProtocolCurves(protocol, seeds, segment_strains, strains, fabric, stress if stressed is not None else None)


def _scored_frames(curves: ProtocolCurves) -> list[np.ndarray]:
    """Per segment, which frames are scored: none of the first segment, not the first of any."""
    return [np.zeros(len(grid), dtype=bool) if k == 0 else grid > 0.0 for k, grid in enumerate(curves.segment_strains)]


def model_protocol_predictions(fabric_model, params, phi: float, curves: ProtocolCurves) -> list[np.ndarray]:
    """The model's fabric along the protocol from the seed-mean fabric at rest, per segment (F_k, 3, 3)."""
    fabric0 = curves.fabric[0][:, 0].mean(axis=0)
    return fabric_models.protocol_fabric(fabric_model, curves.protocol, curves.segment_strains, params, phi, fabric0)


def _scored_seed_components(curves: ProtocolCurves, predicted: list | None = None) -> np.ndarray:
    """(seeds, frames, 6) over the scored frames: each seed's fabric components, less the
    prediction's where one is given."""
    blocks = [
        f[:, keep][..., _ROWS, _COLS] - (0.0 if predicted is None else predicted[k][None, keep][..., _ROWS, _COLS])
        for k, (f, keep) in enumerate(zip(curves.fabric, _scored_frames(curves)))
    ]
    stacked = np.concatenate(blocks, axis=1)
    if stacked.shape[1] == 0:
        raise ValueError(f"protocol {curves.protocol.name}: no frame after the first segment to score")
    return stacked


def fabric_protocol_scores(predicted: list, curves: ProtocolCurves, n12_ss: float) -> np.ndarray:
    """Per seed and component (seeds, 6): mean over the scored frames of (model - seed)^2 / n12_ss^2."""
    return (_scored_seed_components(curves, predicted) ** 2).mean(axis=1) / n12_ss**2


def fabric_protocol_floor(curves: ProtocolCurves, n12_ss: float) -> np.ndarray:
    """Per seed and component (seeds, 6): the seed-noise floor of
    [`fabric_protocol_scores`][suspension_fabric.evaluation.protocol_benchmark.fabric_protocol_scores], the
    between-seed variance (ddof 1) of the simulated fabric over the scored frames / n12_ss^2 (what the
    true mean curve would score on a new seed), as each seed's jackknife pseudo-value
    ([`variance_pseudo_values`][suspension_fabric.analysis.seed_statistics.variance_pseudo_values]): their mean
    is the floor, and a score net of them carries the floor's own error into an interval over seeds."""
    return variance_pseudo_values(_scored_seed_components(curves)).mean(axis=1) / n12_ss**2


def parameters_by_mode(fitted: pd.DataFrame) -> tuple[dict, dict, dict]:
    """A parameters table (the model benchmark's model_parameters.csv) as three mappings
    ``[mode][model]``: each parameter's value, its standard error (NaN for a fit without errors)
    and the fit's leave-one-out correlations ({"a,b": r}; empty where the table has none)."""
    values, errors, correlations = {}, {}, {}
    for (mode, key), rows in fitted.groupby(["mode", "model"], sort=False):
        by_name = rows.set_index("parameter")
        values.setdefault(mode, {})[key] = by_name["value"].to_dict()
        errors.setdefault(mode, {})[key] = by_name["error"].astype(float).to_dict()
        has = "correlations" in rows and isinstance(rows["correlations"].iloc[0], str)
        correlations.setdefault(mode, {})[key] = json.loads(rows["correlations"].iloc[0]) if has else {}
    return values, errors, correlations


def parameter_spread(
    fabric_model, params: Mapping[str, float], errors: Mapping[str, float] | None, phi: float,
    curves: ProtocolCurves, n12_ss: float, correlations: Mapping[str, float] | None = None,
) -> np.ndarray:  # fmt: skip
    """(7,): per component and for their mean (the leaderboard's ``all``), the standard error the
    fit's own uncertainty gives the seed-mean score S, to first order: with h_k = (S(p_k + s_k) -
    S(p_k - s_k)) / 2, s_k parameter k's standard error, sqrt(sum_kl h_k h_l r_kl) where r is the
    fit's leave-one-out correlation matrix (``correlations``: {"a,b": r}); where a pair's
    correlation is missing, sum_k |h_k|, a bound whatever the correlations. NaN where a parameter
    has no finite error or a moved model cannot be integrated: not propagated."""
    names = list(params)
    missing = np.full(len(COMPONENTS) + 1, np.nan)
    if errors is None or not all(np.isfinite(errors.get(name, np.nan)) for name in names):
        return missing
    half_steps = []
    for name in names:
        moved = []
        for sign in (1.0, -1.0):
            shifted = {**params, name: params[name] + sign * errors[name]}
            try:
                predicted = model_protocol_predictions(fabric_model, shifted, phi, curves)
            except (ValueError, fabric_models.ModelError):
                return missing
            per_seed = fabric_protocol_scores(predicted, curves, n12_ss).mean(axis=0)
            moved.append(np.append(per_seed, per_seed.mean()))
        half_steps.append(0.5 * (moved[0] - moved[1]))
    h = np.array(half_steps)  # (parameters, 7)
    matrix = np.eye(len(names))
    for i, first in enumerate(names):
        for j in range(i + 1, len(names)):
            r = (correlations or {}).get(f"{first},{names[j]}", (correlations or {}).get(f"{names[j]},{first}"))
            if r is None or not np.isfinite(r):
                return np.abs(h).sum(axis=0)
            matrix[i, j] = matrix[j, i] = r
    return np.sqrt(np.maximum(np.einsum("kc,kl,lc->c", h, matrix, h), 0.0))


def _paired(
    table: pd.DataFrame, scores: Mapping, own_key, reference_key, reference: str, level: float,
    spread: Mapping | None = None,
):  # fmt: skip
    """Adds to every row the paired per-seed difference of its scores (``scores[own_key(row)]``) from
    the reference's (``scores[reference_key(row)]``), with its t-interval, its t-test p-value and
    that p-value adjusted by Holm's method over every row of the table (NaN without a reference).
    ``spread``: per key the parameters' standard error on the seed-mean score; the difference's is
    the sum of both rows' (a bound whatever the correlation of the two fits), added in quadrature to
    the seeds' (NaN counts as 0: not propagated)."""
    names = [f"difference{suffix}_vs_{reference}" for suffix in ("", "_low", "_high", "_p")]
    table[names] = np.nan
    spread = spread or {}
    for index, row in table.iterrows():
        base = scores.get(reference_key(row))
        if base is not None:
            shift = scores[own_key(row)] - base
            extra = np.nansum([spread.get(own_key(row), 0.0), spread.get(reference_key(row), 0.0)])
            if own_key(row) == reference_key(row):
                extra = 0.0
            paired = t_interval(shift, level, extra)
            table.loc[index, names] = (paired.mean, paired.low, paired.high, t_test_p(shift, extra))
    # every difference of the table is read at once: Holm's adjustment over all of them
    table[f"difference_p_holm_vs_{reference}"] = adjusted_p(table[names[-1]], "holm")
    return table


def fabric_protocol_leaderboard(
    models: Mapping,
    mode_parameters: Mapping[str, Mapping[str, Mapping[str, float]]],
    curves: Mapping[str, ProtocolCurves],
    phi: float,
    n12_ss: float,
    *,
    seen: Mapping[tuple[str, str], set],
    reference: str,
    level: float = LEVEL,
    parameter_errors: Mapping[str, Mapping[str, Mapping[str, float]]] | None = None,
    parameter_correlations: Mapping[str, Mapping[str, Mapping[str, float]]] | None = None,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(leaderboard, predictions): one row per model, mode, protocol and component (the six and
    ``all``) with the mean square error's t-interval over seeds and the paired difference from
    ``reference`` in the steady mode; and the seed-mean predictions on every frame.
    ``mode_parameters[mode][model]`` are each model's parameters in each mode; ``seen[(model, mode)]``
    the seeds its fit saw (suspension_fabric.io.fit_provenance.seen_seeds): a row is ``held_out``
    only if none of its seeds is among them, and ``seeds_seen`` counts those that are.
    ``parameter_errors`` (the same layout: each parameter's standard error) and
    ``parameter_correlations`` (per mode and model, {"a,b": r}): the fits' uncertainty is
    propagated into every interval and p-value
    ([`parameter_spread`][suspension_fabric.evaluation.protocol_benchmark.parameter_spread], column
    ``parameter_se``; NaN where a fit has no error, whose rows carry the seeds' spread only)."""
    rows, predictions, scores, spread = [], [], {}, {}
    parameter_errors, parameter_correlations = parameter_errors or {}, parameter_correlations or {}
    for mode, by_model in mode_parameters.items():
        for key, fabric_model in models.items():
            if key not in by_model:
                continue
            for name, one in curves.items():
                predicted = model_protocol_predictions(fabric_model, by_model[key], phi, one)
                overlap = len(set(one.seeds.tolist()) & seen[(key, mode)])
                per_seed = fabric_protocol_scores(predicted, one, n12_ss)
                columns = {**{c: per_seed[:, k] for k, c in enumerate(COMPONENTS)}, ALL_COMPONENTS: per_seed.mean(1)}
                errors = parameter_errors.get(mode, {}).get(key)
                correlations = parameter_correlations.get(mode, {}).get(key)
                bounds = parameter_spread(fabric_model, by_model[key], errors, phi, one, n12_ss, correlations)
                for (component, values), bound in zip(columns.items(), bounds):
                    scores[(key, mode, name, component)] = values
                    spread[(key, mode, name, component)] = bound
                    interval = t_interval(values, level, 0.0 if np.isnan(bound) else bound)
                    rows.append(
                        {
                            "model": key,
                            "label": fabric_model.label,
                            "mode": mode,
                            "protocol": name,
                            "component": component,
                            "n_seeds": len(values),
                            "seeds_seen": overlap,
                            "held_out": overlap == 0,
                            "mse": interval.mean,
                            "mse_low": interval.low,
                            "mse_high": interval.high,
                            "parameter_se": bound,
                        }
                    )
                for index, (segment_grid, grid, tensors) in enumerate(zip(one.segment_strains, one.strains, predicted)):
                    frame = pd.DataFrame(
                        {
                            "model": key,
                            "mode": mode,
                            "protocol": name,
                            "segment": index,
                            "segment_strain": segment_grid,
                            "strain": grid,
                        }
                    )
                    for c, (i, j) in COMPONENTS.items():
                        frame[c] = tensors[:, i, j]
                    predictions.append(frame)
    table = _paired(
        pd.DataFrame(rows),
        scores,
        lambda row: (row["model"], row["mode"], row["protocol"], row["component"]),
        lambda row: (reference, "steady", row["protocol"], row["component"]),
        reference,
        level,
        spread,
    )
    return table, pd.concat(predictions, ignore_index=True)


def stress_protocol_leaderboard(
    relations: Mapping,
    parameters: pd.DataFrame,
    steady_fabric,
    steady: Mapping[str, float],
    curves: Mapping[str, ProtocolCurves],
    phi: float,
    *,
    seen: set,
    reference: str,
    level: float = LEVEL,
) -> pd.DataFrame:
    """One row per relation, protocol and quantity of `STRESS_SCORED`: the mean square
    error of the relation on each seed's fabric, in units of the steady eta_r, with its t-interval
    and the paired difference from ``reference``. ``parameters`` is the stress benchmark's fitted
    values (stress_relation_parameters.csv: the shape parameters of each relation's mode),
    ``steady_fabric`` the seed-mean steady fabric and ``steady`` the seed-mean steady
    lubrication_12, contact_12 and eta_r; ``seen`` the seeds the relations' parameters were fitted on
    (a row is ``held_out`` only if none of its seeds is among them)."""
    rows, scores = [], {}
    for key, relation in relations.items():
        mine = parameters[parameters["relation"] == key]
        if mine.empty:
            raise ValueError(f"stress relation {key}: not in the stress benchmark's parameters")
        mode = "global" if (mine["mode"] == "global").any() else "steady"
        chosen = mine[mine["mode"] == mode].set_index("parameter")["value"]
        params = {name: float(chosen[name]) for name in relation.names}
        coefficient = coefficients(relation, steady_fabric, steady["lubrication_12"], steady["contact_12"], params)
        for name, one in curves.items():
            overlap = len(set(one.seeds.tolist()) & set(seen))
            if one.stress is None:
                raise ValueError(f"protocol {name}: no stress tables to score the relations on")
            errors = {q: [] for q in STRESS_SCORED}
            for fabric, measured, keep in zip(one.fabric, one.stress, _scored_frames(one)):
                predicted = relation_stress(relation, fabric[:, keep], coefficient, params, phi)
                for q in STRESS_SCORED:
                    errors[q].append((predicted[q] - measured[q][:, keep]) / steady["eta_r"])
            for q in STRESS_SCORED:
                values = (np.concatenate(errors[q], axis=1) ** 2).mean(axis=1)
                scores[(key, name, q)] = values
                interval = t_interval(values, level)
                rows.append(
                    {
                        "relation": key,
                        "label": relation.label,
                        "mode": mode,
                        "protocol": name,
                        "quantity": q,
                        "n_seeds": len(values),
                        "seeds_seen": overlap,
                        "held_out": overlap == 0,
                        "mse": interval.mean,
                        "mse_low": interval.low,
                        "mse_high": interval.high,
                    }
                )
    return _paired(
        pd.DataFrame(rows),
        scores,
        lambda row: (row["relation"], row["protocol"], row["quantity"]),
        lambda row: (reference, row["protocol"], row["quantity"]),
        reference,
        level,
    )

"""The closures held against the measured fourth moment: is <nnnn> a function of <nn>?

Every model of the study writes <nnnn> in terms of <nn> (a closure,
[`suspension_fabric.models.closures`][suspension_fabric.models.closures]); the fabric tables record both moments
([`suspension_fabric.analysis.fabric`][suspension_fabric.analysis.fabric]), so each closure can be tested alone: given
the measured <nn> of a frame, how far is its <nnnn> from the measured one? Two measures per frame:

full
    ||C - M|| / ||M|| over all 81 entries (Frobenius norms), C the closure's <nnnn>, M the
    measured one;
drive
    ||Eh:(C - M)|| / ||Eh:M||, Eh = (e1 e2 + e2 e1)/2 the strain rate of the current shear: the
    contraction through which <nnnn> enters the fabric models (Lh:<nnnn> = Eh:<nnnn>, <nnnn>
    being symmetric) and the G-W stress relation.

Per seed, a measure's value on a protocol is its mean over the frames of a strain window (the
startup's steady window; the first W strain after each rotation). The seeds are the units: the
table gives the mean over seeds with its t-interval and the paired per-seed difference from the
paper's closure (linear) with its t-interval. Runs whose tables predate the fourth moment are
left out, and the table says how many seeds each value rests on.

The distribution of near-contact directions a closure implies: <nn> gives the spherical-harmonic
amplitudes of order 0 and 2 and <nnnn> those of order 4 (each Y_lm of order <= 4 is a quartic in
n on the unit sphere, [`amplitudes_from_moments`][suspension_fabric.evaluation.closure_tests.amplitudes_from_moments]);
the measured distribution has them up to order 6 (`suspension_fabric.analysis.fabric.HARMONIC_COLUMNS`).
"""

from __future__ import annotations

import functools
import itertools

import numpy as np
import pandas as pd

from suspension_fabric.analysis.fabric import FOURTH_MOMENT_COMPONENTS, HARMONIC_COLUMNS, real_spherical_harmonics
from suspension_fabric.analysis.seed_statistics import LEVEL, t_interval
from suspension_fabric.analysis.tables import fabric_tensors
from suspension_fabric.models.closures import CLOSURES

__all__ = [
    "MEASURES",
    "REFERENCE_CLOSURE",
    "fourth_moment_tensors",
    "frame_errors",
    "seed_window_errors",
    "closure_error_table",
    "amplitudes_from_moments",
    "LOW_ORDER_COLUMNS",
]

MEASURES = ("full", "drive")
#: The closure the others are compared with, per seed: the paper's.
REFERENCE_CLOSURE = "linear"
#: Amplitude columns a second and a fourth moment determine (orders 0, 2 and 4).
LOW_ORDER_COLUMNS = tuple(name for name in HARMONIC_COLUMNS if int(name[1]) <= 4)
_STRAIN_RATE = np.array([[0.0, 0.5, 0.0], [0.5, 0.0, 0.0], [0.0, 0.0, 0.0]])


def fourth_moment_tensors(table: pd.DataFrame) -> np.ndarray:
    """The symmetric <nnnn> (rows, 3, 3, 3, 3) from a fabric table's 15 components."""
    tensor = np.empty((len(table), 3, 3, 3, 3))
    for index in itertools.product(range(3), repeat=4):
        name = "n" + "".join(str(i + 1) for i in sorted(index))
        tensor[(slice(None), *index)] = table[name].to_numpy(dtype=float)
    return tensor


def _norm(tensor, axes) -> np.ndarray:
    return np.sqrt(np.sum(tensor**2, axis=axes))


def frame_errors(table: pd.DataFrame, closures: dict | None = None) -> pd.DataFrame:
    """Per frame of a fabric table with the fourth moment (frames without it are dropped) and per
    closure: the ``full`` and ``drive`` measures (module docstring). Columns: seed, theta, strain,
    closure, full, drive, and the table's other metadata columns it has (protocol, segment)."""
    closures = CLOSURES if closures is None else closures
    recorded = table.dropna(subset=list(FOURTH_MOMENT_COMPONENTS))
    second, measured = fabric_tensors(recorded), fourth_moment_tensors(recorded)
    keep = [c for c in ("seed", "theta", "strain", "protocol", "segment", "segment_strain") if c in recorded]
    blocks = []
    for name, closure in closures.items():
        difference = closure(second) - measured
        with np.errstate(divide="ignore", invalid="ignore"):
            full = _norm(difference, (1, 2, 3, 4)) / _norm(measured, (1, 2, 3, 4))
            drive = _norm(np.einsum("kl,fijkl->fij", _STRAIN_RATE, difference), (1, 2)) / _norm(
                np.einsum("kl,fijkl->fij", _STRAIN_RATE, measured), (1, 2)
            )
        blocks.append(recorded[keep].assign(closure=name, full=full, drive=drive))
    return pd.concat(blocks, ignore_index=True)


def seed_window_errors(errors: pd.DataFrame, window, group: str = "theta") -> pd.DataFrame:
    """Per seed, closure and ``group`` (the angle of a rotation, or any other run column), the mean
    of each measure over the frames with window[0] <= strain <= window[1]."""
    low, high = window
    inside = errors[errors["strain"].between(low - 1e-9, high + 1e-9)]
    return inside.groupby(["closure", group, "seed"], sort=False)[list(MEASURES)].mean().reset_index()


def closure_error_table(per_seed: pd.DataFrame, level: float = LEVEL, group: str = "theta") -> pd.DataFrame:
    """One row per closure, ``group`` value and measure: the mean over seeds with its t-interval
    and the paired per-seed difference from `REFERENCE_CLOSURE` (NaN for the reference itself);
    no rows (the same columns) when no run recorded the fourth moment."""
    rows = []
    reference = per_seed[per_seed["closure"] == REFERENCE_CLOSURE].set_index([group, "seed"])
    for (name, key), mine in per_seed.groupby(["closure", group], sort=False):
        mine = mine.set_index("seed")
        for measure in MEASURES:
            value = t_interval(mine[measure].to_numpy(), level)
            row = {
                "closure": name,
                group: key,
                "measure": measure,
                "n_seeds": value.n,
                "mean": value.mean,
                "low": value.low,
                "high": value.high,
            }
            if name != REFERENCE_CLOSURE:
                base = reference.loc[key][measure].reindex(mine.index)
                shift = t_interval((mine[measure] - base).to_numpy(), level)
                row.update(difference=shift.mean, difference_low=shift.low, difference_high=shift.high)
            rows.append(row)
    columns = ["closure", group, "measure", "n_seeds", "mean", "low", "high"]
    columns += ["difference", "difference_low", "difference_high"]
    return pd.DataFrame(rows, columns=columns).assign(level=level)


@functools.cache
def _quartic_map() -> np.ndarray:
    """M (15 amplitudes x 15 components): a_lm (orders 0, 2, 4) = M @ the 15 components of
    <nnnn>, from Y_lm(n) = sum over quartic monomials (each Y_lm of order <= 4, with n.n = 1,
    is a quartic form; the fit on 200 directions is exact to round-off, checked by a test)."""
    directions = np.random.default_rng(0).normal(size=(200, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    index = np.array(list(FOURTH_MOMENT_COMPONENTS.values()))
    monomials = np.prod(directions[:, index], axis=-1)  # the 15 distinct quartic monomials
    values = real_spherical_harmonics(directions)[:, : len(LOW_ORDER_COLUMNS)]
    solution, *_ = np.linalg.lstsq(monomials, values, rcond=None)
    return solution.T


def amplitudes_from_moments(fourth_components) -> np.ndarray:
    """a_lm of orders 0, 2 and 4 (`LOW_ORDER_COLUMNS`) of a direction distribution from the
    15 components of its <nnnn> (..., 15), in the order of FOURTH_MOMENT_COMPONENTS."""
    return np.asarray(fourth_components, dtype=float) @ _quartic_map().T

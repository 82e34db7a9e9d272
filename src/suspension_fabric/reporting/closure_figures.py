"""The closures against the measured fourth moment, drawn (rule closure_tests).

(a) Per rotation angle, each closure's ``drive`` error (suspension_fabric.evaluation.closure_tests)
over the first W strain after the rotation: seed mean with its t-interval over seeds. (b)-(e) The
distribution of near-contact directions a short strain after a rotation by 90 and by 180 degrees,
in the flow-gradient plane (e1, e2) and in the gradient-vorticity plane (e2, e3) of the current
flow: the measured one (spherical harmonics up to order 6, seed mean) and the one each closure
implies (orders 0 and 2 from the measured <nn>, order 4 from the closure's <nnnn>; the measured
one truncated at order 4 drawn dashed for comparison). Radius: f(n) per unit solid angle.
"""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd

from suspension_fabric.analysis.fabric import FOURTH_MOMENT_COMPONENTS, HARMONIC_COLUMNS, real_spherical_harmonics
from suspension_fabric.analysis.tables import fabric_tensors
from suspension_fabric.evaluation.closure_tests import LOW_ORDER_COLUMNS, amplitudes_from_moments
from suspension_fabric.models.closures import CLOSURES

from .figures import plt

__all__ = ["figure_closures", "PLANES"]

#: The planes drawn: name -> (first axis, second axis) of the frame of the current flow.
PLANES = {"flow-gradient (e1, e2)": (0, 1), "gradient-vorticity (e2, e3)": (1, 2)}
_COLORS = {"linear": "C1", "quadratic": "C2", "hybrid": "C4"}


def _circle(plane: tuple[int, int], n: int = 181) -> tuple[np.ndarray, np.ndarray]:
    angles = np.linspace(0.0, 2.0 * np.pi, n)
    directions = np.zeros((n, 3))
    directions[:, plane[0]], directions[:, plane[1]] = np.cos(angles), np.sin(angles)
    return angles, directions


def _closure_amplitudes(second: np.ndarray, closure) -> np.ndarray:
    """a_lm of orders 0, 2, 4 implied by a closure of the seed-mean <nn>: those of its fully
    symmetric part (a distribution sees only that; the quadratic closure is symmetric in pairs)."""
    raw = closure(second)
    closed = sum(np.transpose(raw, order) for order in itertools.permutations(range(4))) / 24.0
    return amplitudes_from_moments([closed[index] for index in FOURTH_MOMENT_COMPONENTS.values()])


def figure_closures(table: pd.DataFrame, snapshots: pd.DataFrame, window: float, level: float):
    """The figure of the module docstring from the closure-error table (measure ``drive``, one row
    per closure and angle) and ``snapshots``: per angle, the seed-mean fabric-table row (<nn>,
    amplitudes) at the strain drawn."""
    fig = plt.figure(figsize=(12, 8.5), constrained_layout=True)
    grid = fig.add_gridspec(2, 3)
    ax = fig.add_subplot(grid[:, 0])
    drive = table[table["measure"] == "drive"]
    for k, (name, rows) in enumerate(drive.groupby("closure", sort=False)):
        rows = rows.sort_values("theta")
        offset = (k - 1) * 1.5
        ax.errorbar(
            rows["theta"] + offset,
            rows["mean"],
            yerr=[rows["mean"] - rows["low"], rows["high"] - rows["mean"]],
            fmt="o-",
            ms=3,
            color=_COLORS.get(name),
            label=name,
        )
    ax.set_xlabel(r"rotation angle $\theta$ (deg)")
    ax.set_ylabel(r"$\|\hat E:(C - M)\| / \|\hat E:M\|$ over the first " + f"{window:g} strain")
    ax.set_title(f"(a) closure error, seed mean [{100 * level:g}% t-interval]", fontsize=10)
    ax.set_ylim(bottom=0.0)
    if drive.empty:
        ax.text(0.5, 0.5, "no run recorded\nthe fourth moment", ha="center", va="center", transform=ax.transAxes)
    else:
        ax.legend(fontsize=8)
    low_order = [HARMONIC_COLUMNS.index(name) for name in LOW_ORDER_COLUMNS]
    for row_index, theta in enumerate((90.0, 180.0)):
        snapshot = snapshots[np.isclose(snapshots["theta"], theta)]
        for column_index, (plane_name, plane) in enumerate(PLANES.items()):
            ax = fig.add_subplot(grid[row_index, 1 + column_index], projection="polar")
            letter = "bcde"[2 * row_index + column_index]
            if snapshot.empty:
                ax.set_title(f"({letter}) theta = {theta:g}: not simulated", fontsize=9)
                continue
            row = snapshot.iloc[0]
            angles, directions = _circle(plane)
            basis = real_spherical_harmonics(directions)
            measured = row[list(HARMONIC_COLUMNS)].to_numpy(dtype=float)
            ax.plot(angles, basis @ measured, color="k", lw=1.6, label="measured (l <= 6)")
            ax.plot(
                angles, basis[:, low_order] @ measured[low_order], color="k", lw=0.8, ls="--", label="measured, l <= 4"
            )
            second = fabric_tensors(row)
            for name, closure in CLOSURES.items():
                amplitudes = _closure_amplitudes(second, closure)
                ax.plot(angles, basis[:, low_order] @ amplitudes, color=_COLORS.get(name), lw=1.0, label=name)
            ax.set_title(f"({letter}) theta = {theta:g}, strain {row['strain']:.2g} after it: {plane_name}", fontsize=9)
            ax.tick_params(labelsize=7)
            if row_index == 0 and column_index == 1:
                ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.1))
    return fig

"""The flow-curve figure (suspension_fabric.evaluation.flow_curve): the relative viscosity, the frictional
fraction of the contacts with the Wyart-Cates form of the fitted onset stress, and the contact number
against sigma / sigma_0, one line per (phi, mu); error bars are the table's t-intervals over seeds."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .figures import plt

__all__ = ["figure_flow_curve"]


def _interval(rows: pd.DataFrame, column: str) -> np.ndarray:
    return np.vstack([rows[column] - rows[f"{column}_low"], rows[f"{column}_high"] - rows[column]])


def figure_flow_curve(table: pd.DataFrame, onsets: pd.DataFrame, level: float):
    """Three panels against sigma / sigma_0 (log): eta_r (log), the frictional fraction with
    exp(-sigma*/sigma) at each curve's fitted sigma*, and Z_touching."""
    with plt.rc_context({"font.size": 11}):
        return _draw(table, onsets, level)


def _draw(table: pd.DataFrame, onsets: pd.DataFrame, level: float):
    fig, axes = plt.subplots(1, 3, figsize=(10.0, 3.6), constrained_layout=True)
    panels = (
        ("eta_r", r"$\eta_r$"),
        ("frictional_fraction", "frictional fraction $f$"),
        ("Z_touching", "contacts per particle $Z_c$"),
    )
    for k, ((phi, mu), rows) in enumerate(table.groupby(["phi", "mu"])):
        rows = rows.sort_values("sigma")
        color = f"C{k}"
        xerr = _interval(rows, "sigma")
        for ax, (column, _) in zip(axes, panels):
            ax.errorbar(
                rows["sigma"],
                rows[column],
                xerr=xerr,
                yerr=_interval(rows, column),
                color=color,
                marker="o",
                ms=5,
                capsize=2,
                lw=1,
                label=rf"$\phi$ = {phi:g}, $\mu$ = {mu:g}",
            )
        onset = onsets[(onsets["phi"] == phi) & (onsets["mu"] == mu)]
        if len(onset) and np.isfinite(onset["sigma_star"].iloc[0]):
            star = float(onset["sigma_star"].iloc[0])
            sigma = np.geomspace(rows["sigma"].min(), rows["sigma"].max(), 200)
            axes[1].plot(
                sigma,
                np.exp(-star / sigma),
                ":",
                color=color,
                lw=1.5,
                label=rf"$e^{{-\sigma^*/\sigma}}$, $\sigma^*/\sigma_0$ = {star:.3g}",
            )
    for ax, (_, label) in zip(axes, panels):
        ax.set_xscale("log")
        ax.set_xlabel(r"$\sigma / \sigma_0$, $\sigma_0 = F_{CL}/a^2$")
        ax.set_ylabel(label)
    axes[0].set_yscale("log")
    axes[0].legend(fontsize=9)
    axes[1].legend(fontsize=9, loc="upper left")
    axes[1].set_ylim(-0.03, 1.03)
    fig.suptitle(f"Steady shear under critical-load friction (mean over seeds, {level:.0%} t-intervals)", fontsize=11)
    return fig

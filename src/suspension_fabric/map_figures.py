"""Figures of the map over the state point (suspension_fabric.state_map): each quantity of the map
table against phi, one line per friction coefficient, error bars from the table (seed standard
errors, jackknife errors of the fits, t-intervals of the claims). Points that did not reach a
steady state are drawn with open markers; points not run are absent from the table's numbers.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .figures import plt, save_figure
from .state_map import bgp_viscosities

__all__ = ["figure_map_models", "figure_map_fabric", "figure_map_rheology", "figure_map_model_errors",
           "MAP_FIGURES"]

_FABRIC = {"n11": r"$\langle nn\rangle_{11}$", "n22": r"$\langle nn\rangle_{22}$",
           "n33": r"$\langle nn\rangle_{33}$", "n12": r"$\langle nn\rangle_{12}$"}


def _simulated(table: pd.DataFrame) -> pd.DataFrame:
    return table[table["steady"].isin(["steady", "drifting", "not resolved"])]


def _per_mu(ax, table: pd.DataFrame, column: str, error):
    """One errorbar line per mu; open markers where the point is not steady. ``error``: a
    column of symmetric errors, or a (low, high) pair of interval columns."""
    table = _simulated(table)
    for k, (mu, rows) in enumerate(table.groupby("mu")):
        rows = rows.sort_values("phi")
        color = f"C{k}"
        if isinstance(error, tuple):
            yerr = np.vstack([rows[column] - rows[error[0]], rows[error[1]] - rows[column]])
        else:
            yerr = rows[error].to_numpy()
        ax.errorbar(rows["phi"], rows[column], yerr=yerr, color=color, marker="none", capsize=2, lw=1,
                    label=f"$\\mu$ = {mu:g}")
        steady = rows["steady"] == "steady"
        ax.plot(rows["phi"][steady], rows[column][steady], "o", color=color, ms=5)
        ax.plot(rows["phi"][~steady], rows[column][~steady], "o", mfc="white", color=color, ms=5)


def _not_run_note(fig, table: pd.DataFrame) -> None:
    missing = table[~table["point"].isin(_simulated(table)["point"])]
    if len(missing):
        fig.text(0.01, 0.005, "not run: " + ", ".join(missing["point"]), fontsize=7, color="0.4")


def figure_map_models(table: pd.DataFrame):
    """G-W beta, modified beta, A and A/beta against phi (jackknife errors over seeds)."""
    fig, axes = plt.subplots(1, 4, figsize=(14, 3.3), constrained_layout=True)
    panels = (("gw_beta", r"G-W $\beta$"), ("modified_beta", r"modified $\beta$"), ("modified_A", "modified $A$"),
              ("modified_A_over_beta", r"modified $A/\beta$"))
    for ax, (column, label) in zip(axes, panels):
        error = "modified_A_over_beta_err" if column == "modified_A_over_beta" else f"{column}_err"
        _per_mu(ax, table, column, error)
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(label)
    axes[0].legend(fontsize=8)
    _not_run_note(fig, table)
    return fig


def figure_map_fabric(table: pd.DataFrame):
    """Steady <nn>_11, _22, _33, _12 and Z against phi (standard error over seeds)."""
    fig, axes = plt.subplots(1, 5, figsize=(15, 3.2), constrained_layout=True)
    for ax, (column, label) in zip(axes, [*_FABRIC.items(), ("Z", "$Z$")]):
        _per_mu(ax, table, column, f"{column}_sem")
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(label)
    axes[0].legend(fontsize=8)
    _not_run_note(fig, table)
    return fig


def figure_map_rheology(table: pd.DataFrame):
    """eta_r and Pi against phi (log scale) with the BGP (2011) law for frictional spheres."""
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    phi = np.linspace(max(0.3, table["phi"].min() - 0.02), min(0.575, table["phi"].max() + 0.02), 200)
    eta_bgp, pi_bgp = bgp_viscosities(phi)
    for ax, column, anchor, label in ((axes[0], "eta_r", eta_bgp, r"$\eta_r$"), (axes[1], "Pi", pi_bgp, r"$\Pi$")):
        _per_mu(ax, table, column, f"{column}_sem")
        ax.plot(phi, anchor, "k--", lw=1, label=r"BGP 2011, $\phi_m$ = 0.585")
        ax.set_yscale("log")
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(label + r" (units $\eta_f\dot\gamma$)")
    axes[0].legend(fontsize=8)
    _not_run_note(fig, table)
    return fig


def figure_map_model_errors(table: pd.DataFrame, level: float):
    """The paired model-error statistics (claims C3' and C4': G-W minus modified MSE with the
    effect size, > 0 where the modified model is better) against phi, with their t-intervals."""
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.4), constrained_layout=True)
    for ax, claim, label in ((axes[0], "C3'", r"$\langle nn\rangle'_{12}$"), (axes[1], "C4'", r"$\langle nn\rangle'_{23}$")):
        if f"{claim}_mean" not in table:
            ax.text(0.5, 0.5, f"{claim} not computed", ha="center", transform=ax.transAxes)
            continue
        _per_mu(ax, table, f"{claim}_mean", (f"{claim}_low", f"{claim}_high"))
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(f"{claim}: modified better on {label} (> 0)")
        ax.set_title(f"{level:.0%} t-intervals over seeds", fontsize=9)
    axes[0].legend(fontsize=8)
    _not_run_note(fig, table)
    return fig


#: figure name -> function of (map table, level)
MAP_FIGURES = {
    "map_models": lambda table, level: figure_map_models(table),
    "map_fabric": lambda table, level: figure_map_fabric(table),
    "map_rheology": lambda table, level: figure_map_rheology(table),
    "map_model_errors": figure_map_model_errors,
}


def save_map_figures(table: pd.DataFrame, level: float, folder) -> list:
    """Every map figure as <folder>/<name>.pdf and .png."""
    paths = []
    for name, make in MAP_FIGURES.items():
        paths += save_figure(make(table, level), f"{folder}/{name}")
    return paths

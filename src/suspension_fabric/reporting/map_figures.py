"""Figures of the map over the state point (suspension_fabric.evaluation.state_map): each quantity of the map
table against phi, one line per friction coefficient (drawn DODGE apart in phi), error bars from the table (seed
standard
errors, jackknife errors of the fits, t-intervals of the claims). Points that did not reach a
steady state are drawn with open markers; points not run are absent from the table's numbers.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from suspension_fabric.evaluation.state_map import bgp_viscosities, fitted_columns

from .figures import plt, save_figure

#: Parameter names as TeX in the panel labels.
_PARAMETER_TEX = {"beta": r"$\beta$", "A": "$A$", "A_over_beta": r"$A/\beta$"}

__all__ = ["figure_map_models", "figure_map_fabric", "figure_map_rheology", "figure_map_model_errors", "MAP_FIGURES"]

#: horizontal offset between the mu lines (in phi), so that their error bars stay apart
DODGE = 0.002
_FABRIC = {
    "n11": r"$\langle nn\rangle_{11}$",
    "n22": r"$\langle nn\rangle_{22}$",
    "n33": r"$\langle nn\rangle_{33}$",
    "n12": r"$\langle nn\rangle_{12}$",
}


def _simulated(table: pd.DataFrame) -> pd.DataFrame:
    return table[table["steady"].isin(["steady", "drifting", "not resolved"])]


def _per_mu(ax, table: pd.DataFrame, column: str, error):
    """One errorbar line per mu; open markers where the point is not steady. ``error``: a
    column of symmetric errors, or a (low, high) pair of interval columns."""
    table = _simulated(table)
    groups = list(table.groupby("mu"))
    for k, (mu, rows) in enumerate(groups):
        rows = rows.sort_values("phi").copy()
        rows["phi"] += DODGE * (k - (len(groups) - 1) / 2)  # side by side, not on top of each other
        color = f"C{k}"
        if isinstance(error, tuple):
            yerr = np.vstack([rows[column] - rows[error[0]], rows[error[1]] - rows[column]])
        else:
            yerr = rows[error].to_numpy()
        ax.errorbar(
            rows["phi"], rows[column], yerr=yerr, color=color, marker="none", capsize=2, lw=1, label=f"$\\mu$ = {mu:g}"
        )
        steady = rows["steady"] == "steady"
        ax.plot(rows["phi"][steady], rows[column][steady], "o", color=color, ms=5)
        ax.plot(rows["phi"][~steady], rows[column][~steady], "o", mfc="white", color=color, ms=5)


def _not_run_note(fig, table: pd.DataFrame) -> None:
    missing = table[~table["point"].isin(_simulated(table)["point"])]
    if len(missing):
        fig.text(0.01, 0.005, "not run: " + ", ".join(missing["point"]), fontsize=10, color="0.4")


#: the docs show a figure at most 868 px wide (figures.DOCS_COLUMN_PX): at most this many panels a
#: row, each PANEL_WIDTH inches, keeps 10 pt text at 13.7 px or more (digits 10 px tall)
MAX_COLUMNS = 3
PANEL_WIDTH = 2.9


def _row(table: pd.DataFrame, panels, height: float):
    """Panels, (column, error column, label) each, against phi with a line per mu; a grid of at most
    MAX_COLUMNS a row, ``height`` inches each row. Returns the figure and the used axes."""
    columns = min(len(panels), MAX_COLUMNS if len(panels) != 4 else 2)
    rows = -(-len(panels) // columns)
    fig, grid = plt.subplots(
        rows, columns, figsize=(max(PANEL_WIDTH * columns, 6.5), height * rows), constrained_layout=True, squeeze=False
    )
    axes = list(grid.ravel())
    for ax in axes[len(panels) :]:
        ax.set_visible(False)
    for ax, (column, error, label) in zip(axes, panels):
        _per_mu(ax, table, column, error)
        ax.set_xlabel(r"$\phi$")
        ax.set_ylabel(label)
    return fig, axes[: len(panels)]


def _finish(table: pd.DataFrame, fig, axes):
    # one legend for all panels, above them: inside a panel it covers points
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside upper center", ncol=len(labels), fontsize=10)
    _not_run_note(fig, table)
    return fig


def model_panels(table: pd.DataFrame) -> list[tuple[str, str, str]]:
    """(column, error column, label) of every fitted parameter of the compared models in the map
    table (state_map.fitted_columns), the model by its label."""
    return [
        (column, error, f"{model} {_PARAMETER_TEX.get(name, name)}")
        for model, name, column, error in fitted_columns(table)
    ]


def figure_map_models(table: pd.DataFrame):
    """The compared models' fitted parameters against phi (jackknife errors over seeds)."""
    panels = model_panels(table)
    return _finish(table, *_row(table, panels, 3.0))


def figure_map_fabric(table: pd.DataFrame):
    """Steady <nn>_11, _22, _33, _12 and Z against phi (standard error over seeds)."""
    panels = [(column, f"{column}_sem", label) for column, label in [*_FABRIC.items(), ("Z", "$Z$")]]
    return _finish(table, *_row(table, panels, 3.0))


def figure_map_rheology(table: pd.DataFrame):
    """eta_r and Pi against phi (log scale) with the BGP (2011) law for frictional spheres."""
    # eta_r is a ratio, dimensionless; Pi is a pressure, in units of eta_f gammadot
    panels = [
        ("eta_r", "eta_r_sem", r"$\eta_r$"),
        ("Pi", "Pi_sem", r"$\Pi$ (units $\eta_f\dot\gamma$)"),
    ]
    fig, axes = _row(table, panels, 3.6)
    phi = np.linspace(max(0.3, table["phi"].min() - 0.02), min(0.575, table["phi"].max() + 0.02), 200)
    for ax, anchor in zip(axes, bgp_viscosities(phi)):
        ax.plot(phi, anchor, "k--", lw=1, label=r"BGP 2011, $\phi_m$ = 0.585")
        ax.set_yscale("log")
    return _finish(table, fig, axes)


def figure_map_model_errors(table: pd.DataFrame, level: float):
    """The paired model-error statistics (claims C3' and C4': G-W minus modified MSE with the
    effect size, > 0 where the modified model is better) against phi, with their t-intervals."""
    claims = {"C3'": r"$\langle nn\rangle'_{12}$", "C4'": r"$\langle nn\rangle'_{23}$"}
    missing = [claim for claim in claims if f"{claim}_mean" not in table]
    if missing:
        raise ValueError(f"the map table lacks the statistics of claim(s) {missing}")
    panels = [
        (f"{claim}_mean", (f"{claim}_low", f"{claim}_high"), f"{claim}: modified better on {label} (> 0)")
        for claim, label in claims.items()
    ]
    fig, axes = _row(table, panels, 3.6)
    for ax in axes:
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_title(f"{level:.0%} t-intervals over seeds", fontsize=9)
    return _finish(table, fig, axes)


#: figure name -> function of (map table, level)
MAP_FIGURES = {
    "map_models": lambda table, level: figure_map_models(table),
    "map_fabric": lambda table, level: figure_map_fabric(table),
    "map_rheology": lambda table, level: figure_map_rheology(table),
    "map_model_errors": figure_map_model_errors,
}


def save_map_figures(table: pd.DataFrame, level: float, folder) -> list:
    """Every map figure as ``<folder>/<name>.pdf`` and .png."""
    paths = []
    for name, make in MAP_FIGURES.items():
        paths += save_figure(make(table, level), f"{folder}/{name}")
    return paths

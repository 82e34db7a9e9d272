"""The flow-curve figure (suspension_fabric.evaluation.flow_curve): the stress against the imposed rate,
then the relative viscosity, the frictional fraction of the contacts with the Wyart-Cates form of the
fitted onset stress, and the contact number against sigma / sigma_0, one line per (phi, mu); error
bars are the table's t-intervals over seeds."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .figures import plt

__all__ = ["figure_flow_curve"]


def _interval(rows: pd.DataFrame, column: str) -> np.ndarray:
    return np.vstack([rows[column] - rows[f"{column}_low"], rows[f"{column}_high"] - rows[column]])


def figure_flow_curve(table: pd.DataFrame, onsets: pd.DataFrame, level: float):
    """Four panels: sigma / sigma_0 against gammadot / gammadot_0 (log-log), then against sigma / sigma_0
    (log) eta_r (log), the frictional fraction with exp(-sigma*/sigma) at each curve's fitted sigma*,
    and Z_touching."""
    with plt.rc_context({"font.size": 11}):
        return _draw(table, onsets, level)


def _draw(table: pd.DataFrame, onsets: pd.DataFrame, level: float):
    fig, grid = plt.subplots(2, 2, figsize=(9.0, 7.4), constrained_layout=True)
    rate_axis, axes = grid[0, 0], (grid[0, 1], grid[1, 0], grid[1, 1])
    panels = (
        ("eta_r", r"$\eta_r$"),
        ("frictional_fraction", "frictional fraction $f$"),
        ("Z_touching", "contacts per particle $Z_c$"),
    )
    onset_lines = []
    for k, ((phi, mu, control), rows) in enumerate(table.groupby(["phi", "mu", "control"])):
        rows = rows.sort_values("sigma")
        color = f"C{k}"
        xerr = _interval(rows, "sigma")
        label = rf"$\phi$ = {phi:g}, $\mu$ = {mu:g}" + ("" if control == "rate" else ", stress imposed")
        style = {"color": color, "marker": "o" if control == "rate" else "s", "ms": 5, "capsize": 2, "lw": 1}
        rate_axis.errorbar(
            rows["rate_ratio"], rows["sigma"], xerr=_interval(rows, "rate_ratio"), yerr=xerr, label=label, **style
        )
        for ax, (column, _) in zip(axes, panels):
            ax.errorbar(rows["sigma"], rows[column], xerr=xerr, yerr=_interval(rows, column), label=label, **style)
        onset = onsets[(onsets["phi"] == phi) & (onsets["mu"] == mu) & (onsets["control"] == control)]
        if len(onset) and np.isfinite(onset["sigma_star"].iloc[0]):
            star = float(onset["sigma_star"].iloc[0])
            sigma = np.geomspace(rows["sigma"].min(), rows["sigma"].max(), 200)
            (line,) = axes[1].plot(
                sigma,
                np.exp(-star / sigma),
                ":",
                color=color,
                lw=1.5,
                label=rf"$\phi$ = {phi:g}: $\sigma^*/\sigma_0$ = {star:.3g}",
            )
            onset_lines.append(line)
    for ax, (_, label) in zip(axes, panels):
        ax.set_xscale("log")
        ax.set_xlabel(r"$\sigma / \sigma_0$, $\sigma_0 = F_{CL}/a^2$")
        ax.set_ylabel(label)
    axes[0].set_yscale("log")
    rate_axis.set_xscale("log")
    rate_axis.set_yscale("log")
    rate_axis.set_xlabel(r"$\dot\gamma / \dot\gamma_0$, $\dot\gamma_0 = F_{CL} / (6\pi\eta_f a^2)$")
    rate_axis.set_ylabel(r"$\sigma / \sigma_0$")
    rate_axis.legend(fontsize=10.5, loc="upper left")
    if onset_lines:  # only the fitted forms: the markers' legend is the first panel's
        # centre right, empty (f is near 1 at large stress): upper left covered the points at sigma/sigma_0 ~ 1
        axes[1].legend(
            handles=onset_lines,
            fontsize=10.5,
            loc="center right",
            title=r"$f = e^{-\sigma^*/\sigma}$",
            title_fontsize=10.5,
        )
    axes[1].set_ylim(-0.03, 1.03)
    fig.suptitle(f"Steady shear under critical-load friction (mean over seeds, {level:.0%} t-intervals)", fontsize=11)
    return fig

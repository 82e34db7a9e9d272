"""The response to a change of flow direction at each steady state of a campaign: eta_r relative to
the theta = 0 control, the frictional fraction and <nn>_12 against the strain since the change, one
line per state point and a column per angle; bands are t-intervals over seeds
(suspension_fabric.evaluation.direction_response)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import t_interval

from .figures import plt

__all__ = ["figure_direction_response"]

_ROWS = (
    ("eta_r", r"$\eta_r(\theta) / \langle\eta_r(0)\rangle$"),
    ("frictional_fraction", r"frictional fraction $f$"),
    ("n12", r"$\langle nn \rangle_{12}$"),
)


def _traces(stress: pd.DataFrame, fabric: pd.DataFrame) -> pd.DataFrame:
    """Per frame the three quantities, eta_r over the same seed's mean eta_r at theta = 0."""
    frames = stress.assign(theta=stress["theta"].astype(float)).copy()
    frames["frictional_fraction"] = frames["Z_frictional"] / frames["Z_touching"]
    control = frames[frames["theta"] == 0.0].groupby("seed")["eta_r"].mean()
    frames["eta_r"] = frames["eta_r"] / frames["seed"].map(control)
    fabric = fabric.assign(theta=fabric["theta"].astype(float))
    return frames.merge(fabric[["seed", "theta", "strain", "n12"]], on=["seed", "theta", "strain"], how="inner")


def figure_direction_response(points: dict[str, dict], level: float):
    """``points``: label -> {"stress": its stress rotation table, "fabric": its fabric rotation table}.
    Columns: the angles other than 0; rows: eta_r relative, f, <nn>_12; the theta = 0 control dashed."""
    traces = {label: _traces(point["stress"], point["fabric"]) for label, point in points.items()}
    angles = sorted({theta for frame in traces.values() for theta in frame["theta"].unique() if theta != 0.0})
    with plt.rc_context({"font.size": 11}):
        fig, axes = plt.subplots(
            len(_ROWS),
            len(angles),
            figsize=(4.4 * len(angles), 8.4),
            sharex=True,
            squeeze=False,
            constrained_layout=True,
        )
        for k, (label, frame) in enumerate(traces.items()):
            color = f"C{k}"
            for column, theta in enumerate(angles):
                for row, (quantity, _) in enumerate(_ROWS):
                    ax = axes[row, column]
                    for angle, style in ((theta, "-"), (0.0, "--")):
                        runs = frame[frame["theta"] == angle].pivot(index="strain", columns="seed", values=quantity)
                        intervals = [t_interval(values, level) for values in runs.to_numpy()]
                        mean = np.array([i.mean for i in intervals])
                        ax.plot(runs.index, mean, style, color=color, lw=1.4 if angle else 1.0,
                                label=label if angle and row == 0 and column == 0 else None)  # fmt: skip
                        if angle:
                            low = np.array([i.low for i in intervals])
                            high = np.array([i.high for i in intervals])
                            ax.fill_between(runs.index, low, high, color=color, alpha=0.2, lw=0)
        for column, theta in enumerate(angles):
            axes[0, column].set_title(rf"$\theta$ = {theta:g}°")
            axes[-1, column].set_xlabel("strain since the change")
        for row, (_, label) in enumerate(_ROWS):
            axes[row, 0].set_ylabel(label)
        # outside, under the panels: inside it covered the orange band
        fig.legend(loc="outside lower center", ncol=len(traces), fontsize=11, title="dashed: θ = 0", title_fontsize=11)
        fig.suptitle(f"Response to a change of flow direction (mean over seeds, {level:.0%} t-intervals)", fontsize=11)
    return fig

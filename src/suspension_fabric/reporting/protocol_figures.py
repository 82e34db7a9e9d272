"""A figure per protocol: the fabric and the viscosity along the flow history, simulation against the
models.

Panels: the six components of <nn> and the near-contact coordination number Z, in the frame of the
current flow, and the relative viscosity eta_r, against the strain since rest. The simulation is
drawn as its seed mean with a band of one standard error over seeds, each fabric model (its
``steady`` fit: parameters from the startup's steady state only, so every protocol is a
prediction) as a line, segment by segment: a change of flow angle re-expresses the fabric in the
new flow's frame, so the curves jump there and are not joined. Dotted lines mark the segment starts,
labelled with the flow angle (and the turning rate of a rotary segment).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from suspension_fabric.io.protocols import Protocol  # noqa: E402

__all__ = ["figure_protocol", "seed_count", "PANELS"]

#: (column, axis label) of each panel, fabric first.
PANELS = (
    ("n11", r"$\langle nn\rangle_{11}$"),
    ("n22", r"$\langle nn\rangle_{22}$"),
    ("n33", r"$\langle nn\rangle_{33}$"),
    ("Z", r"$Z$"),
    ("n12", r"$\langle nn\rangle_{12}$"),
    ("n13", r"$\langle nn\rangle_{13}$"),
    ("n23", r"$\langle nn\rangle_{23}$"),
    ("eta_r", r"$\eta_r$"),
)
_MODEL_STYLES = ("-", "--", "-.", ":")


def _segment_label(segment) -> str:
    turning = f", {segment.turning_deg_per_strain:g}°/strain" if segment.turning_deg_per_strain else ""
    return f"{segment.flow_angle_deg:g}°{turning}"


def figure_protocol(
    protocol: Protocol,
    fabric: pd.DataFrame,
    stress: pd.DataFrame | None,
    predictions: pd.DataFrame,
    model_labels: dict,
    n_seeds: int,
):
    """The figure of one protocol from the seed aggregates (protocol_aggregate.csv,
    stress_protocol_aggregate.csv) and the models' predictions (protocol_predictions.csv,
    ``steady`` mode); ``model_labels`` {model key: label}."""
    mine = fabric[fabric["protocol"] == protocol.name]
    if mine.empty:
        raise ValueError(f"protocol {protocol.name}: not in the fabric aggregate")
    stressed = None if stress is None else stress[stress["protocol"] == protocol.name]
    predicted = predictions[(predictions["protocol"] == protocol.name) & (predictions["mode"] == "steady")]
    fig, axes = plt.subplots(2, 4, figsize=(15, 6.5), sharex=True, constrained_layout=True)
    for ax, (column, label) in zip(axes.ravel(), PANELS):
        source = stressed if column == "eta_r" else mine
        if source is None or source.empty:
            ax.set_visible(False)
            continue
        for index in range(len(protocol.segments)):
            rows = source[source["segment"] == index].sort_values("strain")
            mean, sem = rows[f"{column}_mean"].to_numpy(), rows[f"{column}_sem"].fillna(0.0).to_numpy()
            ax.fill_between(rows["strain"], mean - sem, mean + sem, color="0.75", lw=0)
            ax.plot(rows["strain"], mean, color="k", lw=1.0, label="simulation" if index == 0 else None)
            if column in ("eta_r", "Z"):
                continue
            for style, (key, text) in zip(_MODEL_STYLES, model_labels.items()):
                line = predicted[(predicted["model"] == key) & (predicted["segment"] == index)].sort_values("strain")
                ax.plot(
                    line["strain"],
                    line[column],
                    style,
                    lw=1.3,
                    color=f"C{list(model_labels).index(key)}",
                    label=text if index == 0 else None,
                )
        for start in protocol.start_strains[1:]:
            ax.axvline(start, color="0.5", lw=0.6, ls=":")
        ax.set_ylabel(label)
        ax.axhline(0.0, color="0.85", lw=0.5)
    top = axes[0, 0]
    for start, segment in zip(protocol.start_strains, protocol.segments):
        top.annotate(_segment_label(segment), (start, 1.0), xycoords=("data", "axes fraction"), fontsize=7, va="bottom")
    for ax in axes[1]:
        ax.set_xlabel(r"strain since rest $\gamma$")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=8)
    n = int(mine["N"].iloc[0])
    fig.suptitle(
        f"Protocol {protocol.name}: N = {n}, {n_seeds} seeds (band: one standard error over seeds); "
        "components in the frame of the current flow; models fitted on the startup's steady state",
        fontsize=9,
    )
    return fig


def seed_count(aggregate: pd.DataFrame) -> int:
    """The number of seeds behind an aggregate."""
    return int(np.max(aggregate["n_seeds"]))

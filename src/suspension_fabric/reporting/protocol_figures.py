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
#: a line style per model, cycled: every model the protocol tables score is drawn (a shorter list
#: once left the fifth, the sparse model, out of the figure)
_MODEL_STYLES = ("-", "--", "-.", ":", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)))


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
    # four rows of two, 8 in wide: the docs show it 868 px wide, where 10 pt is 15 px
    fig, axes = plt.subplots(4, 2, figsize=(8, 10.5), sharex=True, constrained_layout=True)
    for ax, (column, label) in zip(_reading_order(axes), PANELS):
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
            for k, (key, text) in enumerate(model_labels.items()):
                line = predicted[(predicted["model"] == key) & (predicted["segment"] == index)].sort_values("strain")
                ax.plot(
                    line["strain"],
                    line[column],
                    linestyle=_MODEL_STYLES[k % len(_MODEL_STYLES)],
                    lw=1.3,
                    color=f"C{k}",
                    label=text if index == 0 else None,
                )
        for start in protocol.start_strains[1:]:
            ax.axvline(start, color="0.5", lw=0.6, ls=":")
        ax.set_ylabel(label)
        ax.axhline(0.0, color="0.85", lw=0.5)
    _label_segments(axes[0, 0], protocol, float(mine["strain"].max()))
    for ax in axes[-1]:
        ax.set_xlabel(r"strain since rest $\gamma$")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=3, fontsize=10)
    n = int(mine["N"].iloc[0])
    fig.suptitle(
        f"Protocol {protocol.name}: N = {n}, {n_seeds} seeds (band: one standard error over seeds)\n"
        "components in the frame of the current flow; models fitted on the startup's steady state",
        fontsize=10,
    )
    return fig


def _label_segments(ax, protocol: Protocol, end: float, rows: int = 2) -> None:
    """The flow angle over each segment start, above the panel, in the lowest of ``rows`` rows where
    it does not run into the label before it; a label that fits no row is left out (an oscillation's
    twenty segments)."""
    span = end - min(protocol.start_strains) or 1.0
    row_ends = [-np.inf] * rows  # axes fraction where each row's last label ends
    for start, segment in zip(protocol.start_strains, protocol.segments):
        text = _segment_label(segment)
        x = (start - min(protocol.start_strains)) / span
        for row, row_end in enumerate(row_ends):
            if x >= row_end:
                ax.annotate(
                    text,
                    (start, 1.0),
                    xycoords=("data", "axes fraction"),
                    xytext=(0, 1 + 12 * row),
                    textcoords="offset points",
                    fontsize=10,
                    va="bottom",
                )
                row_ends[row] = x + 0.027 * len(text) + 0.02  # 10 pt characters in a panel about 3.3 in wide
                break


def _reading_order(axes) -> list:
    """The panels column by column: the first column holds PANELS' first four (n11, n22, n33, Z),
    the second the rest."""
    return list(axes.T.ravel())


def seed_count(aggregate: pd.DataFrame) -> int:
    """The number of seeds behind an aggregate."""
    return int(np.max(aggregate["n_seeds"]))

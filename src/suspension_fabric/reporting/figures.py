"""The paper's figures from the study's tables (matplotlib, Agg backend).

Figure 1 ([`figure_startup`][suspension_fabric.reporting.figures.figure_startup]): fabric components versus strain in
startup shear; simulation seed means with standard errors (symbols) against (a) G-W and
(b) the modified model (lines), fitted parameters in the legends.

Figure 2 ([`figure_rotation`][suspension_fabric.reporting.figures.figure_rotation]): polar maps, radius = post-rotation
strain, angle = rotation angle theta, colour = <nn>'_12/<nn>_12^ss and <nn>'_23/<nn>_12^ss,
rows simulation / G-W / modified, one colour scale per component (column). When
only theta >= 0 was simulated the negative half is filled by the exact symmetry
of shear rotation (12 even, 23 odd in theta) and the figure says so.

Figure 3 ([`figure_stress_startup`][suspension_fabric.reporting.figures.figure_stress_startup]): startup shear, (a) the
relative viscosity eta_r and its contact and lubrication parts, (b) N1 and N2, simulation seed means with standard
errors against the G-W stress relation evaluated on each fabric source.

Figure 4 ([`figure_stress_rotation`][suspension_fabric.reporting.figures.figure_stress_rotation]): after a rotation,
polar maps of sigma'_12 and sigma'_23 over sigma_12^ss (simulation; the relation on the simulated fabric), and per
angle the minimum of eta_r / eta_r^ss and the strain at which it recovers to within 10%.
"""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from suspension_fabric.analysis.seed_statistics import t_interval  # noqa: E402
from suspension_fabric.evaluation.model_vs_simulation import model_labels  # noqa: E402

__all__ = [
    "figure_startup",
    "figure_rotation",
    "polar_cell_errors",
    "figure_stress_startup",
    "figure_stress_rotation",
    "figure_claims",
    "save_figure",
    "smallest_font_pt",
    "displayed_font_px",
    "DOCS_COLUMN_PX",
    "mirror_negative_angles",
]

_STARTUP_COMPONENTS = {"n11": "C0", "n22": "C1", "n33": "C2", "n12": "C3"}
_LABELS = {
    "n11": r"$\langle nn\rangle_{11}$",
    "n22": r"$\langle nn\rangle_{22}$",
    "n33": r"$\langle nn\rangle_{33}$",
    "n12": r"$\langle nn\rangle_{12}$",
}
# Parity of each component under theta -> -theta (mirror e3 -> -e3).
_PARITY = {"n11": 1, "n22": 1, "n33": 1, "n12": 1, "n13": -1, "n23": -1, "Z": 1}


#: Width in CSS px of the docs' text column at a 1400 px window (docs/stylesheets/tables.css): a PNG
#: wider than this is shown scaled down to it.
DOCS_COLUMN_PX = 868
#: PNG text key holding the smallest font drawn, in image px (tests/docs/test_figure_legibility.py).
SMALLEST_FONT_KEY = "Smallest font px"
_DPI = 200


def smallest_font_pt(fig) -> float:
    """The smallest font size (points) of the visible, non-empty texts in ``fig``: ticks, labels,
    legends, titles, annotations."""
    sizes = [
        text.get_fontsize()
        for text in fig.findobj(matplotlib.text.Text)
        if text.get_visible() and text.get_text().strip() and (text.axes is None or text.axes.get_visible())
    ]
    return min(sizes) if sizes else float("inf")


def displayed_font_px(font_pt: float, width_in: float, column_px: int = DOCS_COLUMN_PX) -> float:
    """Height in CSS px of a ``font_pt`` font in a figure ``width_in`` inches wide saved at the
    figures' dpi, as the docs show it: at most ``column_px`` wide."""
    image_px = width_in * _DPI
    return font_pt * _DPI / 72 * min(image_px, column_px) / image_px


def save_figure(fig, stem: str | os.PathLike) -> list[Path]:
    """Save ``fig`` as ``<stem>.pdf`` and ``<stem>.png`` (200 dpi, and the PDF's rasterized parts); returns the
    paths. The PNG records its smallest font in image px (text chunk ``SMALLEST_FONT_KEY``)."""
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [stem.with_suffix(".pdf"), stem.with_suffix(".png")]
    fig.savefig(paths[0], dpi=_DPI, metadata={"CreationDate": None})  # no date: the same inputs, the same bytes
    # the PDF's layout holds for the PNG: without this the second save lays the figure out again,
    # measuring every label once more
    fig.set_layout_engine("none")
    smallest = smallest_font_pt(fig) * _DPI / 72
    fig.savefig(paths[1], dpi=_DPI, metadata={SMALLEST_FONT_KEY: f"{smallest:.2f}"})
    plt.close(fig)
    return paths


_GREEK = {"alpha", "beta", "gamma", "delta", "kappa", "lambda", "mu", "nu", "tau", "xi", "zeta", "eta"}


def _parameter_text(name: str) -> str:
    """A parameter name as TeX: a Greek head gets its backslash, the rest is a subscript (beta_e -> β_e)."""
    head, _, tail = name.partition("_")
    head = f"\\{head}" if head in _GREEK else head
    return f"${head}_{{{tail}}}$" if tail else f"${head}$"


def _legend_label(key: str, fits: dict) -> str:
    """The model's short name and its fitted parameters (fits.json's ``models``)."""
    entry = fits["models"][key]
    values = ", ".join(f"{_parameter_text(name)} = {value:.3g}" for name, value in entry["parameters"].items())
    return f"{entry['label']}, {values}"


def figure_startup(simulation: pd.DataFrame, predictions: pd.DataFrame, fits: dict, max_markers: int = 40):
    """Paper Fig. 1 from the startup seed aggregate and the model predictions."""
    sim = simulation[np.isclose(simulation["theta"], 0.0)].sort_values("strain")
    stride = max(1, -(-len(sim) // max_markers))  # ceil: at most max_markers markers
    shown = sim.iloc[::stride]
    keys = list(dict.fromkeys(predictions["model"]))
    # two panels a row, 4 in each: the docs show it 868 px wide (DOCS_COLUMN_PX), a row of five was unreadable
    columns = min(len(keys), 2)
    rows = -(-len(keys) // columns)
    fig, grid = plt.subplots(
        rows, columns, figsize=(4.0 * columns, 5.0 * rows), sharey=True, constrained_layout=True, squeeze=False
    )
    axes = list(grid.ravel())
    for ax in axes[len(keys) :]:
        ax.set_visible(False)
    for ax, (key, title) in zip(axes, model_labels(fits, keys).items()):
        pred = predictions[(predictions["model"] == key) & (predictions["protocol"] == "startup")]
        for name, colour in _STARTUP_COMPONENTS.items():
            ax.errorbar(
                shown["strain"],
                shown[f"{name}_mean"],
                yerr=shown[f"{name}_sem"].fillna(0.0),
                fmt="o",
                ms=3.5,
                color=colour,
                mfc="none",
                label=f"{_LABELS[name]} simulation",
            )
            ax.plot(pred["strain"], pred[name], "-", color=colour, lw=1.5)
        ax.plot([], [], "k-", label=_legend_label(key, fits))
        ax.axhline(0.0, color="0.7", lw=0.5)
        ax.set_xlabel(r"strain $\gamma$")
        ax.set_title(f"({'abcdefgh'[keys.index(key)]}) {title}")
        # under the panel, off the data; 9.5 pt: 14.3 px in the docs' column (DOCS_COLUMN_PX)
        ax.legend(fontsize=9.5, loc="upper center", bbox_to_anchor=(0.5, -0.15))
    for row in grid:
        row[0].set_ylabel(r"$\langle nn\rangle_{ij}$")
    n_seeds = int(sim["n_seeds"].iloc[0]) if "n_seeds" in sim else 0
    fig.suptitle(
        f"Startup shear, N = {int(sim['N'].iloc[0])}, phi = {fits['phi']:.3g}, "
        f"{n_seeds} seeds (error bars: standard error over seeds)",
        fontsize=10,
        wrap=True,
    )
    return fig


def mirror_negative_angles(table: pd.DataFrame, value_columns) -> tuple[pd.DataFrame, bool]:
    """Add theta -> -theta copies by parity when only theta in [0, 180] is present.

    Returns (table, mirrored). Components follow ``_PARITY`` (12 even, 23 odd);
    theta = 0 is not duplicated; theta = 180 is copied to -180.
    """
    thetas = table["theta"].to_numpy()
    if np.any(thetas < 0):
        return table, False
    # theta = 180 is the same rotation as -180; copy it so the map closes at the back.
    copy = table[table["theta"] > 0].copy()
    copy["theta"] = -copy["theta"]
    for column in value_columns:
        copy[column] = _parity(column) * copy[column]
    return pd.concat([table, copy], ignore_index=True), True


def _parity(column: str) -> int:
    """+1 or -1 under theta -> -theta (e3 -> -e3): odd for a component with one index 3
    (fabric n13, n23; stress <part>_13, <part>_23), even otherwise (eta_r, N1, N2, Pi)."""
    base = column.split("_")[0]
    if base in _PARITY:
        return _PARITY[base]
    digits = [part for part in column.split("_") if len(part) == 2 and part.isdigit()]
    return -1 if digits and digits[0].count("3") == 1 else 1


def _edges(centres):
    centres = np.asarray(centres, dtype=float)
    if len(centres) == 1:
        return np.array([centres[0] - 0.5, centres[0] + 0.5])
    mids = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate([[centres[0] - (mids[0] - centres[0])], mids, [centres[-1] + (centres[-1] - mids[-1])]])


def _polar_grid(table: pd.DataFrame, column: str):
    """(theta_edges_rad, strain_edges, values[strain, theta]) from a tidy table."""
    thetas = np.sort(table["theta"].unique())
    strains = np.sort(table[table["theta"] == thetas[0]]["strain"].unique())
    grid = np.full((len(strains), len(thetas)), np.nan)
    for k, theta in enumerate(thetas):
        rows = table[table["theta"] == theta].sort_values("strain")
        if len(rows) != len(strains):
            raise ValueError(f"theta={theta}: {len(rows)} strain points, expected {len(strains)}")
        grid[:, k] = rows[column].to_numpy()
    theta_edges = np.clip(_edges(thetas), -180.0, 180.0)
    strain_edges = np.clip(_edges(strains), 0.0, None)
    # Split each angular cell into sub-cells of <= 2 degrees so wedges are drawn as arcs.
    fine_edges, owner = [theta_edges[0]], []
    for k, (lo, hi) in enumerate(zip(theta_edges[:-1], theta_edges[1:])):
        n_sub = max(1, int(np.ceil((hi - lo) / 2.0)))
        fine_edges.extend(np.linspace(lo, hi, n_sub + 1)[1:])
        owner.extend([k] * n_sub)
    return np.radians(fine_edges), strain_edges, grid[:, owner]


def polar_cell_errors(simulation: pd.DataFrame, n12_ss: float) -> dict[str, float]:
    """Largest seed-mean standard error over the cells (angle, strain frame) of the polar maps,
    relative to |<nn>_12^ss|, for <nn>'_12 and <nn>'_23 (the figure's patchwork criterion)."""
    return {c: float(np.nanmax(simulation[f"{c}_sem"]) / abs(n12_ss)) for c in ("n12", "n23")}


def figure_rotation(simulation: pd.DataFrame, predictions: pd.DataFrame, fits: dict):
    """Paper Fig. 2 from the rotation seed aggregate (theta in degrees) and model predictions."""
    n12_ss = fits["targets"]["n12"]["mean"]
    sim, mirrored = mirror_negative_angles(simulation, ["n12_mean", "n23_mean"])
    rows = [("simulation", sim.rename(columns={"n12_mean": "n12", "n23_mean": "n23"}))]
    for key, name in model_labels(fits, dict.fromkeys(predictions["model"])).items():
        pred = predictions[(predictions["model"] == key) & (predictions["protocol"] == "rotation")]
        pred, _ = mirror_negative_angles(pred, ["n12", "n23"])
        rows.append((name, pred))
    columns = {
        "n12": r"$\langle nn\rangle'_{12}/\langle nn\rangle_{12}^{ss}$",
        "n23": r"$\langle nn\rangle'_{23}/\langle nn\rangle_{12}^{ss}$",
    }
    grids = {(r, c): _polar_grid(table, c) for r, (_, table) in enumerate(rows) for c in columns}
    limits = {c: np.nanmax([np.nanmax(np.abs(grids[(r, c)][2] / n12_ss)) for r in range(len(rows))]) for c in columns}
    fig, axes = plt.subplots(
        len(rows),
        2,
        subplot_kw={"projection": "polar"},
        figsize=(8.5, 4 * len(rows)),
        constrained_layout=True,
        squeeze=False,
    )
    for r, (row_name, _) in enumerate(rows):
        for c, (column, label) in enumerate(columns.items()):
            ax = axes[r, c]
            theta_edges, strain_edges, grid = grids[(r, column)]
            mesh = ax.pcolormesh(
                theta_edges,
                strain_edges,
                grid / n12_ss,
                cmap="RdBu_r",
                vmin=-limits[column],
                vmax=limits[column],
                shading="flat",
                rasterized=True,  # an image in the PDF, not a path per cell (commit 94e3e9f, figure_pdf_cost.py)
            )
            ax.set_thetamin(-180)
            ax.set_thetamax(180)
            ax.set_title(f"({'abcdefghijklmnop'[2 * r + c]}) {row_name}", fontsize=10)
            ax.tick_params(labelsize=10)
            if r == len(rows) - 1:
                fig.colorbar(mesh, ax=axes[:, c], orientation="horizontal", shrink=0.8, label=label)
    cell = polar_cell_errors(simulation, n12_ss)
    note = (
        "Radius: strain after rotation; angle: rotation angle theta. "
        f"<nn>_12^ss = {n12_ss:.4g} (simulated steady state); largest seed-mean standard error of a "
        f"cell: {cell['n12']:.3f} (12) and {cell['n23']:.3f} (23) of |<nn>_12^ss|, no smoothing."
    )
    if mirrored:
        note += " theta < 0 of the simulation filled by symmetry (12 even, 23 odd in theta)."
    fig.suptitle(note, fontsize=10, wrap=True)
    return fig


_LINE_STYLES = ("-", "--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)))


def _source_styles(sources) -> dict:
    """A line style per fabric source of the stress relation, in order (simulation first: solid)."""
    return {source: _LINE_STYLES[k % len(_LINE_STYLES)] for k, source in enumerate(dict.fromkeys(sources))}


def _band(ax, frame: pd.DataFrame, column: str, color: str, label: str, max_markers: int = 60):
    step = max(1, len(frame) // max_markers)
    shown = frame.iloc[::step]
    ax.errorbar(
        shown["strain"],
        shown[f"{column}_mean"],
        yerr=shown[f"{column}_sem"],
        fmt="o",
        ms=3,
        color=color,
        label=label,
        elinewidth=0.8,
    )


def figure_stress_startup(simulation: pd.DataFrame, relation_predictions: pd.DataFrame, relation: pd.DataFrame):
    """Paper-style Fig. 3 from the startup stress seed aggregate and the relation's predictions."""
    fig, (ax_eta, ax_normal) = plt.subplots(1, 2, figsize=(8, 6.8), constrained_layout=True)
    sim = simulation.sort_values("strain")
    predicted = relation_predictions[relation_predictions["protocol"] == "startup"]
    labels = dict(zip(relation["source"], relation["label"]))
    for column, color, label in (
        ("eta_r", "k", r"$\eta_r$ total"),
        ("contact_12", "C3", "contact"),
        ("lubrication_12", "C0", "lubrication"),
    ):
        _band(ax_eta, sim, column, color, label)
        for source, style in _source_styles(relation["source"]).items():
            rows = predicted[predicted["source"] == source].sort_values("strain")
            ax_eta.plot(
                rows["strain"],
                rows[column],
                linestyle=style,
                color=color,
                lw=1,
                label=f"relation, {labels.get(source, source)}" if column == "eta_r" else None,
            )
    solvent = sim["solvent_12_mean"] + sim["einstein_12_mean"]
    ax_eta.plot(sim["strain"], solvent, color="0.5", lw=1, label=r"solvent + Einstein $1 + 2.5\phi$")
    ax_eta.set_xlabel(r"strain $\gamma$")
    ax_eta.set_ylabel(r"$\sigma_{12} / \eta_f\dot\gamma$")
    ax_eta.set_title("(a) relative viscosity and its parts", fontsize=10)
    # one legend under both panels: inside (a) it covered the eta_r points at strain 0.3-1.5
    for column, color, label in (("N1", "C2", "$N_1$"), ("N2", "C4", "$N_2$")):
        _band(ax_normal, sim, column, color, label)
        for source, style in _source_styles(relation["source"]).items():
            rows = predicted[predicted["source"] == source].sort_values("strain")
            ax_normal.plot(rows["strain"], rows[column], linestyle=style, color=color, lw=1)
    ax_normal.axhline(0.0, color="0.7", lw=0.5)
    ax_normal.set_xlabel(r"strain $\gamma$")
    ax_normal.set_ylabel(r"$N / \eta_f\dot\gamma$")
    ax_normal.set_title("(b) normal stress differences\n(lines: relation, styles as in (a))", fontsize=10)
    handles, labels = [
        sum(pair, []) for pair in zip(ax_eta.get_legend_handles_labels(), ax_normal.get_legend_handles_labels())
    ]
    fig.legend(handles, labels, loc="outside lower center", ncol=2, fontsize=9.5)
    fits = [f"{row.source}: $a_H$ = {row.a_H:.3g}, $a_C$ = {row.a_C:.3g}" for row in relation.itertuples()]
    lines = ["; ".join(fits[k : k + 3]) for k in range(0, len(fits), 3)]  # three a line: wrap=True ran off the page
    fig.suptitle("Startup shear. Stress relation fitted per fabric source:\n" + "\n".join(lines), fontsize=9.5)
    return fig


def _interval_bars(ax, x, value, low, high, color: str, fmt: str = "o", **kwargs):
    """Markers at ``value`` and bars spanning [low, high] exactly (asymmetric about the value;
    drawn as given even where an interval does not contain its value)."""
    x, value, low, high = (np.asarray(a, dtype=float) for a in (x, value, low, high))
    finite = np.isfinite(low) & np.isfinite(high)  # one seed: no interval to draw
    ax.errorbar(
        x[finite],
        0.5 * (low + high)[finite],
        yerr=0.5 * (high - low)[finite],
        fmt="none",
        ecolor=color,
        elinewidth=0.9,
        capsize=2,
    )
    return ax.plot(x, value, fmt, color=color, ms=4, **kwargs)


def _viscosity_transient_panels(fig, cell, transients: pd.DataFrame):
    """Fig. 4 (e-g) per angle: (e) the integrated viscosity deficit, seed mean with its t-interval
    (the deciding number); (f) the minimum of eta_r/eta_r^ss and (g) the recovery strain, each
    with its seed-bootstrap percentile interval (description)."""
    transients = transients.sort_values("theta")
    theta = transients["theta"]
    window, level = float(transients["window"].iloc[0]), float(transients["level"].iloc[0])
    n_seeds = int(transients["n_seeds"].min())
    percent = f"{100 * level:g}%"
    ax_def, ax_min, ax_rec = (fig.add_subplot(c) for c in cell.subgridspec(1, 3, wspace=0.05))
    _interval_bars(
        ax_def,
        theta,
        transients["deficit"],
        transients["deficit_low"],
        transients["deficit_high"],
        "C0",
        fmt="o-",
        lw=1,
    )
    ax_def.axhline(0.0, color="0.6", lw=0.6)
    ax_def.set_ylabel(rf"$\int_0^{{{window:g}}} (1 - \eta_r / \eta_r^{{ss}})\, d\gamma$")
    ax_def.set_title(
        f"(e) deficit over {window:g} strain\n(seed mean, {percent} t-interval,\n{n_seeds} seeds)", fontsize=10
    )
    _interval_bars(
        ax_min, theta, transients["minimum"], transients["minimum_low"], transients["minimum_high"], "k", fmt="o-", lw=1
    )
    ax_min.set_ylabel(r"min $\eta_r / \eta_r^{ss}$")
    ax_min.set_title(f"(f) viscosity minimum\n(seed bootstrap {percent};\ndescription)", fontsize=10)
    settled = transients["recovery_settled"].astype(bool).to_numpy()
    _interval_bars(
        ax_rec,
        theta[settled],
        transients["recovery_strain"][settled],
        transients["recovery_strain_low"][settled],
        transients["recovery_strain_high"][settled],
        "C3",
        label="recovered",
    )
    if (~settled).any():
        _interval_bars(
            ax_rec,
            theta[~settled],
            transients["recovery_strain"][~settled],
            transients["recovery_strain_low"][~settled],
            transients["recovery_strain_high"][~settled],
            "C3",
            fmt="^",
            mfc="none",
            label="not within 10% by the end\n(lower bound)",
        )
    ax_rec.set_ylabel("recovery strain")
    ax_rec.set_title(
        f"(g) strain to recover $\\eta_r$\nto within 10% (seed\nbootstrap {percent}; description)", fontsize=10
    )
    # room above the bars for the legend, so that it covers none of them
    low, high = ax_rec.get_ylim()
    ax_rec.set_ylim(low, high + 0.45 * (high - low))
    ax_rec.legend(fontsize=10, loc="upper left")
    for ax in (ax_def, ax_min, ax_rec):
        ax.set_xlabel(r"angle $\theta$ (deg)", fontsize=10)
        ax.tick_params(labelsize=10)
        ax.yaxis.label.set_size(10)
        ax.xaxis.set_major_locator(matplotlib.ticker.MultipleLocator(45))
    return ax_def, ax_min, ax_rec


def figure_stress_rotation(
    simulation: pd.DataFrame, relation_predictions: pd.DataFrame, transients: pd.DataFrame, sigma12_ss: float
):
    """Paper-style Fig. 4 from the rotation stress seed aggregate, the relation's predictions and
    the viscosity transients per angle (stress_model.viscosity_transients): the integrated
    deficit with its t-interval, the minimum and the recovery strain with their seed-bootstrap
    intervals."""
    sim, mirrored = mirror_negative_angles(simulation, ["total_12_mean", "total_23_mean"])
    sim = sim.rename(columns={"total_12_mean": "total_12", "total_23_mean": "total_23"})
    predicted = relation_predictions[
        (relation_predictions["protocol"] == "rotation") & (relation_predictions["source"] == "simulation")
    ]
    predicted, _ = mirror_negative_angles(predicted, ["total_12", "total_23"])
    rows = [("simulation", sim), ("G-W relation on the simulated fabric", predicted)]
    columns = {"total_12": r"$\sigma'_{12}/\sigma_{12}^{ss}$", "total_23": r"$\sigma'_{23}/\sigma_{12}^{ss}$"}
    grids = {(r, c): _polar_grid(table, c) for r, (_, table) in enumerate(rows) for c in columns}
    fig = plt.figure(figsize=(8.5, 12.5), constrained_layout=True)
    spec = fig.add_gridspec(3, 2, height_ratios=[1, 1, 0.7])
    limits = {
        "total_12": (0.0, max(1.2, np.nanmax([np.nanmax(grids[(r, "total_12")][2]) for r in range(2)]) / sigma12_ss)),
        "total_23": (None, None),
    }
    bound = np.nanmax([np.nanmax(np.abs(grids[(r, "total_23")][2])) for r in range(2)]) / sigma12_ss
    limits["total_23"] = (-bound, bound)
    for r, (row_name, _) in enumerate(rows):
        for c, (column, label) in enumerate(columns.items()):
            ax = fig.add_subplot(spec[r, c], projection="polar")
            theta_edges, strain_edges, grid = grids[(r, column)]
            mesh = ax.pcolormesh(
                theta_edges,
                strain_edges,
                grid / sigma12_ss,
                cmap="viridis" if column == "total_12" else "RdBu_r",
                vmin=limits[column][0],
                vmax=limits[column][1],
                shading="flat",
                rasterized=True,  # an image in the PDF, not a path per cell (commit 94e3e9f, figure_pdf_cost.py)
            )
            ax.set_thetamin(-180)
            ax.set_thetamax(180)
            ax.set_title(f"({'abcd'[2 * r + c]}) {row_name}", fontsize=10)
            ax.tick_params(labelsize=10)
            fig.colorbar(mesh, ax=ax, orientation="horizontal", shrink=0.7, label=label, pad=0.08)
    _viscosity_transient_panels(fig, spec[2, :], transients)
    note = (
        # eta_r is dimensionless: the stress is in units of eta_f gammadot, the ratio is not
        f"Radius: strain after rotation; angle: rotation angle theta. eta_r^ss = sigma_12^ss / (eta_f gammadot) "
        f"= {sigma12_ss:.4g} (simulated steady state, solvent and Einstein terms included)."
    )
    if mirrored:
        note += " theta < 0 filled by symmetry (12 even, 23 odd in theta)."
    fig.suptitle(note, fontsize=10, wrap=True)
    return fig


def _seed_interval(statistics: pd.DataFrame, column: str, level: float) -> pd.DataFrame:
    """Per angle: the seed mean of ``column`` and its t-interval over seeds."""
    rows = []
    for theta, group in statistics.groupby("theta", sort=True):
        interval = t_interval(group[column].to_numpy(), level)
        rows.append({"theta": theta, "mean": interval.mean, "low": interval.low, "high": interval.high})
    return pd.DataFrame(rows)


def figure_claims(statistics: pd.DataFrame, level: float):
    """Fig. 5: the quantities the shear-rotation claims rest on, per angle (primary choice):
    (a) the <nn>'_12 deficit D12, (b) the <nn>'_23 effect E23, (c) the paired mean-square-error
    difference reference - challenger on r12 and r23 (> 0: the challenger is closer), (d) the
    excess X12 above steady inside the challenger's overshoot window. The compared models (config
    verdicts.models) by the labels the statistics record. Simulation: seed mean with its t-interval
    over seeds; models: seed mean of each seed's own fit. Shaded: the claims' ranges."""
    from suspension_fabric.evaluation.claims import CLAIMS  # noqa: PLC0415

    ranges = {claim.key: claim.angles for claim in CLAIMS}
    fig, axes = plt.subplots(2, 2, figsize=(8, 7.8), sharex=True)
    panels = [
        (axes[0, 0], "D12", "C1", r"(a) deficit $D_{12}=\int_0^W (1 - r_{12})\,d\gamma$"),
        (axes[0, 1], "E23", "C2", r"(b) transverse effect $E_{23}=\mathrm{sgn}\,\theta\int_0^W r_{23}\,d\gamma$"),
        (axes[1, 1], "X12", "C6", "(d) excess $X_{12}$ in the challenger's\novershoot window"),
    ]
    colors = {"reference": "C1", "challenger": "C2"}
    labels = {role: str(statistics[f"{role}_label"].iloc[0]) for role in colors}
    percent = f"{100 * level:g}%"
    for ax, quantity, claim, title in panels:
        sim = _seed_interval(statistics, f"{quantity}_sim", level)
        _interval_bars(
            ax, sim["theta"], sim["mean"], sim["low"], sim["high"], "k", label=f"simulation ({percent} t-interval)"
        )
        for role, color in colors.items():
            mean = statistics.groupby("theta")[f"{quantity}_{role}"].mean()
            ax.plot(mean.index, mean.to_numpy(), "-", color=color, marker="s", ms=3, label=labels[role])
        ax.axvspan(*ranges[claim], color="0.9", zorder=0)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_title(title, fontsize=9.5)
    ax = axes[1, 0]
    for component, color in (("12", "C0"), ("23", "C3")):
        difference = statistics.assign(
            d=statistics[f"MSE{component}_reference"] - statistics[f"MSE{component}_challenger"]
        )
        if component == "23":  # both models exact by symmetry at 0 and 180 degrees
            difference = difference[
                ~np.isclose(np.abs(difference["theta"]), 0.0) & ~np.isclose(np.abs(difference["theta"]), 180.0)
            ]
        paired = _seed_interval(difference, "d", level)
        _interval_bars(
            ax,
            paired["theta"] + (1.0 if component == "23" else -1.0),
            paired["mean"],
            paired["low"],
            paired["high"],
            color,
            label=rf"$r_{{{component}}}$ ({percent} t-interval)",
        )
    ax.axvspan(*ranges["C3"], color="0.9", zorder=0)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvspan(*ranges["C4"], ymin=0.0, ymax=0.06, color="C3", alpha=0.25, zorder=0)  # C4's range, on the axis
    ax.set_title(
        f"(c) paired MSE, {labels['reference']} $-$ {labels['challenger']}\n(> 0: {labels['challenger']} closer)",
        fontsize=9.5,
    )
    axes[1, 0].legend(fontsize=9.5, frameon=False, loc="upper left")
    for ax in axes[1]:
        ax.set_xlabel(r"rotation angle $\theta$ (deg)")
    # (a), (b) and (d) share their entries: one legend under the panels, where it covers no curve
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=9.5, frameon=False)
    fig.tight_layout(rect=(0, 0.045, 1, 1))
    return fig

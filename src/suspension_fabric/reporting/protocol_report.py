"""The protocols' results as a Markdown page fragment, written from the tables (never typed): for
each protocol, which fabric model predicts it best and by how much, against G-W, and how the
stress relations do on the simulated fabric.

Rows per protocol: every fabric model in both fitting modes, whether its scored seeds are held out
(no fit behind it saw them) or in-sample, with its mean square error (in units
of (<nn>_12^ss)^2, mean over seeds and t-interval) over the six components and on the shear
components <nn>_12 and <nn>_23 (the diagonal components, which G-W fitted on the steady state
misses by construction, dominate the six-component mean), each with the paired per-seed
difference from G-W's steady fit and its t-interval; then every stress relation's error of eta_r
(in units of (eta_r^ss)^2) and its paired difference from the G-W relation. A difference whose
interval lies wholly below zero is marked "better", wholly above "worse", both bounds round-off
"identical", else "not decided".

Then, per protocol, the simulations' late state of every segment after the startup (the second
half of the segment, [`suspension_fabric.analysis.protocol_tables.segment_states`][]): Z, <nn>_12,
<nn>_23 (in the frame of the current flow), eta_r and Pi, each as the seed mean and its paired
per-seed difference from the startup's steady state with its t-interval. Where a protocol has a
steady or periodic state, this is it; where the segment is too short to reach one, the table says
how far it got.
"""

from __future__ import annotations

import pandas as pd

from suspension_fabric.analysis.protocol_tables import DRIFT_POWER
from suspension_fabric.analysis.seed_statistics import adjusted_p
from suspension_fabric.evaluation.protocol_benchmark import ALL_COMPONENTS
from suspension_fabric.io.fit_provenance import held_out_label

__all__ = [
    "summary_markdown",
    "states_markdown",
    "drift_markdown",
    "comparison",
    "symmetry_zero",
    "SHOWN",
    "STATE_QUANTITIES",
]

#: Shown as 0: values this small are round-off (a component every model keeps at 0 by symmetry).
ROUND_OFF = 1e-12


def comparison(low: float, high: float, p_adjusted: float = 0.0, level: float = 0.95) -> str:
    """The reading of a difference's interval: better (below 0), worse (above), identical (both
    bounds round-off: the same prediction, e.g. a component both models keep at 0), not decided;
    better or worse only where the p-value adjusted for the cells read at once is under 1 - level."""
    if max(abs(low), abs(high)) <= ROUND_OFF:
        return "identical"
    if p_adjusted >= 1.0 - level:
        return "not decided"
    if high < 0.0:
        return "better"
    if low > 0.0:
        return "worse"
    return "not decided"


def _number(value: float) -> str:
    return f"{value:.3g}" if abs(value) > ROUND_OFF else "0"


def _interval(mean: float, low: float, high: float) -> str:
    return f"{_number(mean)} [{_number(low)}, {_number(high)}]"


#: The fabric scores shown: the mean over the six components, and the two shear components the
#: paper's claims after a rotation are about.
SHOWN = (ALL_COMPONENTS, "n12", "n23")


#: The late-state quantities shown: fabric table columns, then stress table columns.
STATE_QUANTITIES = {"Z": "Z", "n12": "⟨nn⟩₁₂", "n23": "⟨nn⟩₂₃", "eta_r": "η_r", "Pi": "Π"}


def _segment_name(row) -> str:
    turning = row["turning_deg_per_strain"]
    flow = f"flow at {row['flow_angle_deg']:g} deg"
    return f"{int(row['segment'])}: {flow}" + (f", turning {turning:g} deg/strain" if turning else "")


def states_markdown(states: pd.DataFrame, level: float) -> list[str]:
    """Per protocol, the late state of each segment after the startup against the startup's steady
    state (module docstring); ``states``: protocol_states.csv and stress_protocol_states.csv rows."""
    percent = f"{100 * level:g}%"
    shown = states[states["quantity"].isin(list(STATE_QUANTITIES))].copy()
    # every difference of the page is read at once: Holm's adjustment over all of them
    shown["difference_p_holm"] = adjusted_p(shown["difference_p"].to_numpy(), "holm")
    lines = [
        f"Late state of each segment (its second half), seed mean; in brackets the per-seed difference from the "
        f"startup's steady state [{percent} t-interval] and its reading: higher or lower where the t-test's p, "
        f"adjusted by Holm's method over the {len(shown)} differences of this list, is below {1 - level:.2g}, else "
        "not decided. ⟨nn⟩ in the frame of the current flow; η_r dimensionless (the shear stress over η_f γ̇), Π "
        "in units of η_f γ̇.",
        "",
    ]
    for protocol, rows in shown.groupby("protocol", sort=False):
        steady = rows.drop_duplicates("quantity").set_index("quantity")["startup_steady"]
        quantities = [q for q in STATE_QUANTITIES if q in steady.index]
        lines += [
            f"**{protocol}**",
            "",
            "| segment | strain window | " + " | ".join(STATE_QUANTITIES[q] for q in quantities) + " |",
            "|---|---|" + "---|" * len(quantities),
            "| startup steady state | | " + " | ".join(f"{steady[q]:.3g}" for q in quantities) + " |",
        ]
        for _, segment in rows.groupby("segment", sort=True):
            by_quantity = segment.set_index("quantity")
            first = segment.iloc[0]
            cells = []
            for q in quantities:
                r = by_quantity.loc[q]
                decided = r["difference_p_holm"] < 1.0 - level
                reading = ("lower" if r["difference"] < 0 else "higher") if decided else "not decided"
                shift = _interval(r["difference"], r["difference_low"], r["difference_high"])
                cells.append(f"{r['mean']:.3g} ({shift} {reading})")
            window = f"{first['window_low']:g}-{first['window_high']:g}"
            lines.append(f"| {_segment_name(first)} | {window} | " + " | ".join(cells) + " |")
        lines.append("")
    return lines


def drift_markdown(drift: pd.DataFrame, level: float) -> list[str]:
    """The drift of the late states over the repeated segments of each protocol that has enough
    (analysis.protocol_tables.segment_drift, with ``slope_p_holm`` over every slope read at once)."""
    if drift.empty or "quantity" not in drift:
        return []
    shown = drift[drift["quantity"].isin(list(STATE_QUANTITIES))]
    if shown.empty:
        return []
    percent = f"{100 * level:g}%"
    lines = [
        "Drift over the repeated segments, from the second after the startup on (the first leaves the steady "
        "state of simple shear): per seed the least-squares slope of the late state against the segment's index "
        f"(per segment), seed mean [{percent} t-interval]; a drift is read only where its p-value, adjusted by "
        f"Holm's method over the {len(shown)} slopes of this table, is under {1 - level:.2g}; the slope such a "
        f"test would detect with {100 * DRIFT_POWER:.0f}% power over these seeds; and the last segment's late "
        "state minus the second's.",
        "",
        "| protocol | segments | quantity | first | second | last | slope per segment | reading | detectable slope "
        "| last − second |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for _, row in shown.iterrows():
        slope = _interval(row["slope"], row["slope_low"], row["slope_high"])
        reading = comparison(row["slope_low"], row["slope_high"], row["slope_p_holm"], level)
        reading = {"better": "falls", "worse": "rises"}.get(reading, reading)
        change = _interval(row["change"], row["change_low"], row["change_high"])
        lines.append(
            f"| {row['protocol']} | {int(row['segments'])} | {STATE_QUANTITIES[row['quantity']]} | "
            f"{_number(row['first'])} | {_number(row['second'])} | {_number(row['last'])} | {slope} | {reading} | "
            f"±{_number(row['detectable_slope'])} | {change} |"
        )
    return lines + [""]


def _difference(row, reference: str) -> tuple[float, float, float]:
    return tuple(row[f"difference{suffix}_vs_{reference}"] for suffix in ("", "_low", "_high"))


def _cell(row, reference: str, is_reference: bool, level: float) -> str:
    """Error [interval]; and, but for the reference, the difference from it [interval] and its
    reading (Holm-adjusted over the table's differences)."""
    error = _interval(row["mse"], row["mse_low"], row["mse_high"])
    if is_reference:
        return f"{error}; reference"
    shift = _difference(row, reference)
    reading = comparison(*shift[1:], row[f"difference_p_holm_vs_{reference}"], level)
    return f"{error}; {_interval(*shift)} {reading}"


def symmetry_zero(board: pd.DataFrame, protocol: str, component: str) -> bool:
    """Whether every model's prediction of ``component`` along ``protocol`` is that of the reference
    to round-off (a component every model keeps at 0 by the flow's symmetry, e.g. <nn>_23 under
    reversals): such a column says nothing about the models."""
    rows = board[(board["protocol"] == protocol) & (board["component"] == component)]
    bounds = rows.filter(regex=r"^difference_(low|high)_vs_").abs().to_numpy()
    return bool(bounds.size) and bool((bounds <= ROUND_OFF).all())


def _parameter_note(board: pd.DataFrame) -> str:
    """The sentence saying whether the fabric intervals carry the fits' own uncertainty, and for
    which rows they do not (a fit without errors)."""
    if "parameter_se" not in board:
        return ""
    missing = board[board["parameter_se"].isna()]
    fitted = {"steady": "steady state", "global": "startup + rotations"}
    names = ", ".join(
        sorted({f"{label} ({fitted.get(mode, mode)})" for label, mode in zip(missing["label"], missing["mode"])})
    )
    note = (
        " Fabric intervals and p-values carry the fits' own uncertainty: each parameter moved by its jackknife error, "
        "the seed-mean score's responses combined with the fit's leave-one-out correlations (first order), added "
        "in quadrature to the seeds' standard error"
    )
    return note + (f"; not for {names}, whose fits have no error." if names else ".")


def summary_markdown(
    board: pd.DataFrame,
    stress_board: pd.DataFrame,
    states: pd.DataFrame,
    level: float,
    *,
    reference: str,
    reference_relation: str,
    drift: pd.DataFrame | None = None,
) -> str:
    """The page fragment (module docstring) from protocol_leaderboard.csv,
    protocol_stress_leaderboard.csv and the late states (protocol_states.csv and
    stress_protocol_states.csv, concatenated); differences from the fabric model ``reference``
    fitted on the steady state and from the stress relation ``reference_relation`` (keys); and
    the drift over repeated segments (``drift``, fabric and stress rows), if given."""
    drift = pd.DataFrame(columns=["quantity"]) if drift is None else drift
    percent = f"{100 * level:g}%"
    eta = stress_board[stress_board["quantity"] == "eta_r"]
    label = board.loc[board["model"] == reference, "label"].iloc[0]
    relation = stress_board.loc[stress_board["relation"] == reference_relation, "label"].iloc[0]
    cells = int(board.filter(regex=r"^difference_p_vs_").notna().to_numpy().sum())
    lines = [
        f"Each cell: error [{percent} interval]; minus {label} fitted on the steady state (stress: minus the "
        f"{relation}) [{percent} interval] and its reading, better or worse only where the p-value adjusted by "
        f"Holm's method over the fabric table's {cells} differences is under {1 - level:.2g}. Fabric errors in units "
        "of (⟨nn⟩₁₂ˢˢ)², η_r's in (η_rˢˢ)². Scored seeds: held out only if no fit behind the row saw any of "
        "them. A component every model keeps at 0 by the flow's symmetry is left out." + _parameter_note(board),
        "",
    ]
    for protocol in dict.fromkeys(board["protocol"]):
        mine = board[board["protocol"] == protocol]
        names = {ALL_COMPONENTS: "six components", "n12": "⟨nn⟩₁₂", "n23": "⟨nn⟩₂₃"}
        shown = [c for c in SHOWN if c == ALL_COMPONENTS or not symmetry_zero(board, protocol, c)]
        lines += [
            f"**{protocol}**",
            "",
            "| model | fitted on | scored seeds | " + " | ".join(names[c] for c in shown) + " |",
            "|---|---|---|" + "---|" * len(shown),
        ]
        for (model, mode), rows in mine.groupby(["model", "mode"], sort=False):
            by_component = rows.set_index("component")
            fitted = "startup steady state" if mode == "steady" else "startup + rotations"
            fitted = f"{rows['fitted_on'].iloc[0]}: {fitted}"
            is_reference = model == reference and mode == "steady"
            cells = [_cell(by_component.loc[c], reference, is_reference, level) for c in shown]
            seeds = held_out_label(bool(rows["held_out"].all()))
            lines.append(f"| {rows['label'].iloc[0]} | {fitted} | {seeds} | " + " | ".join(cells) + " |")
        lines += ["", "| stress relation | scored seeds | η_r |", "|---|---|---|"]
        for _, row in eta[eta["protocol"] == protocol].iterrows():
            cell = _cell(row, reference_relation, row["relation"] == reference_relation, level)
            lines.append(f"| {row['label']} | {held_out_label(bool(row['held_out']))} | {cell} |")
        lines.append("")
    return "\n".join(lines + states_markdown(states, level) + drift_markdown(drift, level))

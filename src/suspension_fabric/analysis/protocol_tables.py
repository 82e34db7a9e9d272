"""Per-frame tables along a flow history: the runs of a protocol's segments joined, and their seed
means.

**Protocol table** ([`protocol_table`][suspension_fabric.analysis.protocol_tables.protocol_table]).
One row per frame of every segment of every seed, with the columns:

| column | meaning |
|---|---|
| ``protocol`` | protocol name ([`Protocol`][suspension_fabric.io.protocols.Protocol]) |
| ``segment`` | index of the segment in the protocol (0 from rest) |
| ``seed`` | integer seed of the run |
| ``frame`` | ``flow``: tensors in the frame of the current flow (e1 the flow direction, e2 the gradient) |
| ``theta`` | flow angle of that frame, degrees about e2 from the first segment's flow direction |
| ``N``, ``phi`` | as in the run tables |
| ``step`` | LAMMPS step of the frame |
| ``segment_strain`` | strain since the segment started |
| ``strain`` | strain since the protocol started (rest) |
| values | the per-run table's value columns (fabric or stress) |

The frame of the current flow has e1 the flow direction at that strain, e2 the gradient and
e3 = e1 x e2. Where one segment ends and the next begins, both rows are kept at the same
``strain``: the last frame of a segment and the first of the next are the same configuration, seen
in the frames of the two flows (a shear rotation turns the frame, not the particles).

**Seed aggregate**
([`aggregate_protocol_seeds`][suspension_fabric.analysis.protocol_tables.aggregate_protocol_seeds]).
Per (protocol, segment, frame): the strains, the frame angle, n_seeds and ``c_mean``, ``c_sem`` for
every value column ``c`` (as
[`suspension_fabric.analysis.tables.aggregate_seeds`][suspension_fabric.analysis.tables.aggregate_seeds]).

**Late states** ([`segment_states`][suspension_fabric.analysis.protocol_tables.segment_states]).
Where a flow history settles: per protocol, segment after the first and value column, each seed's
mean over the last half of the segment (in the frame of the current flow, so a steady state in
rotary shear is steady in the turning frame, and the states after successive reversals are
comparable), the seed mean with its t-interval, and the paired per-seed difference from the seed's
steady state of the protocol's first segment (the startup; mean over the steady window), with its
t-interval. An interval of the difference that excludes 0 says the segment settles elsewhere than
simple shear, or has not settled yet.

**Drift over repeated segments**
([`segment_drift`][suspension_fabric.analysis.protocol_tables.segment_drift]). For a protocol of
many repeated segments (an oscillation): the first change of direction leaves the steady state of
simple shear, so the drift is measured from the second segment after the startup on, over at least
`DRIFT_MIN_SEGMENTS` segments: per seed, the least-squares slope of the late state against the
segment's index (per segment), with its t-interval, t-test p-value and the slope a test at the same
level would detect with 80% power over these seeds (``detectable_slope``), and the paired
difference of the last segment's late state from the second's. A state repeated from segment to
segment has no slope; a slow organisation over the cycles (random organisation towards fewer
contacts, say) has one.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.io.protocols import Protocol

from .seed_statistics import LEVEL, t_interval
from .tables import aggregate_seeds

__all__ = [
    "FLOW_FRAME",
    "PROTOCOL_COLUMNS",
    "protocol_table",
    "aggregate_protocol_seeds",
    "protocol_tables",
    "read_protocol_table",
    "segment_states",
    "DRIFT_MIN_SEGMENTS",
    "DRIFT_POWER",
    "segment_drift",
]

#: The ``frame`` of every protocol-table row: tensors in the frame of the current flow.
FLOW_FRAME = "flow"
#: The columns a protocol table puts before the run tables' value columns.
PROTOCOL_COLUMNS = ("protocol", "segment", "seed", "frame", "theta", "N", "phi", "step", "segment_strain", "strain")


def protocol_table(
    protocol: Protocol,
    runs: Sequence[str],
    read: Callable[[str, int], pd.DataFrame],
    seeds: Sequence[int],
    value_columns,
) -> pd.DataFrame:
    """The protocol's per-frame table: for each seed, ``read(run, seed)`` (a per-run table with the
    run-table columns) of each segment's run ``runs[k]``, joined along the protocol's strain."""
    if len(runs) != len(protocol.segments):
        raise ValueError(f"protocol {protocol.name}: {len(runs)} runs for {len(protocol.segments)} segments")
    blocks = []
    for seed in seeds:
        for index, (run, start) in enumerate(zip(runs, protocol.start_strains)):
            rows = read(run, seed)
            expected = protocol.segments[index].flow_angle_at(rows["strain"].to_numpy())
            if not np.allclose(rows["theta"].to_numpy(), expected, atol=1e-9):
                raise ValueError(
                    f"protocol {protocol.name}, segment {index}: run {run} of seed {seed} has flow angles "
                    f"{rows['theta'].iloc[0]:g} ... where the segment has {expected[0]:g} ..."
                )
            block = pd.DataFrame(
                {
                    "protocol": protocol.name,
                    "segment": index,
                    "seed": rows["seed"].to_numpy(),
                    "frame": FLOW_FRAME,
                    "theta": rows["theta"].to_numpy(),
                    "N": rows["N"].to_numpy(),
                    "phi": rows["phi"].to_numpy(),
                    "step": rows["step"].to_numpy(),
                    "segment_strain": rows["strain"].to_numpy(),
                    "strain": start + rows["strain"].to_numpy(),
                }
            )
            for column in value_columns:
                block[column] = rows[column].to_numpy()
            blocks.append(block)
    return pd.concat(blocks, ignore_index=True)


def aggregate_protocol_seeds(table: pd.DataFrame, value_columns) -> pd.DataFrame:
    """Mean and standard error over seeds per (protocol, segment) and frame of a protocol table
    (module docstring); the seeds of one segment must share its strain grid."""
    blocks = []
    for (name, index), group in table.groupby(["protocol", "segment"], sort=False):
        one = group[group["seed"] == group["seed"].min()].sort_values("segment_strain", kind="stable")
        # aggregate_seeds groups by theta: give every row of this segment one key, then restore it
        keyed = group.assign(theta=0.0, strain=group["segment_strain"])
        aggregate = aggregate_seeds(keyed, value_columns)
        aggregate.insert(0, "protocol", name)
        aggregate.insert(1, "segment", index)
        aggregate.insert(2, "frame", FLOW_FRAME)
        aggregate["theta"] = one["theta"].to_numpy()
        aggregate = aggregate.rename(columns={"strain": "segment_strain"})
        aggregate.insert(aggregate.columns.get_loc("segment_strain") + 1, "strain", one["strain"].to_numpy())
        blocks.append(aggregate)
    return pd.concat(blocks, ignore_index=True)


def read_protocol_table(path: str | os.PathLike) -> pd.DataFrame:
    """A protocol table or aggregate CSV; ``ValueError`` naming the file if it lacks the protocol
    columns or holds another frame than `FLOW_FRAME`."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"protocol table not found: {path}")
    table = pd.read_csv(path)
    missing = [c for c in ("protocol", "segment", "frame", "theta", "segment_strain", "strain") if c not in table]
    if missing:
        raise ValueError(f"{path}: not a protocol table (no column(s) {missing})")
    frames = set(table["frame"].unique())
    if frames != {FLOW_FRAME}:
        raise ValueError(f"{path}: frame(s) {sorted(frames)}, expected {FLOW_FRAME!r} (the current flow's)")
    return table


def protocol_tables(
    protocols: Mapping[str, Protocol],
    run_names: Mapping[str, Sequence[str]],
    read: Callable[[str, int], pd.DataFrame],
    seeds: Sequence[int],
    value_columns,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(protocol table, seed aggregate) of several protocols, ``run_names[name]`` the runs of each."""
    table = pd.concat(
        [protocol_table(p, run_names[name], read, seeds, value_columns) for name, p in protocols.items()],
        ignore_index=True,
    )
    return table, aggregate_protocol_seeds(table, value_columns)


def segment_states(
    protocols: Mapping[str, Protocol], table: pd.DataFrame, value_columns, steady_window, level: float = LEVEL
) -> pd.DataFrame:
    """The late state of every segment after the first of each protocol (module docstring) from a
    protocol table (per seed), with the t-test p-value of each difference from the startup's steady
    state (``difference_p``; a report that reads many cells at once adjusts them)."""
    from .seed_statistics import t_test_p

    low, high = steady_window
    rows = []
    for name, protocol in protocols.items():
        mine = table[table["protocol"] == name]
        first = mine[(mine["segment"] == 0) & mine["segment_strain"].between(low - 1e-9, high + 1e-9)]
        if first.empty:
            raise ValueError(f"protocol {name}: no frame of its first segment in the steady window {steady_window}")
        base = first.groupby("seed")[list(value_columns)].mean()
        for index, segment in enumerate(protocol.segments[1:], start=1):
            window = (segment.strain / 2.0, segment.strain)
            late = mine[(mine["segment"] == index) & mine["segment_strain"].between(window[0] - 1e-9, window[1] + 1e-9)]
            per_seed = late.groupby("seed")[list(value_columns)].mean().loc[base.index]
            for column in value_columns:
                state = t_interval(per_seed[column].to_numpy(), level)
                shift = t_interval((per_seed[column] - base[column]).to_numpy(), level)
                shift_p = t_test_p((per_seed[column] - base[column]).to_numpy())
                rows.append(
                    {
                        "protocol": name,
                        "segment": index,
                        "flow_angle_deg": segment.flow_angle_deg,
                        "turning_deg_per_strain": segment.turning_deg_per_strain,
                        "window_low": window[0],
                        "window_high": window[1],
                        "quantity": column,
                        "n_seeds": state.n,
                        "mean": state.mean,
                        "low": state.low,
                        "high": state.high,
                        "startup_steady": float(base[column].mean()),
                        "difference": shift.mean,
                        "difference_low": shift.low,
                        "difference_high": shift.high,
                        "difference_p": shift_p,
                    }
                )
    return pd.DataFrame(rows)


#: Segments, from the second after the startup on, that a protocol needs for its drift to be measured.
DRIFT_MIN_SEGMENTS = 3
#: The power at which ``detectable_slope`` is stated.
DRIFT_POWER = 0.8


def segment_drift(protocols: Mapping[str, Protocol], table: pd.DataFrame, value_columns, level: float = LEVEL):
    """The drift of the late states over the repeated segments (module docstring), per protocol
    with enough of them and per value column, from a protocol table (per seed)."""
    from scipy import stats

    from .seed_statistics import t_test_p

    rows = []
    for name, protocol in protocols.items():
        later = protocol.segments[1:]
        if len(later) - 1 < DRIFT_MIN_SEGMENTS:
            continue
        mine = table[table["protocol"] == name]
        states = []
        for index, segment in enumerate(later, start=1):
            half = mine[(mine["segment"] == index) & (mine["segment_strain"] >= segment.strain / 2.0 - 1e-9)]
            states.append(half.groupby("seed")[list(value_columns)].mean())
        index = np.arange(2, len(later) + 1, dtype=float)
        centred = index - index.mean()
        for column in value_columns:
            values = np.stack([state[column].to_numpy() for state in states], axis=1)  # (seeds, segments)
            slopes = values[:, 1:] @ centred / (centred @ centred)
            slope = t_interval(slopes, level)
            change = t_interval(values[:, -1] - values[:, 1], level)
            dof = slope.n - 1
            detectable = (stats.t.ppf(0.5 + level / 2.0, dof) + stats.t.ppf(DRIFT_POWER, dof)) * slope.se
            rows.append(
                {
                    "protocol": name,
                    "quantity": column,
                    "segments": len(later) - 1,
                    "n_seeds": slope.n,
                    "first": float(values[:, 0].mean()),
                    "second": float(values[:, 1].mean()),
                    "last": float(values[:, -1].mean()),
                    "slope": slope.mean,
                    "slope_low": slope.low,
                    "slope_high": slope.high,
                    "slope_p": t_test_p(slopes),
                    "detectable_slope": float(detectable),
                    "change": change.mean,
                    "change_low": change.low,
                    "change_high": change.high,
                }
            )
    return pd.DataFrame(rows)

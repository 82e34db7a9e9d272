"""Tidy fabric tables: per-run CSV, seed aggregation, steady-state estimates.

**Per-run table.** One row per analysed frame, a CSV written by
[`write_fabric_table`][suspension_fabric.analysis.tables.write_fabric_table]. Its columns, in this
order:

| column | meaning |
|---|---|
| ``seed`` | integer seed of the run (packing / initial condition) |
| ``theta`` | flow angle of the frame in degrees about e2 (below) |
| ``N`` | number of particles |
| ``phi`` | volume fraction sum(4/3 pi a^3) / V (measured from the dump unless given) |
| ``step`` | LAMMPS step of the frame |
| ``strain`` | strain since the start of this shear, (step - start) dt rate |
| ``n11 n22 n33 n12 n13 n23`` | fabric components <nn>_kl (1/N sum over near contacts of n_k n_l) |
| ``Z`` | near-contact coordination number, 2 n_pairs / N = 2 Tr<nn> |
| ``n1111`` ... ``n3333`` | the 15 independent components of <nnnn> (i <= j <= k <= l) (`MOMENT_COLUMNS`) |
| ``Y0_0`` ... ``Y6_p6`` | spherical-harmonic amplitudes a_lm of the near-contact directions, l = 0, 2, 4, 6 |

``theta`` is 0 for startup shear, theta after a shear rotation by theta, and turns with the strain
in rotary shear; the components are in the frame of this flow (e1' the flow direction, e2 the
gradient, e3' = e1' x e2). <nnnn> has the normalisation and the frame of <nn>; the amplitudes a_lm
are defined in [`suspension_fabric.analysis.fabric`][suspension_fabric.analysis.fabric]. These
last two groups are absent from tables made before they were recorded;
[`read_fabric_table`][suspension_fabric.analysis.tables.read_fabric_table] with ``moments=True``
reads them as empty (NaN).

The file is plain comma-separated text with one header line, no index column, floats written with
full round-trip precision (pandas ``to_csv`` defaults), the moment columns with `MOMENT_DIGITS` = 9
significant digits; ``pandas.read_csv(path)`` reads it,
[`read_fabric_table`][suspension_fabric.analysis.tables.read_fabric_table] also checks it.

**Seed aggregation** ([`aggregate_seeds`][suspension_fabric.analysis.tables.aggregate_seeds]). Per
(theta, frame): the strain, n_seeds, and for every value column ``c`` ``c_mean`` and ``c_sem``
(standard error of the mean over seeds, std(ddof=1)/sqrt(n_seeds); NaN for a single seed). All
seeds of one theta must have the same strain grid, else ``ValueError``.

**Steady state** ([`steady_state`][suspension_fabric.analysis.tables.steady_state]). For every theta
and value column, the mean over the frames with strain_min <= strain <= strain_max of each seed,
averaged over seeds with equal weights. The error accounts for time correlation through the
integrated autocorrelation time tau of each seed's series (Sokal's automatic window: the smallest
window M with M >= c tau(M), c = 5): the variance of a seed's mean is C(0) 2 tau / n, and the error
of the seed average is sqrt(sum_s var_s) / n_seeds. The spread of the seed means,
std(ddof=1)/sqrt(n_seeds), is reported alongside as an assumption-free check.
"""

from __future__ import annotations

import io
import os
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.io.runinfo import read_run_info

from .components import COMPONENTS, DEFAULT_EPS, FOURTH_MOMENT_COMPONENTS, HARMONIC_COLUMNS

__all__ = [
    "METADATA_COLUMNS",
    "VALUE_COLUMNS",
    "TABLE_COLUMNS",
    "MOMENT_COLUMNS",
    "fabric_table",
    "run_fabric_table",
    "write_fabric_table",
    "read_fabric_table",
    "aggregate_seeds",
    "integrated_autocorrelation_time",
    "steady_state",
    "TOLERANCE",
    "settle_strain",
    "settle_strains",
    "fabric_tensors",
]

METADATA_COLUMNS: tuple[str, ...] = ("seed", "theta", "N", "phi")
VALUE_COLUMNS: tuple[str, ...] = (*COMPONENTS, "Z")
TABLE_COLUMNS: tuple[str, ...] = (*METADATA_COLUMNS, "step", "strain", *VALUE_COLUMNS)
#: The per-frame columns after TABLE_COLUMNS in a run's fabric table: <nnnn> and the spherical-harmonic
#: amplitudes of the near-contact directions (suspension_fabric.analysis.fabric), empty in the
#: tables made before they were recorded.
MOMENT_COLUMNS: tuple[str, ...] = (*FOURTH_MOMENT_COMPONENTS, *HARMONIC_COLUMNS)
#: Significant digits of the MOMENT_COLUMNS in a written table (the others: full round-trip precision).
MOMENT_DIGITS = 9
#: The relative band of "settled" and "agrees": a series has settled when its relative deviation
#: stays within it, and a steady value agrees with the simulation when within it.
TOLERANCE = 0.1


def fabric_tensors(values, suffix: str = "") -> np.ndarray:
    """<nn> from the ``n11<suffix>`` ... ``n23<suffix>`` entries of a mapping (one 3x3 tensor) or of
    a table (one per row, shape (rows, 3, 3)), e.g. ``suffix="_mean"`` for a seed aggregate."""
    rows, cols = zip(*COMPONENTS.values())
    stacked = np.stack([np.asarray(values[f"{name}{suffix}"], dtype=float) for name in COMPONENTS], axis=-1)
    tensors = np.empty(stacked.shape[:-1] + (3, 3))
    tensors[..., rows, cols] = stacked
    tensors[..., cols, rows] = stacked
    return tensors


def fabric_table(analysis, *, seed: int, phi: float | None = None) -> pd.DataFrame:
    """Per-run tidy table from a finished [`FabricAnalysis`][suspension_fabric.analysis.fabric.FabricAnalysis].

    ``theta`` is each frame's flow angle in degrees; ``phi`` defaults to the mean
    measured volume fraction of the analysed frames.
    """
    results = analysis.results
    if "strain" not in results:
        raise ValueError("the analysis has not been run (call .run() first)")
    n_frames = len(results.strain)
    measured_phi = float(np.mean(results.volume_fraction)) if n_frames else np.nan
    table = pd.DataFrame(
        {
            "seed": np.full(n_frames, int(seed), dtype=np.int64),
            "theta": np.asarray(results.flow_angle_deg, dtype=float),
            "N": np.full(n_frames, int(results.n_particles), dtype=np.int64),
            "phi": np.full(n_frames, measured_phi if phi is None else float(phi)),
            "step": np.asarray(results.step, dtype=np.int64),
            "strain": np.asarray(results.strain, dtype=float),
            **{name: np.asarray(results[name], dtype=float) for name in COMPONENTS},
            "Z": np.asarray(results.coordination, dtype=float),
            **{name: np.asarray(results[name], dtype=float) for name in MOMENT_COLUMNS},
        }
    )
    return table[[*TABLE_COLUMNS, *MOMENT_COLUMNS]]


def run_fabric_table(
    dump: str | os.PathLike, marker: str | os.PathLike, *, seed: int, eps: float = DEFAULT_EPS
) -> pd.DataFrame:
    """Per-run tidy table of a finished shear run: its trajectory ``dump`` analysed with the
    time step, shear rate, first step and flow (angle, turning rate) recorded in its completion ``marker``
    ([`suspension_fabric.io.runinfo.read_run_info`][suspension_fabric.io.runinfo.read_run_info]), near contacts at gap <
    ``eps`` d_min.
    """
    from .fabric import FabricAnalysis  # noqa: PLC0415 (MDAnalysis only where contacts are detected)

    info = read_run_info(marker)
    analysis = FabricAnalysis.from_dump(
        dump,
        dt=info.dt,
        shear_rate=info.rate,
        shear_start_step=info.first_step,
        flow_angle_deg=info.segment.flow_angle_deg,
        turning_deg_per_strain=info.segment.turning_deg_per_strain,
        eps=eps,
    ).run()
    table = fabric_table(analysis, seed=seed)
    if info.strain_recorded:
        _check_complete(table["step"].to_numpy(), info, dump)
    return table


def _check_complete(steps, info, dump) -> None:
    """A dump cut at a frame boundary reads as a shorter run: its last frame must be within one
    dump interval of the run's last step (the first step plus the segment's strain in steps, from
    the run's record), else ``ValueError`` naming the dump and both steps."""
    last = info.first_step + round(info.segment.strain / (info.dt * info.rate))
    stride = int(np.min(np.diff(steps))) if len(steps) > 1 else last - info.first_step
    if last - int(steps[-1]) >= max(stride, 1):
        raise ValueError(
            f"{dump}: the last frame is at step {int(steps[-1])}, but the run's record "
            f"ends the segment at step {last}: the trajectory is truncated (frames missing at its end)"
        )


def _check_table(table: pd.DataFrame, source: str, value_columns=VALUE_COLUMNS) -> pd.DataFrame:
    required = (*METADATA_COLUMNS, "step", "strain", *value_columns)
    missing = [c for c in required if c not in table.columns]
    if missing:
        kind = "fabric table" if tuple(value_columns) == VALUE_COLUMNS else "table"
        raise ValueError(f"{source}: {kind} lacks column(s) {missing}")
    numeric = ["theta", "phi", "strain", *value_columns]
    values = table[numeric].to_numpy(dtype=float)
    if not np.all(np.isfinite(values)):
        bad = [c for c in numeric if not np.all(np.isfinite(table[c].to_numpy(dtype=float)))]
        raise ValueError(f"{source}: non-finite values in column(s) {bad}")
    return table


def write_fabric_table(table: pd.DataFrame, path: str | os.PathLike) -> Path:
    """Write a per-run (or concatenated) fabric table as CSV (format in the module docstring)."""
    path = Path(path)
    _check_table(table, str(path))
    written = table[[*TABLE_COLUMNS, *(c for c in MOMENT_COLUMNS if c in table.columns)]].copy()
    for column in MOMENT_COLUMNS:  # far below the seeds' scatter; a third of the file at full precision
        if column in written:
            written[column] = [f"{value:.{MOMENT_DIGITS}g}" for value in written[column]]
    written.to_csv(path, index=False)
    return path


def read_table_csv(path: str | os.PathLike, what: str, unrecorded_ok=()) -> pd.DataFrame:
    """A per-frame table CSV (fabric or stress) as written by pandas, its structure checked: the
    whole file ends with a newline (a cut file is refused, not read with a cut number), every
    header name is distinct and named, every row has the header's fields, every column is
    numeric and finite (the columns ``unrecorded_ok`` may instead be empty in every row).
    ``ValueError`` naming the file otherwise; ``FileNotFoundError`` if absent."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{what} not found: {path}")
    raw = path.read_bytes()
    if not raw.endswith(b"\n"):
        raise ValueError(f"{path}: the {what} does not end with a newline (cut or incomplete)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", pd.errors.ParserWarning)  # a row longer than the header
            table = pd.read_csv(io.BytesIO(raw), index_col=False, encoding="utf-8")  # the bytes checked above
    except (
        pd.errors.ParserError,
        pd.errors.ParserWarning,
        pd.errors.EmptyDataError,
        UnicodeDecodeError,
        ValueError,
    ) as err:
        raise ValueError(f"{path}: not a readable {what} ({type(err).__name__}: {err})") from None
    names = list(table.columns)
    bad = [str(n) for n in names if str(n).startswith("Unnamed:") or "." in str(n) and str(n).split(".")[0] in names]
    if bad or len(set(names)) != len(names):
        raise ValueError(f"{path}: the {what}'s header has empty or repeated column names {bad}")
    if len(raw.splitlines()) - 1 != len(table):
        raise ValueError(f"{path}: {len(raw.splitlines()) - 1} rows but {len(table)} read (blank or broken lines)")
    text = [str(c) for c in names if not pd.api.types.is_numeric_dtype(table[c])]
    if text:
        raise ValueError(f"{path}: non-numeric values in column(s) {text} of the {what}")
    missing = [
        str(c)
        for c in names
        if not np.isfinite(table[c].to_numpy(dtype=float)).all() and not (c in unrecorded_ok and table[c].isna().all())
    ]
    if missing:
        raise ValueError(f"{path}: empty or non-finite values in column(s) {missing} of the {what}")
    return table


def read_fabric_table(path: str | os.PathLike, moments: bool = False) -> pd.DataFrame:
    """Read a fabric-table CSV, checking its structure
    ([`read_table_csv`][suspension_fabric.analysis.tables.read_table_csv]) and columns; errors name the file. The
    columns of TABLE_COLUMNS and, with ``moments``, of MOMENT_COLUMNS too (NaN in a table made before they were
    recorded)."""
    table = _check_table(read_table_csv(path, "fabric table", unrecorded_ok=MOMENT_COLUMNS), str(path))
    if not moments:
        return table[list(TABLE_COLUMNS)]
    return table.reindex(columns=[*TABLE_COLUMNS, *MOMENT_COLUMNS])


def _seed_series(group: pd.DataFrame, theta: float) -> dict[int, pd.DataFrame]:
    series = {}
    for seed, rows in group.groupby("seed", sort=True):
        rows = rows.sort_values("strain", kind="stable")
        if rows["strain"].duplicated().any():
            raise ValueError(f"theta={theta}: seed {seed} has duplicated strain values")
        series[int(seed)] = rows
    return series


def aggregate_seeds(table: pd.DataFrame, value_columns=VALUE_COLUMNS) -> pd.DataFrame:
    """Mean and standard error over seeds per (theta, strain) of every value column
    (the fabric's by default; any per-frame table with the metadata columns works).

    Raises ``ValueError`` if the seeds of one theta do not share the same strain grid
    (compared with a relative tolerance of 1e-9) or the same N.
    """
    _check_table(table, "aggregate_seeds", value_columns)
    blocks = []
    for theta, group in table.groupby("theta", sort=True):
        series = _seed_series(group, theta)
        seeds = list(series)
        reference_seed = seeds[0]
        strain = series[reference_seed]["strain"].to_numpy()
        for seed in seeds[1:]:
            other = series[seed]["strain"].to_numpy()
            if len(other) != len(strain) or not np.allclose(other, strain, rtol=1e-9, atol=1e-12):
                raise ValueError(
                    f"theta={theta}: strain grid of seed {seed} ({len(other)} frames) differs from "
                    f"that of seed {reference_seed} ({len(strain)} frames)"
                )
        n_values = group["N"].unique()
        if len(n_values) != 1:
            raise ValueError(f"theta={theta}: seeds have different N {sorted(n_values.tolist())}")
        stacked = np.stack([series[s][list(value_columns)].to_numpy(dtype=float) for s in seeds])
        n_seeds = len(seeds)
        mean = stacked.mean(axis=0)
        if n_seeds > 1:
            sem = stacked.std(axis=0, ddof=1) / np.sqrt(n_seeds)
        else:
            sem = np.full_like(mean, np.nan)
        block = pd.DataFrame(
            {
                "theta": theta,
                "N": int(n_values[0]),
                "phi": float(group["phi"].mean()),
                "strain": strain,
                "n_seeds": n_seeds,
            }
        )
        for k, name in enumerate(value_columns):
            block[f"{name}_mean"] = mean[:, k]
            block[f"{name}_sem"] = sem[:, k]
        blocks.append(block)
    return pd.concat(blocks, ignore_index=True)


def integrated_autocorrelation_time(series, window_factor: float = 5.0) -> float:
    r"""Integrated autocorrelation time $\tau = 1/2 + \sum_{t \ge 1} \rho(t)$, in frames.

    $\rho$ is the normalised autocovariance (FFT, biased estimator); the sum is cut at
    Sokal's automatic window, the smallest $M$ with $M \ge c\,\tau(M)$, $c$ = ``window_factor``
    (or the whole series if none). $\tau = 1/2$ for uncorrelated data, so that the variance of
    the mean is $2\tau C(0)/n$; the result is clipped below at 1/2, and a constant series gives 1/2.
    """
    x = np.asarray(series, dtype=float)
    n = len(x)
    if n < 2:
        raise ValueError(f"need at least 2 values for an autocorrelation time, got {n}")
    x = x - x.mean()
    size = 1 << (2 * n - 1).bit_length()
    spectrum = np.fft.rfft(x, size)
    autocovariance = np.fft.irfft(spectrum * np.conj(spectrum), size)[:n] / n
    if autocovariance[0] <= 0:
        return 0.5
    rho = autocovariance / autocovariance[0]
    tau = 0.5 + np.cumsum(rho[1:])  # tau[M - 1] = tau(M)
    windows = np.arange(1, n)
    acceptable = np.flatnonzero(windows >= window_factor * tau)
    value = tau[acceptable[0]] if len(acceptable) else tau[-1]
    return float(max(value, 0.5))


def steady_state(
    table: pd.DataFrame,
    strain_min: float,
    strain_max: float,
    window_factor: float = 5.0,
    value_columns=VALUE_COLUMNS,
) -> pd.DataFrame:
    """Steady-state means over strain_min <= strain <= strain_max, one row per (theta, quantity).

    Columns: theta, quantity, mean, sem (correlation-aware, see module docstring),
    sem_between_seeds, tau_strain (mean over seeds of tau times the median strain
    spacing), n_frames (per seed, smallest), n_seeds, strain_min, strain_max.
    Raises ``ValueError`` if a seed has fewer than 2 frames in the window.
    """
    if not strain_max > strain_min:
        raise ValueError(f"empty strain window [{strain_min}, {strain_max}]")
    _check_table(table, "steady_state", value_columns)
    rows = []
    for theta, group in table.groupby("theta", sort=True):
        windows = {}
        for seed, series in _seed_series(group, theta).items():
            inside = series[(series["strain"] >= strain_min) & (series["strain"] <= strain_max)]
            if len(inside) < 2:
                raise ValueError(
                    f"theta={theta}: seed {seed} has {len(inside)} frame(s) in the strain window "
                    f"[{strain_min}, {strain_max}], need at least 2"
                )
            windows[seed] = inside
        n_seeds = len(windows)
        for name in value_columns:
            means, variances, taus, spacings = [], [], [], []
            for inside in windows.values():
                values = inside[name].to_numpy(dtype=float)
                tau = integrated_autocorrelation_time(values, window_factor)
                means.append(values.mean())
                variances.append(values.var() * 2.0 * tau / len(values))
                taus.append(tau)
                spacings.append(np.median(np.diff(inside["strain"].to_numpy())))
            means = np.array(means)
            rows.append(
                {
                    "theta": theta,
                    "quantity": name,
                    "mean": means.mean(),
                    "sem": np.sqrt(np.sum(variances)) / n_seeds,
                    "sem_between_seeds": means.std(ddof=1) / np.sqrt(n_seeds) if n_seeds > 1 else np.nan,
                    "tau_strain": float(np.mean(np.array(taus) * np.array(spacings))),
                    "n_frames": min(len(w) for w in windows.values()),
                    "n_seeds": n_seeds,
                    "strain_min": strain_min,
                    "strain_max": strain_max,
                }
            )
    return pd.DataFrame(rows)


def settle_strain(strain: np.ndarray, deviation: np.ndarray, tolerance: float = TOLERANCE) -> tuple[float, bool]:
    """First strain from which |deviation| <= tolerance to the end; (strain, settled).

    A series still outside the band at its last point is censored: (last strain, False).
    """
    settled_at, settled = settle_strains(strain, np.asarray(deviation, float)[None], tolerance)
    return float(settled_at[0]), bool(settled[0])


def settle_strains(
    strain: np.ndarray, deviations: np.ndarray, tolerance: float = TOLERANCE
) -> tuple[np.ndarray, np.ndarray]:
    """[`settle_strain`][suspension_fabric.analysis.tables.settle_strain] of many series at once
    (``deviations`` (..., len(strain)), e.g. a bootstrap's resampled curves): arrays (...) of the
    strains and of whether each settled."""
    strain, outside = np.asarray(strain, float), np.abs(np.asarray(deviations, float)) > tolerance
    if strain.ndim != 1 or outside.shape[-1:] != strain.shape:
        raise ValueError(f"strain and deviation lengths differ: {strain.shape} and {outside.shape}")
    # index just after the last point outside the band (0 if none is)
    after_last = np.where(outside.any(axis=-1), len(strain) - np.argmax(outside[..., ::-1], axis=-1), 0)
    settled = ~outside[..., -1]
    return np.where(settled, strain[np.minimum(after_last, len(strain) - 1)], strain[-1]), settled

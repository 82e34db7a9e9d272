r"""The suspension stress per dumped strain, in the paper frame of the current shear.

From the per-run stress table of a shear run ([`suspension_fabric.io.stressio`][suspension_fabric.io.stressio], one row
every ``table_strain``) to one row per trajectory frame (the fabric table's steps), with the
stress split into its parts, symmetric, per unit volume, in units of $\eta_f\dot\gamma$ (solvent
viscosity times shear rate), in the paper frame (e1', e2, e3') of the current shear
([`suspension_fabric.analysis.frames.simulation_to_paper`][suspension_fabric.analysis.frames.simulation_to_paper]). The
total is

$$
\sigma = \sigma^{\mathrm{contact}} + \sigma^{\mathrm{lubrication}} + \sigma^{\mathrm{kinetic}}
+ 2\hat{E} + 5\phi\,\hat{E},
$$

the particle parts each $-P$ of their LAMMPS pressure tensor (for the contacts and the lubrication
the pair virial of the particle stress, Batchelor, J. Fluid Mech. 41, 545 (1970)), $2\hat{E}$ the
solvent and $5\phi\,\hat{E}$ the Einstein term (Einstein, Ann. Phys. 34, 591 (1911), correcting
Ann. Phys. 19, 289 (1906)), with
$\hat{E} = E/\dot\gamma$ the normalised strain rate (its 12 component is 1/2 in simple shear) and
$\phi$ the volume fraction.

Parts (the total is their sum)
    ``contact``      -P of the granular contacts. LAMMPS tallies the virial sum (x_i - x_j)_a F_b
                     unsymmetrised; with T the summed torque of the contacts on the particles
                     (recorded by ``lubricate/sf``), sum_pairs r_ij x F_ij = -T exactly (LAMMPS
                     puts the tangential force at the lever arms a_i - overlap/2 and
                     a_j - overlap/2, which add up to |r_ij|), so the symmetric part is
                     P_xy + T_z/2V, P_xz - T_y/2V, P_yz + T_x/2V
                     ([`symmetric_contact_pressure`][suspension_fabric.analysis.stress.symmetric_contact_pressure]).
    ``lubrication``  -P of the pairwise lubrication forces (force dipole (x_i - x_j) F_ij),
                     symmetrised by the plugin.
    ``kinetic``      -P of the velocity fluctuations about the imposed flow (Reynolds stress;
                     O(St) = O(1/eta_f) small).
    ``solvent``      2 eta_f E: in units of eta_f gammadot, 1 on the 12 component.
    ``einstein``     the one-body stresslet of force- and torque-free spheres in the straining
                     flow, (20/3) pi eta_f a^3 E per sphere, i.e. 5 phi eta_f E: 2.5 phi on the
                     12 component. The force model has no one-body strain resistance (the drag
                     acts on force and torque only), so this term is added analytically (LF_DEM's
                     current source adds none); it makes the dilute limit eta_r = 1 + 2.5 phi + O(phi^2).

Recorded beside the parts, not summed into the total
    ``stresslet``    the pair lubrication stresslets (Jeffrey 1992 X^G, Y^G, Y^H, X^M, Y^M at the
                     force model's order and regularisation; ``simulation/lammps/plugin_source/lubrication.h``):
                     an alternative to ``lubrication`` for the same interactions, traceless, and
                     at this order the force dipole at contact distance without its trace.
                     NaN where the run did not record it (the stock force model, and tables
                     written before it was recorded;
                     [`read_stress_csv`][suspension_fabric.analysis.stress.read_stress_csv] fills it in for older CSVs).
                     ``total`` - ``lubrication`` + ``stresslet`` is the shear stress and normal stress differences as
                     the pair-stresslet codes report them (docs/gw_stress_relation.md, sections 2.2 and 2.5).

What each reported quantity contains (solvent, Einstein term, dipoles or stresslets) and which
combination the figures, the steady-state table and the G-W stress relation use is stated in
docs/gw_stress_relation.md, section 2.5, with how to compare with LF_DEM (no Einstein term,
stresslets with their trace). Which lubrication stress the study's tables use from the seed
aggregates on is the config key ``analysis.lubrication_stress``
([`with_lubrication_stress`][suspension_fabric.analysis.stress.with_lubrication_stress]): ``dipole`` (the default) keeps
the per-run tables as they are; ``stresslet`` puts the stresslets in the ``lubrication`` part and the total, and
recomputes eta_r, N1, N2 and Pi (the stresslets add nothing to Pi).

Each value at a frame is the mean of the table rows within half a frame interval of it
(rows with step in (s - h, s + h], h = half the frame spacing in steps; only rows after the
first step; the frame at the first step takes the rows in (s, s + max(h, row spacing)], so
at least the first row after it). The first row of every table is printed at set-up, before any step: its
lubrication virial belongs to the velocities read in (after a rotation they follow the old
flow), so it is never used. Derived columns, per unit $\eta_f\dot\gamma$: the relative viscosity
``eta_r``, the normal stress differences ``N1``, ``N2`` and the particle pressure ``Pi``,

$$
\eta_r = \sigma_{12}, \qquad N_1 = \sigma_{11} - \sigma_{22}, \qquad N_2 = \sigma_{22} - \sigma_{33},
\qquad \Pi = -\frac{1}{3}\operatorname{Tr}\left(\sigma^{\mathrm{contact}}
+ \sigma^{\mathrm{lubrication}} + \sigma^{\mathrm{kinetic}}\right).
$$
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.io.runinfo import read_run_info
from suspension_fabric.io.stressio import read_stress_table

from .constants import EINSTEIN_COEFFICIENT
from .frames import VECTOR_ORDER, simulation_to_paper, sym_to_vec
from .tables import read_fabric_table, read_table_csv

__all__ = [
    "PARTS",
    "PARTICLE_PARTS",
    "ALTERNATIVE_PARTS",
    "PAPER_COMPONENTS",
    "DERIVED_COLUMNS",
    "CONTACT_COLUMNS",
    "LOAD_COLUMNS",
    "STRESSLET_COLUMNS",
    "STRESS_VALUE_COLUMNS",
    "STRESS_TABLE_COLUMNS",
    "OPTIONAL_COLUMNS",
    "pressure_tensors",
    "symmetric_contact_pressure",
    "stress_parts",
    "stress_on_frames",
    "run_stress_table",
    "read_stress_csv",
    "LUBRICATION_STRESSES",
    "with_lubrication_stress",
    "recorded_value_columns",
    "STRESS_FLOAT_FORMAT",
    "derived_quantities",
]

PARTS: tuple[str, ...] = ("total", "contact", "lubrication", "kinetic", "solvent", "einstein")
PARTICLE_PARTS: tuple[str, ...] = ("contact", "lubrication", "kinetic")
#: Parts recorded beside ``PARTS`` and left out of the total (module docstring).
ALTERNATIVE_PARTS: tuple[str, ...] = ("stresslet",)
PAPER_COMPONENTS: tuple[str, ...] = VECTOR_ORDER
DERIVED_COLUMNS: tuple[str, ...] = ("eta_r", "N1", "N2", "Pi")
#: The contacts (overlapping pairs) beside the stress, per particle: ``Z_touching`` = 2 contacts / N
#: (not the near-contact Z of the fabric, which counts gaps below eps too) and ``Z_frictional`` = 2
#: frictional contacts / N, those that can carry friction (below the critical load a contact is
#: frictionless; all with rate-independent friction mu > 0, none with mu = 0); window means of the
#: counts the simulation records at every table row. The frictional fraction is their ratio, taken of
#: means (a window may hold no contact).
CONTACT_COLUMNS: tuple[str, ...] = ("Z_touching", "Z_frictional")
#: The critical load F_CL of the contact law (simulation units, at a shear rate of 1), window mean of
#: the table's per-row value: constant under an imposed rate, following the stress under stress control,
#: where the physical rate over gammadot_0 is 6 pi eta_f a^2 / F_CL at each row and its mean over time
#: 6 pi eta_f a^2 / (the mean of F_CL over strain) (suspension_fabric.evaluation.flow_curve); 0 without a
#: critical load, NaN in tables from before it was recorded.
LOAD_COLUMNS: tuple[str, ...] = ("critical_load",)
STRESS_VALUE_COLUMNS: tuple[str, ...] = (
    *DERIVED_COLUMNS,
    *(f"{part}_{c}" for part in (*PARTS, *ALTERNATIVE_PARTS) for c in PAPER_COMPONENTS),
    *CONTACT_COLUMNS,
    *LOAD_COLUMNS,
)
#: The values of the config key analysis.lubrication_stress
#: ([`with_lubrication_stress`][suspension_fabric.analysis.stress.with_lubrication_stress]).
LUBRICATION_STRESSES: tuple[str, ...] = ("dipole", "stresslet")
#: Columns that older per-run CSVs lack; [`read_stress_csv`][suspension_fabric.analysis.stress.read_stress_csv] gives
#: them as NaN.
STRESSLET_COLUMNS: tuple[str, ...] = tuple(f"{part}_{c}" for part in ALTERNATIVE_PARTS for c in PAPER_COMPONENTS)
OPTIONAL_COLUMNS: tuple[str, ...] = (*STRESSLET_COLUMNS, *CONTACT_COLUMNS, *LOAD_COLUMNS)
STRESS_TABLE_COLUMNS: tuple[str, ...] = ("seed", "theta", "N", "phi", "step", "strain", "n_rows", *STRESS_VALUE_COLUMNS)
#: Significant digits of the per-run stress CSV: far below the stress's frame-to-frame noise
#: (~1e-2 relative), and half the size of full round-trip precision.
STRESS_FLOAT_FORMAT = "%.9g"
_LAMMPS_ORDER = ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")
#: The stress table's counts per row (io.stressio), absent from tables written before them.
COUNT_COLUMNS: tuple[str, ...] = ("contacts", "frictional_contacts")


def pressure_tensors(table: dict[str, np.ndarray], prefix: str = "") -> np.ndarray:
    """(n, 3, 3) symmetric tensors from the six columns ``<prefix>pxx ... <prefix>pyz``."""
    names = [f"{prefix}{name}" for name in _LAMMPS_ORDER]
    missing = [name for name in names if name not in table]
    if missing:
        raise ValueError(
            f"stress table lacks column(s) {missing}: written before the stress "
            "parts were recorded in full; rerun the simulation"
        )
    xx, yy, zz, xy, xz, yz = (np.asarray(table[name], dtype=float) for name in names)
    return np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1), np.stack([xz, yz, zz], -1)], -2)


def symmetric_contact_pressure(table: dict[str, np.ndarray]) -> np.ndarray:
    """The contact pressure tensor with LAMMPS's off-diagonals (sum dx_a F_b / V, a < b)
    replaced by the symmetric ones, from the summed contact torque T (see the module docstring)."""
    for name in ("contact_torque_x", "contact_torque_y", "contact_torque_z", "vol"):
        if name not in table:
            raise ValueError(f"stress table lacks column {name!r}: rerun the simulation")
    pressure = pressure_tensors(table, "contact_")
    half = 0.5 / np.asarray(table["vol"], dtype=float)
    tx, ty, tz = (np.asarray(table[f"contact_torque_{k}"], dtype=float) * half for k in "xyz")
    for (a, b), correction in (((0, 1), tz), ((0, 2), -ty), ((1, 2), tx)):
        pressure[:, a, b] += correction
        pressure[:, b, a] = pressure[:, a, b]
    return pressure


def _imposed_strain_rate(rows: int, flow_angle) -> np.ndarray:
    """2 E / gammadot = f e2 + e2 f of the shear with flow f = (cos t, sin t, 0), gradient z, per
    row (``flow_angle`` one angle or one per row, radians)."""
    angle = np.broadcast_to(np.asarray(flow_angle, dtype=float), (rows,))
    flow = np.stack([np.cos(angle), np.sin(angle), np.zeros(rows)], axis=-1)
    gradient = np.array([0.0, 0.0, 1.0])
    return flow[:, :, None] * gradient[None, None, :] + gradient[None, :, None] * flow[:, None, :]


def stress_parts(
    table: dict[str, np.ndarray], *, eta_f: float, rate: float, phi: float, theta_deg: float
) -> dict[str, np.ndarray]:
    """Every part (and the total, and the alternative parts) per table row as (n, 3, 3) arrays in
    the frame of the flow at angle ``theta_deg`` (one angle, or one per row in rotary shear), in
    units of eta_f gammadot."""
    if not (eta_f > 0 and rate > 0):
        raise ValueError(f"eta_f and rate must be positive, got {eta_f}, {rate}")
    scale = -1.0 / (eta_f * rate)
    angle = np.radians(theta_deg)
    rows = len(table["step"])
    twice_e = _imposed_strain_rate(rows, angle)
    sim = {
        "contact": scale * symmetric_contact_pressure(table),
        "lubrication": scale * pressure_tensors(table, "lubrication_"),
        "kinetic": scale * pressure_tensors(table, "kinetic_"),
        "solvent": twice_e,
        "einstein": EINSTEIN_COEFFICIENT * phi * twice_e,
    }
    parts = {name: simulation_to_paper(value, angle) for name, value in sim.items()}
    parts["total"] = sum(parts[name] for name in sim)
    # absent columns (tables from before the stresslets were recorded) give NaN like the stock model
    stresslet = pressure_tensors(table, "stresslet_") if "stresslet_pxx" in table else np.full((rows, 3, 3), np.nan)
    parts["stresslet"] = simulation_to_paper(scale * stresslet, angle)
    return parts


def derived_quantities(frame: pd.DataFrame) -> pd.DataFrame:
    """Add eta_r, N1, N2 and Pi (module docstring) from the ``<part>_<ij>`` columns."""
    frame = frame.copy()
    frame["eta_r"] = frame["total_12"]
    frame["N1"] = frame["total_11"] - frame["total_22"]
    frame["N2"] = frame["total_22"] - frame["total_33"]
    trace = sum(frame[f"{part}_{c}"] for part in PARTICLE_PARTS for c in ("11", "22", "33"))
    frame["Pi"] = -trace / 3.0
    return frame


def stress_on_frames(
    table: dict[str, np.ndarray],
    frame_steps,
    *,
    first_step: int,
    eta_f: float,
    rate: float,
    phi: float,
    theta_deg: float,
    n_particles: int | None = None,
) -> pd.DataFrame:
    """Window means of every part's paper-frame components at each frame step (module docstring).

    Columns: step, n_rows (table rows averaged), ``<part>_<ij>`` for every part and component,
    the derived quantities and ``CONTACT_COLUMNS`` (from the counts of a table that has them, with
    ``n_particles`` the number of particles; else NaN). Raises ``ValueError`` for a frame with no
    table row near it.
    """
    steps = np.asarray(table["step"], dtype=np.int64)
    frame_steps = np.asarray(frame_steps, dtype=np.int64)
    if len(frame_steps) == 0:
        raise ValueError("no frame steps given")
    spacing = np.diff(frame_steps)
    if len(spacing) and np.any(spacing <= 0):
        raise ValueError("frame steps must increase")
    usable = steps > first_step  # the set-up row is never used
    row_spacing = int(np.min(np.diff(steps))) if len(steps) > 1 else 1
    half = (int(np.min(spacing)) if len(spacing) else row_spacing) / 2.0
    parts = stress_parts(table, eta_f=eta_f, rate=rate, phi=phi, theta_deg=theta_deg)
    columns = {"step": frame_steps, "n_rows": np.zeros(len(frame_steps), dtype=int)}
    shown = (*PARTS, *ALTERNATIVE_PARTS)
    values = {f"{part}_{c}": np.empty(len(frame_steps)) for part in shown for c in PAPER_COMPONENTS}
    # tables from before the contacts were counted give NaN
    counts = {name: np.asarray(table[name], dtype=float) for name in COUNT_COLUMNS if name in table}
    if counts and n_particles is None:
        raise ValueError("the stress table counts contacts: give n_particles for Z_touching")
    count_means = {name: np.full(len(frame_steps), np.nan) for name in COUNT_COLUMNS}
    loads = {name: np.asarray(table[name], dtype=float) for name in LOAD_COLUMNS if name in table}
    values.update({name: np.full(len(frame_steps), np.nan) for name in LOAD_COLUMNS})
    for k, step in enumerate(frame_steps):
        # the frame at the set-up step takes the rows just after it, at least the first one
        reach = max(half, row_spacing) if step == first_step else half
        inside = usable & (steps > step - half) & (steps <= step + reach)
        if not inside.any():
            raise ValueError(f"no stress-table row within {half:g} steps of frame step {step}")
        columns["n_rows"][k] = int(inside.sum())
        for part in shown:
            for c, value in zip(PAPER_COMPONENTS, sym_to_vec(parts[part][inside].mean(axis=0))):
                values[f"{part}_{c}"][k] = value
        for name, count in counts.items():
            count_means[name][k] = count[inside].mean()
        for name, load in loads.items():
            values[name][k] = load[inside].mean()
    values["Z_touching"] = 2.0 * count_means["contacts"] / (n_particles or 1)
    values["Z_frictional"] = 2.0 * count_means["frictional_contacts"] / (n_particles or 1)
    return derived_quantities(pd.DataFrame({**columns, **values}))


def run_stress_table(
    stress_table: str | os.PathLike,
    marker: str | os.PathLike,
    fabric_table: str | os.PathLike,
    *,
    eta_f: float | None = None,
) -> pd.DataFrame:
    """Stress per trajectory frame of one finished run (columns ``STRESS_TABLE_COLUMNS``).

    The frames, seed, theta, N and phi (for the Einstein part) are those of the run's fabric
    table ([`suspension_fabric.analysis.tables`][suspension_fabric.analysis.tables]), the time step, rate,
    first step, flow angle and (unless given) eta_f those of its completion ``marker``.
    """
    info = read_run_info(marker)
    eta_f = info.eta_f if eta_f is None else eta_f
    if eta_f is None:
        raise ValueError(f"{marker}: the run record has no variables.eta_f")
    fabric = read_fabric_table(fabric_table)
    segment = info.segment
    frame_angles = segment.flow_angle_at((fabric["step"].to_numpy() - info.first_step) * info.dt * info.rate)
    if not np.allclose(fabric["theta"], frame_angles):
        raise ValueError(
            f"{fabric_table}: the flow angles of its frames ({fabric['theta'].iloc[0]} ...) differ from "
            f"those of the run record's segment ({segment.flow_angle_deg} at its start) ({marker})"
        )
    phi = float(fabric["phi"].mean())
    if not Path(stress_table).read_bytes().endswith(b"\n"):  # a finished run's table is whole
        raise ValueError(
            f"{stress_table}: truncated: its last row ends without a newline (cut by a kill or a full disk)"
        )
    table = read_stress_table(stress_table)
    frames = stress_on_frames(
        table,
        fabric["step"].to_numpy(),
        first_step=info.first_step,
        eta_f=eta_f,
        rate=info.rate,
        phi=phi,
        theta_deg=segment.flow_angle_at((np.asarray(table["step"]) - info.first_step) * info.dt * info.rate),
        n_particles=int(fabric["N"].iloc[0]),
    )
    meta = fabric[["seed", "theta", "N", "phi", "step", "strain"]].reset_index(drop=True)
    out = pd.concat([meta, frames.drop(columns="step")], axis=1)
    return out[list(STRESS_TABLE_COLUMNS)]


def with_lubrication_stress(frame: pd.DataFrame, choice: str, source: str = "stress table") -> pd.DataFrame:
    """The stress table with ``choice`` (``LUBRICATION_STRESSES``) as its lubrication part.

    ``dipole``: unchanged. ``stresslet``: lubrication_ij = stresslet_ij, total_ij shifted by
    their difference, derived quantities recomputed; ``ValueError`` naming ``source`` if any
    stresslet value is missing (a run of the stock model, or from before they were recorded).
    """
    if choice not in LUBRICATION_STRESSES:
        raise ValueError(f"analysis.lubrication_stress must be one of {list(LUBRICATION_STRESSES)}, got {choice!r}")
    if choice == "dipole":
        return frame
    values = frame[list(STRESSLET_COLUMNS)]
    if values.isna().any().any():
        raise ValueError(
            f"{source}: analysis.lubrication_stress = stresslet, but {int(values.isna().any(axis=1).sum())} "
            "row(s) have no pair stresslets (runs of the stock force model, or from before the "
            "stresslets were recorded); rerun them or use dipole"
        )
    frame = frame.copy()
    for c in PAPER_COMPONENTS:
        frame[f"total_{c}"] += frame[f"stresslet_{c}"] - frame[f"lubrication_{c}"]
        frame[f"lubrication_{c}"] = frame[f"stresslet_{c}"]
    return derived_quantities(frame)


def recorded_value_columns(frame: pd.DataFrame, source: str = "stress tables") -> tuple[str, ...]:
    """``STRESS_VALUE_COLUMNS`` without the optional columns that no row of ``frame`` recorded
    (NaN throughout: runs from before the stresslets were recorded, or of the stock model); an
    optional column recorded in some rows only is an error naming ``source``, but for `LOAD_COLUMNS`:
    only runs at imposed rate can lack them (stress control came with them), where the critical load
    is the config's constant, so they are left out of every run with a message."""
    missing = []
    for column in OPTIONAL_COLUMNS:
        absent = frame[column].isna()
        if absent.all():
            missing.append(column)
        elif absent.any() and column in LOAD_COLUMNS:
            print(f"{source}: {column} recorded in some runs only (runs at imposed rate, a constant there): left out")
            missing.append(column)
        elif absent.any():
            seeds = sorted(frame.loc[absent, "seed"].unique().tolist()) if "seed" in frame else []
            raise ValueError(
                f"{source}: {column} is recorded in some runs but not in others (missing for seeds "
                f"{seeds}); rerun those runs so that all record it"
            )
    return tuple(c for c in STRESS_VALUE_COLUMNS if c not in missing)


def read_stress_csv(path: str | os.PathLike, lubrication_stress: str = "dipole") -> pd.DataFrame:
    """A per-run (or concatenated) stress CSV, its columns checked; errors name the file.

    ``OPTIONAL_COLUMNS`` missing from the file (written before they were recorded) come back NaN;
    ``lubrication_stress`` as in [`with_lubrication_stress`][suspension_fabric.analysis.stress.with_lubrication_stress].
    """
    path = Path(path)
    frame = read_table_csv(path, "stress table", unrecorded_ok=OPTIONAL_COLUMNS)
    for column in OPTIONAL_COLUMNS:
        if column not in frame.columns:
            frame[column] = np.nan
    missing = [c for c in STRESS_TABLE_COLUMNS if c not in frame.columns]
    if missing:
        raise ValueError(f"{path}: stress table lacks column(s) {missing}")
    return with_lubrication_stress(frame[list(STRESS_TABLE_COLUMNS)], lubrication_stress, str(path))

"""The per-run stress table written by the shear scripts (``stress.txt``): reading and writing.

A text table with one ``# step strain ...`` header line and one row per ``table_strain``
(``simulation/lammps/inputs/shear_run.lmp``): step, strain (from the first step of the run), the LAMMPS
pressure tensor pxx pyy pzz pxy pxz pyz and press (the stress is minus these; kinetic part
relative to the imposed flow), all six components of its kinetic, contact (granular) and
lubrication parts (``kinetic_pxx`` ... ``lubrication_pyz``), the summed contact torque
``contact_torque_x/y/z`` (for the symmetric contact stress,
[`suspension_fabric.analysis.stress`][suspension_fabric.analysis.stress]), ``stresslet_pxx ... stresslet_pyz`` (minus
the pair lubrication stresslets over the volume, beside the dipoles; absent from tables written before they were
recorded, NaN from the stock stand-in), the box volume ``vol``, tilts xz, yz and height lz, and the counts
``contacts`` (overlapping pairs) and ``frictional_contacts`` (of them those that can carry friction; both
absent from tables written before they were recorded), and ``critical_load``, the critical load of the
step (0 without one; under stress control it follows the stress; absent from older tables). The first row is printed at
set-up, before the first step. Tables written before the parts were recorded in full hold only the
contact and lubrication pxz, pyz and press; [`suspension_fabric.analysis.stress`][suspension_fabric.analysis.stress]
refuses them.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

__all__ = ["read_stress_table", "iter_table_rows", "UNRECORDED_COLUMNS"]

#: Columns a force model may leave NaN because it cannot record them: the stock stand-in
#: (forces_stock.lmp) cannot tell the contact torque from its lubrication's.
UNRECORDED_COLUMNS = (
    "contact_torque_x",
    "contact_torque_y",
    "contact_torque_z",
    *(f"stresslet_p{c}" for c in ("xx", "yy", "zz", "xy", "xz", "yz")),
)


def read_stress_table(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """The stress/tilt table of a shear run as {column: array}; a last row without its newline (a
    killed run) is left out; errors name the file."""
    path = Path(path)
    try:
        text = path.read_text()
    except UnicodeDecodeError as err:
        raise ValueError(f"{path}: not a text table ({err})") from None
    lines = text.splitlines(keepends=True)
    if not lines or not lines[0].startswith("#"):
        raise ValueError(f"{path}: expected a '# step strain ...' header line")
    if not lines[0].endswith("\n"):
        raise ValueError(f"{path}: the file ends inside its header line")
    names = lines[0][1:].split()
    rows = [line for line in lines[1:] if line.strip() and not line.startswith("#")]
    if rows and not rows[-1].endswith("\n"):  # a row cut by a killed run, as iter_table_rows
        rows = rows[:-1]
    try:
        data = np.loadtxt(rows, ndmin=2) if rows else np.empty((0, len(names)))
    except ValueError as err:
        raise ValueError(f"{path}: a malformed row ({err})") from None
    if data.shape[1] != len(names):
        raise ValueError(f"{path}: {data.shape[1]} columns but header names {len(names)}")
    return {name: data[:, k] for k, name in enumerate(names)}


def iter_table_rows(path: str | os.PathLike):
    """(step, line) of each complete data row of a stress table, as written; the header is skipped.

    A last line without its newline (a killed run) is left out.
    """
    with open(path) as handle:
        for line in handle:
            if line.startswith("#") or not line.strip():
                continue
            if not line.endswith("\n"):
                return
            yield int(line.split(maxsplit=1)[0]), line

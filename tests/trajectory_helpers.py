"""Two runs of the default engine that should follow one trajectory to the solver tolerance
(tests/simulation/test_lammps_mpi.py, test_local_solves.py)."""

from __future__ import annotations

import numpy as np

from suspension_fabric.io.dumpio import iter_dump_frames
from suspension_fabric.simulation.lammps import read_stress_table

STRESS_COLUMNS = ("pxz", "pxx", "pzz", "contact_pxz", "contact_pxx", "lubrication_pxz", "stresslet_pxz")


def last_positions(dump_file) -> np.ndarray:
    frame = list(iter_dump_frames(dump_file))[-1]
    return frame.positions[np.argsort(frame.ids)]


def assert_same_run(a, b) -> None:
    """Last positions within 1e-7 d, the same table steps, every stress part within 1e-6 of its
    largest value (and not zero)."""
    assert np.abs(last_positions(a.dump_file) - last_positions(b.dump_file)).max() < 1e-7
    first, second = read_stress_table(a.table_file), read_stress_table(b.table_file)
    np.testing.assert_array_equal(first["step"], second["step"])
    for column in STRESS_COLUMNS:
        scale = np.abs(first[column]).max()
        assert scale > 0.0, column
        assert np.abs(first[column] - second[column]).max() < 1e-6 * scale, column

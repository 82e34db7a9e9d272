"""Two runs of the default engine that should follow one trajectory to the solver tolerance
(tests/simulation/test_lammps_mpi.py, test_local_solves.py, test_initial_guess.py), and the dense
startup the solver's tests run."""

from __future__ import annotations

import numpy as np

from suspension_fabric.io.dumpio import iter_dump_frames
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, pack, read_stress_table, run_startup
from suspension_fabric.simulation.lammps.plugin import plugin_path

#: the solver tests' dense startup: N particles touching at phi = 0.50, STEPS steps of DT, and a
#: tolerance far below the step's own error, at which two solves agree to the solver tolerance
N, STEPS, DT = 500, 500, 1.0e-4
TIGHT_TOLERANCE = 1.0e-7
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


def dense_packing(folder):
    return pack(folder, N, phi=0.5, seed=3, gap_margin=0.0)


def newton_startup(folder, packing, steps: int = STEPS, dt: float = DT, *, ranks: int = 1, thermo_strain=None, **model):
    """A startup of ``packing`` (touching, dense) for ``steps`` steps of ``dt`` with the contact law
    solved by Newton passes at kn = 1.25e8 and every solve verified; ``model``: the other ForceModel
    keys (solver_tol, local_solve_fraction, initial_guess)."""
    return run_startup(
        folder,
        packing.data_file,
        steps * dt,
        settings=ShearSettings(
            dt=dt,
            dump_strain=steps * dt / 2,
            table_strain=steps * dt / 10,
            thermo_strain=thermo_strain or steps * dt / 100,
            restart_strain=steps * dt,
            max_stress_jitter=None,
            ranks=ranks,
        ),
        force_model=ForceModel(plugin=plugin_path(), contact_solve="newton", kn=1.25e8, verify_solve=True, **model),
        progress=None,
    )

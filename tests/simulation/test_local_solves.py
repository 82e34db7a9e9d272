"""Local solves in the implicit solve (fix hydro/implicit/sf `local`, run.local_solve_fraction),
real LAMMPS.

Once at most the given fraction of the atoms have a velocity error above tol (and the largest
is more than twice tol), the fix solves the system restricted to them and their pair neighbours
and restarts the global CG; the stopping rule, |M^-1 r| <= tol on every atom, is the same. So
with the solve converged far below the step's own error (tol 1e-7 in gammadot d) the trajectory
is the one of global iterations alone to the solver tolerance: over 500 steps of a dense
frictional packing (N = 500, phi = 0.50, touching from the start, the contact law solved by
Newton passes), positions within 1e-7 d and the stress within 1e-6 of its size, on 1 rank and
with each of 2 ranks solving its own patches; and every solve of these runs is verified (the fix
recomputes the residual from the solution and stops the run if it misses tol: a local update of
the residual that left out a neighbour's row fails there). At the default tol (1e-3) the local solves take
over global iterations: fewer of them per step. (At 1e-7 they do not: each restart loses the
conjugate directions, and the global iterations grow.)
"""

from __future__ import annotations

import numpy as np
import pytest
from trajectory_helpers import DT, STEPS, TIGHT_TOLERANCE, assert_same_run, dense_packing, newton_startup

from suspension_fabric.io.schema import schema_default
from suspension_fabric.simulation.lammps import ForceModel
from suspension_fabric.simulation.lammps.process import thermo_rows

pytestmark = pytest.mark.lammps

DEFAULT_TOLERANCE = schema_default("run", "solver_tol")
FRACTION = 0.02


def mean_global_iterations(run) -> float:
    """Mean of the thermo column v_solver_iterations (each step's CG iterations) after step 0."""
    return float(np.mean([row["v_solver_iterations"] for row in thermo_rows(run.log_file.read_text())[1:]]))


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The same startup with global iterations only, and with local solves on 1 and 2 ranks."""
    root = tmp_path_factory.mktemp("local")
    packing = dense_packing(root / "packing")
    cases = {
        "global": (0.0, 1, TIGHT_TOLERANCE),
        "local": (FRACTION, 1, TIGHT_TOLERANCE),
        "local_2_ranks": (FRACTION, 2, TIGHT_TOLERANCE),
        "global_default_tol": (0.0, 1, DEFAULT_TOLERANCE),
        "local_default_tol": (FRACTION, 1, DEFAULT_TOLERANCE),
    }
    return {
        name: newton_startup(
            root / name, packing, STEPS, DT, ranks=ranks, solver_tol=tolerance, local_solve_fraction=fraction
        )
        for name, (fraction, ranks, tolerance) in cases.items()
    }


def iterations(run) -> list[str]:
    return [line for line in run.log_file.read_text().splitlines() if line.strip()[:1].isdigit()]


@pytest.mark.parametrize("case", ["local", "local_2_ranks"])
def test_local_solves_keep_the_trajectory(runs, case):
    """Same trajectory to the bounds above; and the local solves ran (the thermo lines, with each
    step's CG iterations, differ from those of global iterations alone)."""
    assert_same_run(runs["global"], runs[case])
    assert iterations(runs[case]) != iterations(runs["global"])


def test_local_solves_take_over_global_iterations_at_the_default_tolerance(runs):
    """Fewer global CG iterations per step at tol 1e-3 (the thermo's per-step iterations, averaged)."""
    with_local = mean_global_iterations(runs["local_default_tol"])
    without = mean_global_iterations(runs["global_default_tol"])
    assert with_local < 0.9 * without, (with_local, without)


@pytest.mark.parametrize("fraction", [1.0, -0.1])
def test_a_fraction_outside_0_1_is_refused_before_lammps_starts(fraction):
    """A fraction of 1 or more (every atom) or below 0 is refused, naming the key and the range."""
    with pytest.raises(ValueError, match="local_solve_fraction must be in"):
        ForceModel(local_solve_fraction=fraction).variables()

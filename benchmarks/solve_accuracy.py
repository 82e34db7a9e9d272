"""What the solver's tolerance means for each preconditioner: one step of a point's engine from a sheared
state, solved with each preconditioner at each tolerance, against the same step solved with dilu at
REFERENCE_TOL (BENCHMARKS.md, "The two dear points made again").

The stopping rule is |z|_max <= tol with z = M^-1 r (M the preconditioner, r the residual): with block
Jacobi z is the residual scaled by each particle's own resistance, with dilu it is close to the error
A^-1 r itself, so the same tol is a looser solve with block Jacobi. Prints the largest and the rms
difference of the solved velocities (translational and angular, units of gammadot d and gammadot) from
the reference.

    .venv/bin/python benchmarks/solve_accuracy.py --point phi0.55_mu1 \
        --states 'results/corner_probe/seed*/startup/checkpoint.rst' \
        --config benchmarks/configs/campaign_corner_point.yaml

(the --config holds the point's engine the states were made with: the map's first datasets of the two points)
"""

from __future__ import annotations

import argparse
import glob
from pathlib import Path

import numpy as np
from contact_solve import engine_from_checkpoint

from suspension_fabric.study.campaign import campaign_points
from suspension_fabric.study.config import load_config

REPO = Path(__file__).resolve().parent.parent
REFERENCE_TOL = 1e-8
TOLERANCES = (1e-3, 3e-4, 1e-4)
PRECONDITIONERS = ("dilu", "jacobi")


def solved_velocities(state: Path, study: dict, preconditioner: str, tol: float) -> np.ndarray:
    """The velocities and angular velocities after one step of the point's engine, by atom ID."""
    run = {**study["run"], "preconditioner": preconditioner, "solver_tol": tol}
    lmp = engine_from_checkpoint(state, {**study, "run": run}, study["run"]["dt"])
    lmp.command("run 1 post no")
    n = lmp.get_natoms()
    order = np.argsort(lmp.numpy.extract_atom("id")[:n])
    velocities = np.hstack([lmp.numpy.extract_atom("v")[:n], lmp.numpy.extract_atom("omega")[:n]])[order]
    lmp.close()
    return velocities


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--point", required=True, help="the campaign point whose engine made the states")
    parser.add_argument("--states", required=True, help="glob of the checkpoints, one per seed")
    parser.add_argument("--config", type=Path, default=REPO / "config" / "campaign.yaml")
    args = parser.parse_args(argv)
    study = campaign_points(load_config(args.config))[args.point]
    print(f"{args.point}: one step (dt {study['run']['dt']:g}); difference from dilu at tol {REFERENCE_TOL:g}\n")
    print("| state | preconditioner | tol | largest | rms |\n|---|---|--:|--:|--:|")
    for state in sorted(glob.glob(args.states)):
        reference = solved_velocities(Path(state), study, "dilu", REFERENCE_TOL)
        for preconditioner in PRECONDITIONERS:
            for tol in TOLERANCES:
                error = np.abs(solved_velocities(Path(state), study, preconditioner, tol) - reference)
                print(
                    f"| {state} | {preconditioner} | {tol:g} | {error.max():.2e} | {np.sqrt((error**2).mean()):.2e} |",
                    flush=True,
                )


if __name__ == "__main__":
    main()

"""Engine acceptance run at production size (BENCHMARKS.md, "Acceptance run").

    .venv/bin/python benchmarks/acceptance_n500.py [--out results/acceptance_stiff]

N = 500, phi = 0.45, packing seed 2024, project default forces (paper eta_f, mu; stiff
kn = 1.25e9) and dt = 2e-7: startup to strain 5 with its checkpoint, then a shear rotation
by 90 degrees from that checkpoint for 0.5 strain, with every runner check on. Finished runs
in --out are reused. Prints wall times, largest overlaps, the steady-state fabric over
strain 2-5 with correlation-aware errors (tables.steady_state), the startup fabric at a few
strains, the G-W and modified fits to the steady n12 (and n11), and the rotated-frame
fabric after the rotation. ~80 min on one core.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from suspension_fabric.analysis.tables import run_fabric_table, steady_state
from suspension_fabric.models.gillissen_wilson import fit_gw, fit_modified
from suspension_fabric.simulation.lammps import (
    PACK_FILES,
    RUN_FILES,
    ForceModel,
    ShearSettings,
    is_complete,
    pack,
    run_rotation,
    run_startup,
)

COLUMNS = ("n11", "n22", "n33", "n12", "n13", "n23", "Z")
# the run documented in BENCHMARKS.md used explicit integration (benchmarks/engine_accuracy.py
# compares it with the implicit default)
EXPLICIT = ForceModel(integrator="explicit")
# its time step and output spacing (a frame every 0.01 strain, as when it was made)
SETTINGS = ShearSettings(dt=2e-7, dump_strain=0.01)


def marker(run_dir: Path) -> dict:
    return json.loads((run_dir / RUN_FILES["run_complete"]).read_text())


def fabric(run_dir: Path):
    return run_fabric_table(run_dir / RUN_FILES["trajectory"], run_dir / RUN_FILES["run_complete"], seed=2024)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("results/acceptance_stiff"))
    args = parser.parse_args()
    packing_dir, startup_dir, rotation_dir = (args.out / name for name in ("packing", "startup", "rotate_90"))
    if not is_complete(packing_dir):
        pack(packing_dir, 500, phi=0.45, seed=2024)
    if not is_complete(startup_dir):
        run_startup(
            startup_dir,
            packing_dir / PACK_FILES["data"],
            5.0,
            force_model=EXPLICIT,
            settings=SETTINGS,
            progress_interval=60,
        )
    if not is_complete(rotation_dir):
        run_rotation(
            rotation_dir,
            startup_dir / RUN_FILES["checkpoint"],
            90.0,
            0.5,
            force_model=EXPLICIT,
            settings=SETTINGS,
            progress_interval=60,
        )

    startup, rotation = marker(startup_dir), marker(rotation_dir)
    dt = float(startup["variables"]["dt"])
    print(f"N = 500, phi = 0.45, kn = {startup['variables']['kn']}, dt = {dt:g}, packing seed 2024")
    for name, info in (("startup", startup), ("rotation 90 deg", rotation)):
        results = info["results"]
        print(
            f"{name}: strain {results['strain']:g} (steps {results['first_step']}-{results['last_step']}), "
            f"wall {info['wall_time_s']:.0f} s = {info['wall_time_s'] / (500 * results['strain']):.2f} "
            f"core-s per particle per unit strain, largest overlap {results['max_overlap']:.2e} d"
        )

    table = fabric(startup_dir)
    steady = steady_state(table, 2.0, 5.0).set_index("quantity")
    print("\nsteady state over strain 2-5 (mean +- correlation-aware standard error, tau in strain):")
    print("| quantity | mean | sem | tau |\n|---|---|---|---|")
    for name in COLUMNS:
        row = steady.loc[name]
        print(f"| {name} | {row['mean']:.4f} | {row['sem']:.4f} | {row['tau_strain']:.3f} |")
    n11, n12 = steady.loc["n11", "mean"], steady.loc["n12", "mean"]
    modified = fit_modified(n11, n12, 0.45)
    print(
        f"fits to these means (paper: 10.9; 9.4 and 42.4): G-W beta = {fit_gw(n12, 0.45):.2f}; "
        f"modified beta = {modified.beta:.2f}, A = {modified.A:.1f}"
    )

    print("\nstartup fabric (frame nearest to each strain):")
    print("| strain | " + " | ".join(COLUMNS) + " |\n|" + "---|" * (len(COLUMNS) + 1))
    for gamma in (0.25, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0):
        k = int(np.argmin(np.abs(table["strain"].to_numpy() - gamma)))
        print(f"| {table['strain'].iloc[k]:.2f} | " + " | ".join(f"{table[c].iloc[k]:.3f}" for c in COLUMNS) + " |")

    rotated = fabric(rotation_dir)
    print("\nafter the 90 deg rotation (rotated frame e1' = -e3, e3' = e1; frame nearest to each strain):")
    print("| strain | " + " | ".join(COLUMNS) + " |\n|" + "---|" * (len(COLUMNS) + 1))
    for gamma in (0.0, 0.05, 0.1, 0.2, 0.3, 0.5):
        k = int(np.argmin(np.abs(rotated["strain"].to_numpy() - gamma)))
        print(f"| {rotated['strain'].iloc[k]:.2f} | " + " | ".join(f"{rotated[c].iloc[k]:.3f}" for c in COLUMNS) + " |")


if __name__ == "__main__":
    main()

"""Time-step check at production size (BENCHMARKS.md, "Time step at N = 500").

    .venv/bin/python benchmarks/timestep_study.py [--n 500] [--strain 2] [--dt 5e-7 2e-7] [--out results/kn_study]

One packing (N particles, phi 0.45, seed 2024, as the acceptance run), a startup at the
project's default forces (kn = 1.25e9) for each dt; runs already complete in --out are reused,
and a dt = 2e-7 startup in results/acceptance_stiff/startup is used if present. Prints, per dt
and strain bin, the near-contact fabric, P, -sigma_xz and the contact share; then the largest
stress jitter of each run (lammps.checks.stress_jitter; stable runs ~0.04) and its cost. The jitter
check is off on purpose: the large-dt run is meant to show it. ~10 min per unit strain at
N = 500 and dt = 5e-7, 25 min at 2e-7. The explicit integrator: this is its time-step check.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from suspension_fabric.analysis.fabric import FabricAnalysis
from suspension_fabric.simulation.lammps import (
    ForceModel,
    ShearSettings,
    is_complete,
    pack,
    read_stress_table,
    run_startup,
    stress_jitter,
)

BINS = [(0.2, 0.5), (0.5, 1.0), (1.0, 1.5), (1.5, 2.0), (2.0, 3.0), (3.0, 4.0), (4.0, 5.0)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("results/kn_study"))
    parser.add_argument("--n", type=int, default=500)
    parser.add_argument("--strain", type=float, default=2.0)
    parser.add_argument("--dt", type=float, nargs="+", default=[5e-7, 2e-7])
    args = parser.parse_args()
    packing_dir = args.out / f"packing_n{args.n}_seed2024"
    if not is_complete(packing_dir):
        pack(packing_dir, args.n, phi=0.45, seed=2024)
    acceptance = Path("results/acceptance_stiff/startup")
    print(
        f"N = {args.n}, phi = 0.45, packing seed 2024, default forces (kn = 1.25e9), startup to strain {args.strain}\n"
    )
    print("| dt | strain | n11 | n22 | n33 | n12 | Z | P | -sigma_xz | contact share |")
    print("|" + "---|" * 10)
    summary = []
    for dt in args.dt:
        run_dir = args.out / f"n{args.n}_kn1e9_dt{dt:.0e}"
        if dt == 2e-7 and args.n == 500 and is_complete(acceptance):
            run_dir = acceptance
        elif not is_complete(run_dir):
            run_startup(
                run_dir,
                packing_dir / "packing.data",
                args.strain,
                force_model=ForceModel(integrator="explicit"),
                settings=ShearSettings(dt=dt, dump_strain=0.01, max_overlap=1.0, max_stress_jitter=None),
                progress_interval=60,
            )
        marker = json.loads((run_dir / "run_complete.json").read_text())
        fabric = FabricAnalysis.from_dump(run_dir / "trajectory.dump", dt=dt).run().results
        table = read_stress_table(run_dir / "stress.txt")
        for lo, hi in BINS:
            if hi > args.strain + 1e-9:
                break
            frames = (fabric.strain > lo) & (fabric.strain <= hi)
            rows = (table["strain"] > lo) & (table["strain"] <= hi)
            print(
                f"| {dt:.0e} | {lo:g}-{hi:g} | "
                + " | ".join(f"{fabric[c][frames].mean():.3f}" for c in ("n11", "n22", "n33", "n12"))
                + f" | {fabric.coordination[frames].mean():.3f} | {table['press'][rows].mean():.0f} | "
                f"{-table['pxz'][rows].mean():.0f} | "
                f"{table['contact_pxz'][rows].mean() / table['pxz'][rows].mean():.2f} |"
            )
        jitter, lo, hi = stress_jitter(table)
        cost = marker["wall_time_s"] / (args.n * marker["results"]["strain"])
        summary.append(
            f"dt {dt:.0e}: largest stress jitter {jitter:.3g} (strain {lo:.3g}-{hi:.3g}); "
            f"{cost:.2f} core-s per particle per unit strain ({run_dir})"
        )
    print()
    print("\n".join(summary))


if __name__ == "__main__":
    main()

"""Contact-stiffness and time-step study of the startup fabric (BENCHMARKS.md, "Contact stiffness").

    .venv/bin/python benchmarks/stiffness_study.py [--out results/kn_study] [--n 100] [--strain 3]
                                                   [--seed 7] [--only-h-out]

One packing (N particles, phi 0.45, --seed), startup shear to --strain at the paper's
eta_f = 223, mu = 0.5, delta = 1e-3, for each (kn, dt, h_out) in RUNS. Runs already
complete in --out are reused. Prints, per run, the near-contact fabric (gap < 0.01 d_min)
averaged over the last unit of strain, the pressure P, the shear stress and the contact share
of it, overlaps, the stress jitter (lammps.checks.stress_jitter) and the contact relaxation time
(suspension_fabric.simulation.scales), then <nn>_12 versus strain. Failure checks are off on purpose
(the soft and the too-large-dt runs are the point); ~8 min per run at N = 100 and dt = 2e-7.
The explicit integrator throughout, as when the tables in BENCHMARKS.md were made.
--only-h-out runs just the two lubrication ranges at the default kn and dt (for more seeds).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from suspension_fabric.analysis.fabric import FabricAnalysis, near_contact_pairs
from suspension_fabric.simulation.lammps import (
    ForceModel,
    ShearSettings,
    is_complete,
    iter_dump_frames,
    pack,
    read_stress_table,
    run_startup,
    stress_jitter,
)
from suspension_fabric.simulation.scales import contact_relaxation_time

# (kn, dt, h_out): the stiffness ladder, the time step, and the lubrication range
RUNS = [
    (1.25e5, 2e-7, 0.05),
    (1.25e7, 2e-7, 0.05),
    (1.25e9, 2e-7, 0.05),
    (1.25e11, 2e-7, 0.05),
    (1.25e9, 5e-7, 0.05),
    (1.25e9, 1e-6, 0.05),
    (1.25e9, 2e-7, 0.1),
]
BINS = [(0.2, 0.5), (0.5, 1.0), (1.0, 1.5), (1.5, 2.0), (2.0, 2.5), (2.5, 3.0), (3.0, 4.0), (4.0, 5.0)]


def run_name(n: int, kn: float, dt: float, h_out: float) -> str:
    return f"n{n}_kn{kn:.0e}_dt{dt:.0e}" + ("" if h_out == 0.05 else f"_hout{h_out:g}")


def overlaps(dump: Path) -> tuple[float, float]:
    """Mean and largest overlap (in d) over all overlapping pairs of all frames."""
    values = []
    for frame in iter_dump_frames(dump):
        positions = frame.positions - np.asarray(frame.box.origin)
        pairs = near_contact_pairs(positions, frame.radii, frame.box.mdanalysis_dimensions(), eps=0.0)
        values.append(-pairs.gaps)
    values = np.concatenate(values) if values else np.zeros(1)
    return float(values.mean()), float(values.max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("results/kn_study"))
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--strain", type=float, default=3.0)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--only-h-out", action="store_true")
    args = parser.parse_args()
    packing_dir = args.out / (f"packing_n{args.n}" + ("" if args.seed == 7 else f"_seed{args.seed}"))
    if not is_complete(packing_dir):
        pack(packing_dir, args.n, phi=0.45, seed=args.seed)
    runs = [run for run in RUNS if run[:2] == (1.25e9, 2e-7)] if args.only_h_out else RUNS
    rows, series = [], {}
    for kn, dt, h_out in runs:
        name = run_name(args.n, kn, dt, h_out) + ("" if args.seed == 7 else f"_seed{args.seed}")
        run_dir = args.out / name
        if not is_complete(run_dir):
            run_startup(
                run_dir,
                packing_dir / "packing.data",
                args.strain,
                force_model=ForceModel(kn=kn, h_out=h_out, integrator="explicit"),
                settings=ShearSettings(dt=dt, dump_strain=0.02, max_overlap=1.0, max_stress_jitter=None),
                progress_interval=60,
            )
        marker = json.loads((run_dir / "run_complete.json").read_text())
        fabric = FabricAnalysis.from_dump(run_dir / "trajectory.dump", dt=dt).run().results
        table = read_stress_table(run_dir / "stress.txt")
        last = fabric.strain > args.strain - 1.0
        stress_rows = table["strain"] > args.strain - 1.0
        shear = -table["pxz"][stress_rows].mean()
        mean_overlap, max_overlap = overlaps(run_dir / "trajectory.dump")
        rows.append(
            (
                kn,
                dt,
                h_out,
                contact_relaxation_time(1.4, 1.4, ForceModel.eta_f, ForceModel.delta, kn),
                *(fabric[c][last].mean() for c in ("n11", "n22", "n33", "n12")),
                fabric.coordination[last].mean(),
                table["press"][stress_rows].mean(),
                shear,
                -table["contact_pxz"][stress_rows].mean() / shear,
                mean_overlap,
                max_overlap,
                stress_jitter(table)[0],
                marker["wall_time_s"],
            )
        )
        series[name] = [
            fabric.n12[(fabric.strain > lo) & (fabric.strain <= hi)].mean()
            if ((fabric.strain > lo) & (fabric.strain <= hi)).any()
            else float("nan")
            for lo, hi in BINS
        ]
    print(
        f"N = {args.n}, phi = 0.45, eta_f = 223, mu = 0.5, delta = 1e-3, packing seed {args.seed}, "
        f"startup to strain {args.strain}; fabric and stress averaged over strain "
        f"{args.strain - 1:g}-{args.strain:g}\n"
    )
    print(
        "| kn | dt | h_out | tau_LL (strain) | n11 | n22 | n33 | n12 | Z | P | -sigma_xz | contact share | "
        "mean overlap / d | max overlap / d | jitter | wall s |"
    )
    print("|" + "---|" * 16)
    for row in rows:
        print(
            "| {:.3g} | {:.0e} | {:g} | {:.2g} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.2f} | {:.0f} | {:.0f} | "
            "{:.2f} | {:.1e} | {:.1e} | {:.3g} | {:.0f} |".format(*row)
        )
    print("\n<nn>_12 averaged over strain bins:\n")
    shown = [b for b in BINS if b[1] <= args.strain + 1e-9]
    print("| run | " + " | ".join(f"{lo:g}-{hi:g}" for lo, hi in shown) + " |")
    print("|" + "---|" * (len(shown) + 1))
    for name, values in series.items():
        print(f"| {name} | " + " | ".join(f"{v:.3f}" for v in values[: len(shown)]) + " |")


if __name__ == "__main__":
    main()

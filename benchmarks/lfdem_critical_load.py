"""The project's flow curves under critical-load friction against LF_DEM's, on the same packings at the
same gammadot / gammadot_0: steady viscosity, frictional and overlapping contacts per particle.

For each packing (a LAMMPS data file of a flow-curve point's pack rule, e.g.
results/thickening/phi0.54_mu1_rate0.01/seed1/packing/packing.data) and each rate ratio, LF_DEM
(ryseto/LF_DEM at PEER_COMMIT, overdamped, explicit steps of at most 1e-3 radii; built as
``lfdem_comparison.py`` prints) shears it from rest to STRAIN at ``-r <ratio>cl``, its critical-load
friction (friction_model 2, forced by the ``cl`` unit): |F_t| <= mu (F_n - F_CL) above F_CL,
frictionless with the spring reset below, the project's law. The other physics are matched as in
``lfdem_comparison.py`` (lubrication, cutoff, regularisation, contact dashpot, kt = 2/7 kn, the spring
kn matched on small-small pairs) with the flow-curve campaign's kn and mu (config/thickening.yaml).
The project's run of the same packing and ratio is read from its finished study (the stress table of
results/<study>/<point>/seed<k>/startup), not run again.

Per run the mean over WINDOW of eta_r - 1 - 2.5 phi for the project (LF_DEM's viscosity has the
solvent and no Einstein term: its viscosity - 1), the contacts per particle and the frictional ones;
then per ratio the mean and standard error over packings of each code and of the paired difference.

    .venv/bin/python benchmarks/lfdem_critical_load.py --lfdem /path/to/LF_DEM --study results/thickening \\
        --phi 0.54 --seeds 1 2 --ratios 0.01 0.1
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd
from lfdem_comparison import BUILD_HELP, data_columns, reached_strain, start_lfdem, write_lfdem_inputs
from stresslet_vs_dipole import mean_se

from suspension_fabric.study.campaign import point_name
from suspension_fabric.study.config import load_config

STRAIN, WINDOW = 4.0, (2.0, 4.0)


def lfdem_run(
    binary: Path,
    packing: Path,
    folder: Path,
    ratio: float,
    engine: dict,
    strain: float,
    read_until: float | None = None,
) -> Path:
    """LF_DEM on ``packing`` at gammadot / gammadot_0 = ``ratio`` (``-r <ratio>cl``), one thread; a
    folder holding a finished run of the same input (its ``finished`` file) is kept as it is, and with
    ``read_until`` so is a run still going (or stopped) that has passed that strain."""
    finished = folder / "finished"
    if finished.exists() and finished.read_text() == f"{packing.resolve()} {ratio:g}cl {strain:g}\n":
        return folder
    if read_until is not None:
        if reached_strain(folder) >= read_until:
            return folder
        raise RuntimeError(f"{folder}: LF_DEM has reached strain {reached_strain(folder):g}, not {read_until:g}")
    folder.mkdir(parents=True, exist_ok=True)
    write_lfdem_inputs(packing, folder, strain, engine, friction_model=2)
    with open(folder / "lfdem.out", "w") as out:
        code = start_lfdem(binary, folder, out, f"{ratio:g}cl").wait()
    if code != 0:
        raise RuntimeError(f"{packing} at {ratio:g}cl: LF_DEM failed ({code}); see {folder}/lfdem.out")
    finished.write_text(f"{packing.resolve()} {ratio:g}cl {strain:g}\n")
    return folder


def lfdem_observables(folder: Path, window) -> dict[str, float]:
    path = next(folder.glob("data_*.dat"))
    columns, data = data_columns(path), np.loadtxt(path)
    strain = data[:, columns["cumulated shear strain"]]
    inside = (strain >= window[0]) & (strain <= window[1])
    return {
        "eta_r - 1 - 2.5 phi": float(data[inside, columns["viscosity"]].mean() - 1.0),
        "contacts per particle": float(data[inside, columns["contact number"]].mean()),
        "frictional contacts per particle": float(data[inside, columns["frictional contact number"]].mean()),
    }


def project_observables(table: Path, phi: float, window) -> dict[str, float]:
    frame = pd.read_csv(table)
    rows = frame[(frame["strain"] >= window[0] - 1e-9) & (frame["strain"] <= window[1] + 1e-9)]
    return {
        "eta_r - 1 - 2.5 phi": float(rows["eta_r"].mean() - 1.0 - 2.5 * phi),
        "contacts per particle": float(rows["Z_touching"].mean()),
        "frictional contacts per particle": float(rows["Z_frictional"].mean()),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lfdem", type=Path, default=os.environ.get("LF_DEM") or shutil.which("LF_DEM"))
    parser.add_argument("--config", type=Path, default=Path("config/thickening.yaml"))
    parser.add_argument("--study", type=Path, default=Path("results/thickening"))
    parser.add_argument("--phi", type=float, default=0.54)
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--ratios", type=float, nargs="+", default=[0.01, 0.1])
    parser.add_argument("--strain", type=float, default=STRAIN)
    parser.add_argument("--window", type=float, nargs=2, default=WINDOW)
    parser.add_argument("--jobs", type=int, default=2, help="LF_DEM runs at a time, one core each")
    parser.add_argument("--keep", type=Path, default=Path("benchmarks/lfdem_runs"), help="LF_DEM's run folders")
    parser.add_argument(
        "--read-running",
        action="store_true",
        help="read runs (finished or not) that have passed the window's end instead of running LF_DEM",
    )
    args = parser.parse_args(argv)
    if args.lfdem is None or not Path(args.lfdem).is_file():
        print(BUILD_HELP)
        sys.exit(0)
    config = load_config(args.config)
    mu = config["campaign"]["mu"][0]
    runs = {}
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for ratio in args.ratios:
            point = point_name(args.phi, mu, ratio)
            overrides = config["campaign"]["overrides"].get(point, {})
            kn = overrides.get("forces", {}).get("kn", config["forces"]["kn"])
            engine = {**config["forces"], "kn": kn, "kt": 2.0 / 7.0 * kn, "mu": mu, "rate": 1.0}
            for seed in args.seeds:
                run = args.study / point / f"seed{seed}"
                folder = args.keep / point / f"seed{seed}"
                peer = pool.submit(
                    lfdem_run,
                    args.lfdem.resolve(),
                    run / "packing/packing.data",
                    folder,
                    ratio,
                    engine,
                    args.strain,
                    args.window[1] if args.read_running else None,
                )
                runs[(ratio, seed)] = (run / "startup/stress.csv", peer)
    print(f"LF_DEM {args.lfdem}; phi {args.phi:g}, mu {mu:g}; strain {args.strain:g}, window {list(args.window)}")
    for ratio in args.ratios:
        pairs = [
            (project_observables(table, args.phi, args.window), lfdem_observables(peer.result(), args.window))
            for (r, _), (table, peer) in runs.items()
            if r == ratio
        ]
        heading = f"gammadot/gammadot_0 = {ratio:g} (mean +- s.e. over {len(pairs)} packings)"
        print(f"\n| {heading} | project | LF_DEM | project - LF_DEM (paired) |")
        print("|---|--:|--:|--:|")
        for name in pairs[0][0]:
            ours, theirs = [p[0][name] for p in pairs], [p[1][name] for p in pairs]
            print(f"| {name} | {mean_se(ours)} | {mean_se(theirs)} | {mean_se(np.subtract(ours, theirs))} |")


if __name__ == "__main__":
    main()

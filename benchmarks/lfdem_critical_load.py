"""The project's flow curves under critical-load friction against LF_DEM's, on the same packings at the
same gammadot / gammadot_0: steady viscosity, frictional and overlapping contacts per particle.

For each packing (a LAMMPS data file of a flow-curve point's pack rule, e.g.
results/thickening/phi0.54_mu1_rate0.01/seed1/packing/packing.data) and each rate ratio, LF_DEM
(ryseto/LF_DEM at PEER_COMMIT, overdamped, explicit steps of at most 1e-3 radii; built as
``lfdem_comparison.py`` prints) shears it from rest to STRAIN at ``-r <ratio>cl``, its critical-load
friction (friction_model 2, forced by the ``cl`` unit): |F_t| <= mu (F_n - F_CL) above F_CL,
frictionless with the spring reset below, the project's law. The other physics are matched as in
``lfdem_comparison.py`` (lubrication, cutoff, regularisation, contact dashpot, kt = 2/7 kn, the spring
kn matched on small-small pairs) with the config's kn and mu (config/thickening.yaml, or a config at
another kn: benchmarks/configs/lfdem_soft_kn.yaml). LF_DEM shears the packing with the gradient along
z, the project along y: the runs start from the same packing but do not follow one trajectory.
The project's run of the same packing and ratio is read from its finished study (the stress table of
<tables>/<point>/seed<k>/startup, ``--tables`` defaulting to the study), not run again.

Per run the mean over WINDOW of eta_r - 1 - 2.5 phi for the project (LF_DEM's viscosity has the
solvent and no Einstein term: its viscosity - 1), the contacts per particle and the frictional ones,
and LF_DEM's step in strain; then per ratio the mean and standard error over packings of each code and
of the difference per packing. ``--save`` adds the runs to a table (benchmarks/data/lfdem_critical_load.csv).
``--continue-from <keep folder>`` continues that folder's finished LF_DEM runs from their checkpoints to
``--strain`` instead of starting from rest, and ``--dt-max`` caps LF_DEM's step there (the table's
``lfdem_dt_max``; "own" for LF_DEM's own step):

    .venv/bin/python benchmarks/lfdem_critical_load.py --lfdem /path/to/LF_DEM --study results/thickening \\
        --tables data/thickening --continue-from benchmarks/lfdem_runs_stiff \\
        --keep benchmarks/lfdem_runs_stepcap/capped --dt-max 2e-6 --phi 0.54 --seeds 1 --ratios 0.1 \\
        --strain 0.55 --window 0.52 0.55

    .venv/bin/snakemake --cores 2 --configfile config/thickening.yaml -- \\
        results/thickening/phi0.54_mu1_rate0.1/seed1/packing/packing.data
    .venv/bin/python benchmarks/lfdem_critical_load.py --lfdem /path/to/LF_DEM --study results/thickening \\
        --tables data/thickening --keep benchmarks/lfdem_runs_stiff --phi 0.54 --seeds 1 --ratios 0.1 \\
        --strain 0.5 --window 0.3 0.5

Each kn needs its own ``--keep`` folder: a folder whose ``finished`` record names another packing or
strain is run again, over the run it holds.
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

from suspension_fabric.analysis.stress import run_stress_table
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
    continue_from: Path | None = None,
    dt_max: float | None = None,
) -> Path:
    """LF_DEM on ``packing`` at gammadot / gammadot_0 = ``ratio`` (``-r <ratio>cl``), one thread; a
    folder holding a finished run of the same input (its ``finished`` file) is kept as it is, and with
    ``read_until`` so is a run still going (or stopped) that has passed that strain.

    With ``continue_from`` (a finished run's folder) that run is copied into ``folder`` and continued
    from its last checkpoint (positions and tangential springs: LF_DEM's ``-c`` restart) to ``strain``;
    ``dt_max`` caps LF_DEM's step, in strain (its ``dt_max`` parameter in hydrodynamic time)."""
    finished = folder / "finished"
    record = f"{packing.resolve()} {ratio:g}cl {strain:g}"
    if continue_from is not None:
        record += f" from {continue_from.resolve()} dt_max {dt_max:g}" if dt_max else f" from {continue_from.resolve()}"
    if finished.exists() and finished.read_text() == record + "\n":
        return folder
    if read_until is not None:
        if reached_strain(folder) >= read_until:
            return folder
        raise RuntimeError(f"{folder}: LF_DEM has reached strain {reached_strain(folder):g}, not {read_until:g}")
    if continue_from is None:
        folder.mkdir(parents=True, exist_ok=True)
        write_lfdem_inputs(packing, folder, strain, engine, friction_model=2)
        inputs = None
    else:
        inputs = continuation(continue_from, folder, strain, dt_max)
    with open(folder / "lfdem.out", "w") as out:
        code = start_lfdem(binary, folder, out, f"{ratio:g}cl", inputs).wait()
    if code != 0:
        raise RuntimeError(f"{packing} at {ratio:g}cl: LF_DEM failed ({code}); see {folder}/lfdem.out")
    finished.write_text(record + "\n")
    return folder


def continuation(source: Path, folder: Path, strain: float, dt_max: float | None) -> list[str]:
    """``source``'s finished run copied into ``folder`` with its end moved to ``strain`` (and its step
    capped at ``dt_max``); returns LF_DEM's input arguments that restart it from the checkpoint. LF_DEM
    appends to the copied output files, so their rows before the checkpoint are the source's."""
    if not (source / "finished").exists():
        raise RuntimeError(f"{source}: no finished LF_DEM run to continue")
    if folder.exists():
        shutil.rmtree(folder)
    shutil.copytree(source, folder)
    (folder / "finished").unlink()
    lines = [line for line in (folder / "shear.txt").read_text().splitlines() if not line.startswith("dt_max")]
    lines = [f"time_end = {strain:g}h;" if line.startswith("time_end") else line for line in lines]
    if dt_max:
        lines.append(f"dt_max = {dt_max:g}h;")
    (folder / "shear.txt").write_text("\n".join(lines) + "\n")
    checkpoint = next(folder.glob("chk_*.dat")).name
    configuration = "conf_" + checkpoint.removeprefix("chk_")
    return ["-n", "-c", checkpoint, configuration, "shear.txt"]


def lfdem_observables(folder: Path, window) -> dict[str, float]:
    path = next(folder.glob("data_*.dat"))
    columns, data = data_columns(path), np.loadtxt(path)
    strain = data[:, columns["cumulated shear strain"]]
    inside = (strain >= window[0]) & (strain <= window[1])
    return {
        "eta_r - 1 - 2.5 phi": float(data[inside, columns["viscosity"]].mean() - 1.0),
        "contacts per particle": float(data[inside, columns["contact number"]].mean()),
        "frictional contacts per particle": float(data[inside, columns["frictional contact number"]].mean()),
        # its explicit step, set by the largest displacement (disp_max), in strain
        "strain per step": float((data[inside, columns["dt"]] * data[inside, columns["shear rate"]]).mean()),
    }


def project_observables(table: Path, phi: float, window) -> dict[str, float]:
    """The project's observables over ``window`` from a run's stress table, or, where the workflow
    refused to write it (a kn softer than the stiff limit, chosen on purpose to meet LF_DEM's step),
    from the run's own files by the same function."""
    if table.exists():
        frame = pd.read_csv(table)
    else:
        run = table.parent
        frame = run_stress_table(run / "stress.txt", run / "run_complete.json", run / "fabric.csv")
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
    parser.add_argument("--study", type=Path, default=Path("results/thickening"), help="the packings' study")
    parser.add_argument("--tables", type=Path, help="the project's runs (default: the study; or its dataset)")
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
    parser.add_argument("--save", type=Path, help="add each run's observables to this table (CSV)")
    parser.add_argument(
        "--continue-from",
        type=Path,
        help="continue the finished LF_DEM runs under this folder (a --keep folder) from their checkpoints",
    )
    parser.add_argument("--dt-max", type=float, help="with --continue-from: cap LF_DEM's step at this strain")
    args = parser.parse_args(argv)
    if args.lfdem is None or not Path(args.lfdem).is_file():
        print(BUILD_HELP)
        sys.exit(0)
    config = load_config(args.config)
    mu = config["campaign"]["mu"][0]
    runs, kn_of = {}, {}
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for ratio in args.ratios:
            point = point_name(args.phi, mu, ratio)
            overrides = config["campaign"]["overrides"].get(point, {})
            kn = overrides.get("forces", {}).get("kn", config["forces"]["kn"])
            engine = {**config["forces"], "kn": kn, "kt": 2.0 / 7.0 * kn, "mu": mu, "rate": 1.0}
            kn_of[ratio] = kn
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
                    args.continue_from / point / f"seed{seed}" if args.continue_from else None,
                    args.dt_max,
                )
                tables = (args.tables or args.study) / point / f"seed{seed}"
                runs[(ratio, seed)] = (tables / "startup/stress.csv", peer)
    print(f"LF_DEM {args.lfdem}; phi {args.phi:g}, mu {mu:g}; strain {args.strain:g}, window {list(args.window)}")
    window = f"{args.window[0]:g}-{args.window[1]:g}"
    observed = {
        (ratio, seed): (
            project_observables(table, args.phi, args.window),
            lfdem_observables(peer.result(), args.window),
        )
        for (ratio, seed), (table, peer) in runs.items()
    }
    for ratio in args.ratios:
        pairs = [pair for (r, _), pair in observed.items() if r == ratio]
        heading = f"gammadot/gammadot_0 = {ratio:g} (mean +- s.e. over {len(pairs)} packings)"
        print(f"\n| {heading} | project | LF_DEM | project - LF_DEM (per packing) |")
        print("|---|--:|--:|--:|")
        for name in pairs[0][0]:
            ours, theirs = [p[0][name] for p in pairs], [p[1][name] for p in pairs]
            print(f"| {name} | {mean_se(ours)} | {mean_se(theirs)} | {mean_se(np.subtract(ours, theirs))} |")
        print(f"| LF_DEM's strain per step | | {mean_se([p[1]['strain per step'] for p in pairs])} | |")
    # LF_DEM's step: its own (displacement-limited) or capped at --dt-max strain
    step = f"{args.dt_max:g}" if args.dt_max else "own"
    records = [
        {
            "kn": kn_of[ratio],
            "ratio": ratio,
            "seed": seed,
            "window": window,
            "lfdem_dt_max": step,
            "code": code,
            "quantity": name,
            "value": v,
        }
        for (ratio, seed), pair in observed.items()
        for code, values in zip(("project", "LF_DEM"), pair)
        for name, v in values.items()
    ]
    if args.save is not None:
        save_records(args.save, pd.DataFrame(records))


def save_records(path: Path, records: pd.DataFrame) -> None:
    """Add ``records`` to the table at ``path``, in place of its rows of the same kn, ratio, seed, window
    and LF_DEM step."""
    key = ["kn", "ratio", "seed", "window", "lfdem_dt_max"]
    if path.exists():
        kept = pd.read_csv(path, dtype={"window": str, "lfdem_dt_max": str})
        merged = kept.merge(records[key].drop_duplicates(), on=key, how="left", indicator=True)
        records = pd.concat([kept[(merged["_merge"] == "left_only").to_numpy()], records], ignore_index=True)
    records.sort_values(key + ["code", "quantity"]).to_csv(path, index=False, float_format="%.6g")


if __name__ == "__main__":
    main()

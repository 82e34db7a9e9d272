"""The lubrication stress two ways on the same packings: the force dipoles (the runs' virial)
and the pair stresslets of Jeffrey (1992) that the plugin records beside them.

For each packing (a LAMMPS data file of a finished study's pack rule), a startup shear with the
project's default engine (implicit hydrodynamics and contact springs, kn = 1.25e8, dt = 1e-4,
solver_tol 1e-3, eta_f = 223, mu = 0.5, delta = 1e-3, h_out = 0.05) to strain 3, stress table
every 0.01 strain; per run, the mean over strain [1.5, 3] of, in units of eta_f gammadot, the
12 (here xz) shear stress of: the lubrication force dipoles, the pair stresslets, the contacts,
and the particle pressure of the dipoles (the stresslets carry none); then the mean and standard
error over the packings. At leading order the stresslet of a pair is (a_i + a_j) times the
traceless symmetric part of n F (simulation/lammps/plugin_source/lubrication.h; tested), i.e. the dipole at
contact distance, so the two shear stresses should differ by O(h/(a_i + a_j)) only.

    .venv/bin/python benchmarks/stresslet_vs_dipole.py results/default/seed{1,2,3}/packing/packing.data
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
from pathlib import Path

import numpy as np

from suspension_fabric.io.resources import LAMMPS_SCRIPTS_DIR
from suspension_fabric.io.stressio import read_stress_table
from suspension_fabric.simulation.lammps.plugin import plugin_path
from suspension_fabric.simulation.lammps.process import lammps_command, launch

REPO = Path(__file__).resolve().parents[1]
ETA_F = 223.0
STRAIN, WINDOW = 3.0, (1.5, 3.0)
ENGINE = {
    "lubrication": "sf",
    "eta_f": ETA_F,
    "kn": 1.25e8,
    "mu": 0.5,
    "kt": 1.25e8 * 2 / 7,
    "delta": 1e-3,
    "h_out": 0.05,
    "newton_pair": "on",
    "integrator": "implicit",
    "contact_springs": "implicit",
    "preconditioner": "dilu",
    "solver_tol": 1e-3,
    "dt": 1e-4,
    "rate": 1.0,
}


def startup_run(packing: Path, folder: Path, strain: float = STRAIN, dump_strain: float = 0.5) -> Path:
    """A startup shear of ``packing`` to ``strain`` with ENGINE in ``folder`` (stress table every
    0.01 strain, trajectory every ``dump_strain``); the folder, or RuntimeError naming the log."""
    variables = {
        "lammps_dir": LAMMPS_SCRIPTS_DIR,
        "start_from": "packing",
        "start_file": packing.resolve(),
        **ENGINE,
        "plugin": plugin_path(),
        "dump_strain": dump_strain,
        "table_strain": 0.01,
        "thermo_strain": 0.1,
        "restart_strain": 10.0,
        "skin": 0.1,
        "strain_total": strain,
        "dump_file": "trajectory.dump",
        "table_file": "stress.txt",
        "checkpoint_file": "checkpoint.rst",
        "restart_file_a": "a.rst",
        "restart_file_b": "b.rst",
    }
    result = launch(
        lammps_command(LAMMPS_SCRIPTS_DIR / "segment.lmp", variables),
        folder,
        label=packing.parent.parent.name,
        strain_total=strain,
    )
    if result.returncode != 0:
        raise RuntimeError(f"{packing}: LAMMPS failed ({result.returncode}); see {folder}/log.lammps")
    return folder


def shear(packing: Path, folder: Path, strain: float = STRAIN, window=WINDOW) -> dict[str, float]:
    table = read_stress_table(startup_run(packing, folder, strain) / "stress.txt")
    inside = (table["strain"] >= window[0]) & (table["strain"] <= window[1])

    def mean(name):  # stress = -P, in units eta_f gammadot (gammadot = 1)
        return float(-np.mean(table[name][inside]) / ETA_F)

    return {
        "dipole_12": mean("lubrication_pxz"),
        "stresslet_12": mean("stresslet_pxz"),
        "contact_12": mean("contact_pxz"),
        "dipole_pressure": -(mean("lubrication_pxx") + mean("lubrication_pyy") + mean("lubrication_pzz")) / 3,
        "stresslet_trace": mean("stresslet_pxx") + mean("stresslet_pyy") + mean("stresslet_pzz"),
    }


def mean_se(values) -> str:
    """``mean +- standard error`` of ``values`` ("" if all are NaN; the error NaN for one value)."""
    values = np.asarray(values, dtype=float)
    if np.all(np.isnan(values)):
        return ""
    se = values.std(ddof=1) / np.sqrt(len(values)) if len(values) > 1 else float("nan")
    return f"{values.mean():.4g} +- {se:.2g}"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("packings", nargs="+", type=Path)
    parser.add_argument("--strain", type=float, default=STRAIN, help=f"startup strain (default {STRAIN:g})")
    parser.add_argument("--window", type=float, nargs=2, default=WINDOW, help="strain window of the means")
    args = parser.parse_args(argv)
    rows = []
    for packing in args.packings:
        folder = Path(tempfile.mkdtemp(prefix="stresslet_"))
        try:
            rows.append(shear(packing, folder, args.strain, args.window))
        finally:
            shutil.rmtree(folder, ignore_errors=True)
        print(packing, {k: round(v, 4) for k, v in rows[-1].items()}, flush=True)
    window = f"strain {args.window[0]:g}-{args.window[1]:g}"
    print(f"\n| quantity (eta_f gammadot, {window}) | mean +- s.e. over {len(rows)} packings |\n|---|--:|")
    for name in rows[0]:
        print(f"| {name} | {mean_se([row[name] for row in rows])} |")
    ratios = [round(row["stresslet_12"] / row["dipole_12"], 4) for row in rows]
    print(f"\nstresslet_12 / dipole_12 per packing: {ratios}")


if __name__ == "__main__":
    main()

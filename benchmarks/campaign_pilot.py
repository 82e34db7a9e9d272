"""Pilot runs that set each campaign point's contact stiffness and strains (config/campaign.yaml).

For every point of the campaign grid: seed 1's packing at the campaign's N, a startup to
``--strain`` on the campaign's base engine with the overlap bound lifted (a pilot only measures),
and from strain ``--strain``/2 on: the particle pressure Pi and eta_r (units eta_f gammadot), the
largest overlap, the LAMMPS wall time. From Pi it proposes the stiffness that keeps the point in
the stiff limit measured at the paper's point, kn / (eta_f Pi) >= STIFF_RATIO (BENCHMARKS.md,
"Engine speed II": kn = 1.25e8 was independent of kn at kn / P ~ 3e4 and the lubrication stress
moved at 1e4), as the base kn times a factor m of ``STIFFNESS_FACTORS`` with dt divided by the
same m (dt stays 0.024 of the contact relaxation time), and the cost that follows.

    .venv/bin/python benchmarks/campaign_pilot.py run       # ~10 min on one core
    .venv/bin/python benchmarks/campaign_pilot.py report    # the table of BENCHMARKS.md
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.analysis.stress import stress_parts
from suspension_fabric.io.stressio import read_stress_table
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, pack, run_startup
from suspension_fabric.study.campaign import campaign_points
from suspension_fabric.study.config import load_config

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
TABLE = HERE / "data" / "campaign_pilot.csv"
STIFF_RATIO = 3.0e4
#: kn and 1/dt multipliers that keep dt a whole fraction of the output strides
STIFFNESS_FACTORS = (1, 2, 4, 5, 10, 20, 25, 50, 100)
#: pressure scale the proposal provides for: the pilot's single seed fluctuates
SAFETY = 1.5


def measure(config_path: Path, workdir: Path, strain: float, points: list[str] | None) -> pd.DataFrame:
    rows = []
    for name, study in campaign_points(load_config(config_path)).items():
        if points and name not in points:
            continue
        where = workdir / name
        p = study["particles"]
        packing = pack(
            where / "packing",
            n_particles=p["n"],
            phi=p["phi"],
            seed=1,
            split=p["split"],
            fraction_large=p["fraction_large"],
            d_small=p["d_small"],
            d_large=p["d_large"],
            overwrite=True,
        )
        settings = ShearSettings.from_config(
            {**study, "run": {**study["run"], "max_overlap": 1.0, "max_stress_jitter": 1e9}}
        )
        result = run_startup(
            where / "startup",
            packing.data_file,
            strain,
            force_model=ForceModel.from_config(study),
            settings=settings,
            overwrite=True,
        )
        table = read_stress_table(where / "startup" / "stress.txt")
        parts = stress_parts(table, eta_f=study["forces"]["eta_f"], rate=1.0, phi=p["phi"], theta_deg=0.0)
        late = np.asarray(table["strain"]) >= strain / 2
        particle = sum(parts[part] for part in ("contact", "lubrication", "kinetic", "einstein"))
        pressure = -np.trace(particle[late], axis1=1, axis2=2) / 3.0
        rows.append(
            {
                "point": name,
                "phi": p["phi"],
                "mu": study["forces"]["mu"],
                "n": p["n"],
                "kn": study["forces"]["kn"],
                "dt": study["run"]["dt"],
                "strain": strain,
                "Pi": pressure.mean(),
                "eta_r": parts["total"][late, 0, 1].mean(),
                "max_overlap": result.max_overlap,
                "wall_s": result.wall_time,
            }
        )
        print(pd.DataFrame(rows[-1:]).to_string(index=False), flush=True)
    return pd.DataFrame(rows)


def proposal(pilot: pd.DataFrame, eta_f: float) -> pd.DataFrame:
    """Per point: the stiffness factor m (kn x m, dt / m) for kn / (eta_f Pi) >= STIFF_RATIO at
    SAFETY x the pilot's Pi, and the cost per particle and strain relative to the base engine."""
    table = pilot.copy()
    needed = STIFF_RATIO * eta_f * SAFETY * table["Pi"] / table["kn"]
    table["factor"] = [next((m for m in STIFFNESS_FACTORS if m >= need), np.nan) for need in needed]
    table["kn_proposed"] = table["kn"] * table["factor"]
    table["dt_proposed"] = table["dt"] / table["factor"]
    table["kn_over_eta_f_Pi"] = table["kn_proposed"] / (eta_f * table["Pi"])
    # core-s per particle per unit strain: the pilot's (its CG iterations at this point) x m steps
    table["cost_proposed"] = table["wall_s"] / (table["n"] * table["strain"]) * table["factor"]
    return table


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("command", choices=("run", "report"))
    parser.add_argument("--config", type=Path, default=REPO / "config" / "campaign.yaml")
    parser.add_argument("--workdir", type=Path, default=REPO / "results" / "campaign_pilot")
    parser.add_argument("--strain", type=float, default=2.0)
    parser.add_argument("--points", nargs="*", help="only these points (default: the whole grid)")
    args = parser.parse_args(argv)
    if args.command == "run":
        table = measure(args.config, args.workdir, args.strain, args.points)
        if TABLE.is_file() and args.points:  # keep the other points' rows
            old = pd.read_csv(TABLE)
            table = pd.concat([old[~old["point"].isin(table["point"])], table], ignore_index=True)
        TABLE.parent.mkdir(parents=True, exist_ok=True)
        table.sort_values(["phi", "mu"]).to_csv(TABLE, index=False, float_format="%.6g")
    if not TABLE.is_file():
        sys.exit(f"{TABLE} not found: run `{Path(__file__).name} run` first")
    eta_f = load_config(args.config)["forces"]["eta_f"]
    table = proposal(pd.read_csv(TABLE), eta_f)
    columns = [
        "point",
        "Pi",
        "eta_r",
        "max_overlap",
        "wall_s",
        "factor",
        "kn_proposed",
        "dt_proposed",
        "kn_over_eta_f_Pi",
        "cost_proposed",
    ]
    print(table[columns].to_markdown(index=False, floatfmt=".3g"))


if __name__ == "__main__":
    main()

"""The step error of the two contact solves over a short horizon (BENCHMARKS.md, "Engine III").

From one sheared state of a campaign point (seed 1's packing, a startup to strain 2 on the
point's own engine: the lagged solve at dt = 0.024 tau), each rung continues the shear for
``--strain`` at one (solve, dt) and records, per chunk of strain: the contact shear stress and
pressure (units eta_f gammadot), the sliding fraction of the contacts, the contact-state passes
and CG iterations per step and the wall time. Over so short a horizon the trajectories of
different steps stay close, so the difference from the reference rung (the point's own engine)
is the step error, not sampling noise.

    .venv/bin/python benchmarks/contact_solve.py run [--points phi0.53_mu0.5 ...]
    .venv/bin/python benchmarks/contact_solve.py report

tau = X(delta)/kn of two small spheres (suspension_fabric.simulation.scales.contact_relaxation_time).
The wall times are per unit strain, one LAMMPS process at a time; time it on an idle machine.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, pack, run_startup
from suspension_fabric.simulation.lammps.plugin import new_lammps
from suspension_fabric.simulation.scales import contact_relaxation_time
from suspension_fabric.study.campaign import campaign_points
from suspension_fabric.study.config import load_config

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
TABLE = HERE / "data" / "contact_solve.csv"
#: (solve, dt as a fraction of the point's tau); 0.024 lagged is the point's own engine
RUNGS = (
    ("lagged", 0.024),
    ("lagged", 0.24),
    ("newton", 0.024),
    ("newton", 0.12),
    ("newton", 0.24),
    ("newton", 0.6),
)
DEFAULT_POINTS = ("phi0.53_mu0.5", "phi0.55_mu0.5")
#: the engine of the points the campaign left out: kn from the pilot's stiffness factor
#: (campaign_pilot.py, m = 25) and the lagged solve's step, 0.024 tau
MISSING_POINT_ENGINE = {
    name: {"forces": {"kn": 3.125e9}, "run": {"dt": 4.0e-6}} for name in ("phi0.53_mu1", "phi0.55_mu0.5")
}
CHUNK = 0.005


def point_study(name: str, config: Path) -> dict:
    """The validated study of one point of the campaign's grid, the points it left out included."""
    campaign_config = load_config(config)
    campaign = campaign_config["campaign"]
    overrides = {**campaign["overrides"], **{k: v for k, v in MISSING_POINT_ENGINE.items() if k == name}}
    campaign = {**campaign, "points": [name], "not_run": {}, "overrides": overrides}
    return campaign_points({**campaign_config, "campaign": campaign})[name]


def sheared_state(study: dict, where: Path, tau: float) -> Path:
    """The checkpoint of seed 1's startup to strain 2 on the lagged solve at dt ~ 0.024 tau."""
    checkpoint = where / "startup" / "checkpoint.rst"
    if checkpoint.is_file():
        return checkpoint
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
    run = {**study["run"], "dt": rung_dt(0.024, tau), "max_overlap": 1.0, "max_stress_jitter": None}
    settings = ShearSettings.from_config({**study, "run": run})
    model = ForceModel.from_config({**study, "run": {**run, "contact_solve": "lagged"}})
    run_startup(where / "startup", packing.data_file, 2.0, force_model=model, settings=settings, overwrite=True)
    return checkpoint


def rung_dt(fraction: float, tau: float) -> float:
    """fraction x tau rounded down to 1, 2, 4 or 5 x 10^k, so that chunks are whole steps."""
    target = fraction * tau
    decade = 10.0 ** np.floor(np.log10(target))
    return max(m * decade for m in (1, 2, 4, 5) if m * decade <= target * (1 + 1e-9))


def continue_shear(checkpoint: Path, study: dict, solve: str, dt: float, strain: float) -> list[dict]:
    """Rows per chunk of strain: contact stress, sliding fraction, passes, iterations, wall time."""
    forces, run = study["forces"], study["run"]
    model = ForceModel.from_config({**study, "run": {**run, "contact_solve": solve}})
    variables = model.variables()
    lmp = new_lammps(load_plugin=False)
    lmp.commands_string(
        f"""
units lj
atom_style sphere
atom_modify map array
dimension 3
boundary p p p
plugin load {variables["plugin"]}
read_restart {checkpoint}
newton on on
pair_style lubricate/sf {variables["eta_f"]} {variables["delta"]} {variables["h_out"]} implicit
pair_coeff * *
fix integrate all hydro/implicit/sf tol {variables["solver_tol"]} precond {variables["preconditioner"]} &
    contacts {variables["kn"]} {variables["kt"]} {variables["mu"]} solve {solve}
neighbor 0.1 bin
neigh_modify delay 0 every 1 check yes
comm_modify mode single vel yes
fix shear all deform 1 xz erate 1.0 remap v flip yes
timestep {dt!r}
thermo_style custom step
run 0 post no
"""
    )
    scale = 1.0 / forces["eta_f"]
    steps = round(CHUNK / dt)
    rows = []
    for chunk in range(round(strain / CHUNK)):
        start = time.perf_counter()
        lmp.command(f"run {steps} post no")
        wall = time.perf_counter() - start
        vector = [lmp.extract_fix("integrate", 0, 1, k) for k in range(29)]
        volume = lmp.get_thermo("vol")
        contacts = vector[19]
        rows.append(
            {
                "strain": (chunk + 1) * CHUNK,
                "contact_12": -vector[7] / volume * scale,
                "contact_pressure": (vector[3] + vector[4] + vector[5]) / (3.0 * volume) * scale,
                "contacts": contacts,
                "sliding_fraction": vector[20] / contacts if contacts else np.nan,
                "passes_per_step": vector[18],
                "iterations_per_step": vector[1],
                "wall_per_strain": wall / CHUNK,
            }
        )
    lmp.close()
    return rows


def measure(points, config: Path, workdir: Path, strain: float) -> pd.DataFrame:
    rows = []
    for name in points:
        study = point_study(name, config)
        forces = study["forces"]
        tau = contact_relaxation_time(1.0, 1.0, forces["eta_f"], forces["delta"], forces["kn"])
        checkpoint = sheared_state(study, workdir / name, tau)
        for solve, fraction in RUNGS:
            dt = rung_dt(fraction, tau)
            for row in continue_shear(checkpoint, study, solve, dt, strain):
                rows.append({"point": name, "kn": forces["kn"], "tau": tau, "solve": solve, "dt": dt, **row})
            print(pd.DataFrame(rows[-1:]).to_string(index=False), flush=True)
    return pd.DataFrame(rows)


def report(table: pd.DataFrame) -> str:
    """Per point and rung: means over the horizon, and their difference from the reference rung."""
    lines = []
    for point, rows in table.groupby("point", sort=False):
        means = rows.groupby(["solve", "dt"], sort=False).agg(
            tau=("tau", "first"),
            contact_12=("contact_12", "mean"),
            contact_pressure=("contact_pressure", "mean"),
            sliding_fraction=("sliding_fraction", "mean"),
            passes_per_step=("passes_per_step", "last"),
            iterations_per_step=("iterations_per_step", "last"),
            wall_per_strain=("wall_per_strain", "mean"),
        )
        reference = means.iloc[0]
        means.insert(0, "dt_over_tau", [dt / tau for (_, dt), tau in zip(means.index, means["tau"])])
        for column in ("contact_12", "contact_pressure"):
            means[f"{column}_change"] = means[column] / reference[column] - 1.0
        means["speed_up"] = reference["wall_per_strain"] / means["wall_per_strain"]
        lines.append(
            f"{point}: kn = {rows['kn'].iloc[0]:.4g}, tau = {reference['tau']:.3g}; means over strain "
            f"0-{rows['strain'].max():g} after the sheared state"
        )
        lines.append(means.drop(columns="tau").reset_index().to_markdown(index=False, floatfmt=".4g"))
        lines.append("")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("command", choices=("run", "report"))
    parser.add_argument("--config", type=Path, default=REPO / "config" / "campaign.yaml")
    parser.add_argument("--workdir", type=Path, default=REPO / "results" / "contact_solve")
    parser.add_argument("--points", nargs="*", default=list(DEFAULT_POINTS))
    parser.add_argument("--strain", type=float, default=0.05)
    args = parser.parse_args(argv)
    if args.command == "run":
        table = measure(args.points, args.config, args.workdir, args.strain)
        TABLE.parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(TABLE, index=False, float_format="%.6g")
    print(report(pd.read_csv(TABLE)))


if __name__ == "__main__":
    main()

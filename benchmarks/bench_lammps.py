"""Speed and time-step benchmark of the LAMMPS force models, side by side.

    .venv/bin/python benchmarks/bench_lammps.py [--steps 4000] [--repeats 3]

N = 500 bidisperse spheres (d = 1 and 1.4, 50:50 by number), phi = 0.45, mu = 0.5,
kn = 1.25e9 (project default, stiff limit), kt = 2/7 kn, eta_f = 223, simple shear xz erate 1 (strain rate 1), one core:
  (i)  granular + lubricate/sf + fix stokes/sf (this project's plugin), newton on and off;
  (ii) granular + stock lubricate/poly (flagfld 1 supplies the one-body drag), newton off
       (lubricate/poly requires it).
Both use the reduced-gap cutoffs delta = 1e-3, h_out = 0.05 (lubricate/poly gets them as
centre distances per type pair, r = (a_i + a_j)(1 + xi/2)), the same dt and skin 0.1.
Then a dt ladder over 0.02 strain: a dt is "stable" if no atom is lost, nothing is NaN, the
largest overlap stays below 2% of the small diameter and the largest non-affine speed below
10 gammadot d.  The packing is made here: random insertion at phi ~ 0.06, compression with
soft damped contacts, relaxation.
Timings on a shared 2-core machine are noisy (best of --repeats is reported).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from suspension_fabric.simulation.lammps.plugin import new_lammps  # noqa: E402

N_ATOMS = 500
PHI = 0.45
D_SMALL, D_LARGE = 1.0, 1.4
MU, KN = 0.5, 1.25e9
KT = 2.0 / 7.0 * KN
ETA_F = 223.0
DELTA, H_OUT = 1e-3, 0.05
SKIN = 0.1
SHEAR_RATE = 1.0


def box_length() -> float:
    n_half = N_ATOMS // 2
    particle_volume = n_half * np.pi / 6.0 * (D_SMALL**3 + D_LARGE**3)
    return (particle_volume / PHI) ** (1.0 / 3.0)


def make_packing(path: Path, seed: int = 2024) -> None:
    """Random insertion in a dilute box, damped compression to phi, relaxation; write_data."""
    final = box_length()
    start = 2.5 * final
    lmp = new_lammps(load_plugin=False)
    lmp.commands_string(f"""
units lj
atom_style sphere
boundary p p p
region box prism 0 {start} 0 {start} 0 {start} 0 0 0
create_box 2 box
create_atoms 2 random {N_ATOMS // 2} {seed} NULL overlap {D_LARGE} maxtry 1000
create_atoms 1 random {N_ATOMS - N_ATOMS // 2} {seed + 1} NULL overlap {0.5 * (D_SMALL + D_LARGE)} maxtry 1000
set type 1 diameter {D_SMALL}
set type 2 diameter {D_LARGE}
set group all density 1.0
comm_modify vel yes
neighbor 0.3 bin
pair_style granular
pair_coeff * * hooke 1.0e4 0.5 tangential linear_nohistory 0 0
fix damp all viscous 5.0
fix nve all nve/sphere
fix squeeze all deform 1 x final 0 {final} y final 0 {final} z final 0 {final} remap x
timestep 1e-3
run 20000
unfix squeeze
run 5000
write_data {path}
""")
    assert lmp.get_natoms() == N_ATOMS
    lmp.close()


def force_model_commands(model: str) -> str:
    if model == "sf":
        return f"""
pair_style hybrid/overlay granular lubricate/sf {ETA_F} {DELTA} {H_OUT}
pair_coeff * * granular hooke {KN} 0 tangential linear_history {KT} 0 {MU}
pair_coeff * * lubricate/sf
fix drag all stokes/sf {ETA_F}
"""
    if model == "stock":
        cut = {(1, 1): D_SMALL, (1, 2): 0.5 * (D_SMALL + D_LARGE), (2, 2): D_LARGE}
        lines = [
            f"pair_style hybrid/overlay granular lubricate/poly {ETA_F} 1 1 "
            f"{D_LARGE * (1 + 0.5 * DELTA)} {D_LARGE * (1 + 0.5 * H_OUT)} 1 0",
            f"pair_coeff * * granular hooke {KN} 0 tangential linear_history {KT} 0 {MU}",
        ]
        for (i, j), radsum in cut.items():
            lines.append(f"pair_coeff {i} {j} lubricate/poly {radsum * (1 + 0.5 * DELTA)} {radsum * (1 + 0.5 * H_OUT)}")
        return "\n".join(lines) + "\n"
    raise ValueError(model)


def sheared_system(packing: Path, model: str, newton: str, dt: float):
    lmp = new_lammps(load_plugin=(model == "sf"))
    lmp.commands_string(f"""
units lj
atom_style sphere
newton {newton}
comm_modify vel yes
read_data {packing}
neighbor {SKIN} bin
{force_model_commands(model)}
fix nve all nve/sphere
fix shear all deform 1 xz erate {SHEAR_RATE} remap v flip yes
timestep {dt}
thermo 0
""")
    return lmp


def time_model(packing: Path, model: str, newton: str, dt: float, steps: int, repeats: int):
    best = np.inf
    for _ in range(repeats):
        lmp = sheared_system(packing, model, newton, dt)
        lmp.command("run 200 post no")  # warm-up: neighbour lists, history
        start = time.perf_counter()
        lmp.command(f"run {steps} post no")
        best = min(best, time.perf_counter() - start)
        lmp.close()
    atom_steps_per_s = N_ATOMS * steps / best
    strain = steps * dt * SHEAR_RATE
    core_s_per_particle_strain = best / (N_ATOMS * strain)
    return atom_steps_per_s, core_s_per_particle_strain


def stability_check(lmp) -> tuple[bool, float, float]:
    """(ok, max overlap / d_small, max non-affine speed) of the current state."""
    nlocal = lmp.extract_global("nlocal")
    x = lmp.numpy.extract_atom("x")[:nlocal].copy()
    v = lmp.numpy.extract_atom("v")[:nlocal].copy()
    radius = lmp.numpy.extract_atom("radius")[:nlocal].copy()
    boxlo, boxhi, xy, yz, xz, *_ = lmp.extract_box()
    shape = np.array([[boxhi[0] - boxlo[0], xy, xz], [0, boxhi[1] - boxlo[1], yz], [0, 0, boxhi[2] - boxlo[2]]])
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
        return False, np.inf, np.inf
    frac = np.linalg.solve(shape, (x - boxlo).T).T
    dfrac = frac[:, None, :] - frac[None, :, :]
    dfrac -= np.round(dfrac)
    dist = np.linalg.norm(dfrac @ shape.T, axis=-1)
    gap = dist - (radius[:, None] + radius[None, :])
    np.fill_diagonal(gap, np.inf)
    max_overlap = max(0.0, -gap.min()) / D_SMALL
    affine = np.zeros_like(v)
    affine[:, 0] = SHEAR_RATE * (x[:, 2] - boxlo[2])
    max_speed = np.linalg.norm(v - affine, axis=1).max()
    return max_overlap < 0.02 and max_speed < 10.0, max_overlap, max_speed


def dt_ladder(packing: Path, model: str, newton: str, ladder, strain: float):
    rows = []
    for dt in ladder:
        lmp = sheared_system(packing, model, newton, dt)
        try:
            lmp.command(f"run {int(round(strain / dt))} post no")
            ok, overlap, speed = stability_check(lmp)
            lost = N_ATOMS - lmp.get_natoms()
            ok = ok and lost == 0
        except Exception as error:  # LAMMPS aborts on lost atoms
            ok, overlap, speed = False, np.nan, np.nan
            lost = "run aborted: " + str(error).splitlines()[0].removeprefix("ERROR: ")[:30]
        lmp.close()
        rows.append((dt, ok, overlap, speed, lost))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=4000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--dt", type=float, default=1e-6)
    parser.add_argument("--ladder-strain", type=float, default=0.02)
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        packing = Path(tmp) / "packing.data"
        make_packing(packing)
        print(
            f"N = {N_ATOMS}, phi = {PHI}, box = {box_length():.3f}, dt = {args.dt:g}, "
            f"{args.steps} steps, best of {args.repeats}, 1 core, OMP_NUM_THREADS=1"
        )
        print()
        print("| force model | newton | atom-steps/s | core-s per particle per unit strain |")
        print("|---|---|---|---|")
        speeds = {}
        for model, newton, label in [
            ("sf", "on", "granular + lubricate/sf + stokes/sf"),
            ("sf", "off", "granular + lubricate/sf + stokes/sf"),
            ("stock", "off", "granular + lubricate/poly (stock)"),
        ]:
            rate, cost = time_model(packing, model, newton, args.dt, args.steps, args.repeats)
            speeds[(model, newton)] = rate
            print(f"| {label} | {newton} | {rate:.3g} | {cost:.3g} |")
        print()
        print(
            "speed ratio plugin/stock (atom-steps/s): "
            f"newton on {speeds[('sf', 'on')] / speeds[('stock', 'off')]:.2f}, "
            f"newton off {speeds[('sf', 'off')] / speeds[('stock', 'off')]:.2f}"
        )
        print()
        ladder = [1e-6, 1.5e-6, 2e-6, 2.5e-6, 3e-6, 5e-6]
        print(
            f"dt ladder over strain {args.ladder_strain} (stable = no lost atoms, max overlap "
            "< 0.02 d, max non-affine speed < 10):"
        )
        print()
        print("| force model | dt | stable | max overlap / d | max non-affine speed | lost atoms |")
        print("|---|---|---|---|---|---|")
        largest = {}
        for model, newton in [("sf", "on"), ("stock", "off")]:
            for dt, ok, overlap, speed, lost in dt_ladder(packing, model, newton, ladder, args.ladder_strain):
                print(f"| {model} | {dt:g} | {'yes' if ok else 'no'} | {overlap:.3g} | {speed:.3g} | {lost} |")
                if ok:
                    largest[model] = max(largest.get(model, 0.0), dt)
        print()
        for model in ("sf", "stock"):
            print(f"largest stable dt ({model}, eta_f = {ETA_F:g}, delta = {DELTA:g}): {largest.get(model, 'none')}")


if __name__ == "__main__":
    main()

"""The project against the overdamped peer code LF_DEM on the same packings: fabric and stress.

For each packing (a LAMMPS data file of a finished study's pack rule, N = 500 at phi = 0.45), a
startup shear to strain STRAIN twice:

- the project: the default engine of ``stresslet_vs_dipole.py`` (implicit lubrication and contact
  springs, kn = 1.25e8, dt = 1e-4, eta_f = 223, mu = 0.5, delta = 1e-3, h_out = 0.05, inertia
  with St = 1/223);
- LF_DEM (ryseto/LF_DEM, overdamped, explicit Heun steps of at most 1e-3 radii): the same
  packing (lengths doubled: its unit is the small radius), lubrication ``tangential`` (squeeze
  1/xi, shear, pump and rotation log(1/xi), the project's resistances) with the same outer cutoff
  on xi = 2h/(a_i + a_j) and the same regularisation xi + delta; its contact dashpot set to the
  lubrication at xi = 0 (relaxation time -1, as the project's overlapping pairs); Coulomb friction
  mu on the spring force, kt = 2/7 kn. Its spring is kn_LF a_bar overlap with a_bar the pair's
  mean radius, the project's kn overlap for every pair: kn_LF = kn / (6 pi eta_f gammadot a_bar)
  is matched on small-small pairs (small-large and large-large pairs 1.2 and 1.4 times stiffer;
  both are in the stiff limit, BENCHMARKS.md "Contact stiffness").

Per run, the mean over strain WINDOW of, in units of eta_f gammadot: the fabric (near contacts,
gap < 0.01 min(d_i, d_j), per particle, paper frame e1 flow, e2 gradient, e3 vorticity; LF_DEM's
from its interaction snapshots with its own gaps), the shear viscosity without the Einstein term
(LF_DEM has none), N1, N2 and the particle pressure, and the parts as each code groups them;
then the mean and standard error over packings of each code and of the paired difference.
The conventions behind each row are in BENCHMARKS.md "Against the peer code LF_DEM" and
docs/gw_stress_relation.md, section 2.5.

    .venv/bin/python benchmarks/lfdem_comparison.py --lfdem /path/to/LF_DEM \
        results/default/seed{1,2,3}/packing/packing.data
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
from stresslet_vs_dipole import ENGINE, ETA_F, STRAIN, WINDOW, mean_se, startup_run

from suspension_fabric.analysis.fabric import FabricAnalysis
from suspension_fabric.analysis.stress import stress_parts
from suspension_fabric.io.stressio import read_stress_table

PEER_COMMIT = "00fa7cc0"
EPS = 0.01  # near contact: gap < EPS * min(d_i, d_j), the project's default
BUILD_HELP = f"""LF_DEM was not found (give --lfdem PATH or set LF_DEM=PATH). To build it (about a minute):
    apt-get install libsuitesparse-dev
    git clone https://github.com/ryseto/LF_DEM && cd LF_DEM/LF_DEM && git checkout {PEER_COMMIT}
    sed s/-lopenblas/-lblas/ config/Makefile_config_Ubuntu_OpenBLAS.mk > config/Makefile_config.mk
    echo '#define GIT_VERSION "{PEER_COMMIT}"' > VersionInfo.h && make
and pass --lfdem LF_DEM/LF_DEM (the binary next to the Makefile)."""
# LF_DEM's paper frame: flow x, gradient z, vorticity e3 = e1 x e2 = -y
TO_PAPER = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


def read_packing(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(positions wrapped into the box from its lower corner, diameters, box lengths) of an
    orthogonal LAMMPS data file with ``Atoms # sphere`` rows (id type diameter density x y z ...),
    ordered by atom id."""
    bounds, atoms, section = {}, [], None
    for line in path.read_text().splitlines()[1:]:
        words = line.split()
        if not words:
            continue
        if len(words) >= 4 and words[2] in ("xlo", "ylo", "zlo"):
            bounds[words[2][0]] = (float(words[0]), float(words[1]))
        elif len(words) >= 6 and words[3:] == ["xy", "xz", "yz"] and any(float(w) for w in words[:3]):
            raise ValueError(f"{path}: a tilted box; LF_DEM starts from an orthogonal one")
        elif words[0][0].isalpha():
            section = words[0]
        elif section == "Atoms":
            atoms.append((int(words[0]), float(words[2]), *map(float, words[4:7])))
    if not atoms or sorted(bounds) != ["x", "y", "z"]:
        raise ValueError(f"{path}: expected a box and an 'Atoms # sphere' section")
    atoms.sort()
    rows = np.array([a[1:] for a in atoms])
    lower = np.array([bounds[k][0] for k in "xyz"])
    lengths = np.array([bounds[k][1] - bounds[k][0] for k in "xyz"])
    return np.mod(rows[:, 1:] - lower, lengths), rows[:, 0], lengths


def write_lfdem_configuration(packing: Path, target: Path) -> tuple[float, float]:
    """LF_DEM's text configuration (its generator's header, rows x y z radius) of ``packing`` with
    lengths in units of the small radius; returns (phi, small radius in the project's unit)."""
    positions, diameters, lengths = read_packing(packing)
    radii = diameters / 2.0
    scale = 1.0 / radii.min()
    small = np.isclose(radii, radii.min())
    volume = np.prod(lengths)
    vf = [float(np.sum(4.0 / 3.0 * math.pi * radii[mask] ** 3) / volume) for mask in (small, ~small)]
    header = (
        f"# np1 np2 vf lx ly lz vf1 vf2 disp\n# {small.sum()} {(~small).sum()} {sum(vf):.15g} "
        + " ".join(f"{scale * v:.15g}" for v in lengths)
        + f" {vf[0]:.15g} {vf[1]:.15g} 0\n"
    )
    body = "".join(f"{x:.15g} {y:.15g} {z:.15g} {a:.15g}\n" for (x, y, z), a in zip(scale * positions, scale * radii))
    target.write_text(header + body)
    return sum(vf), float(radii.min())


def lfdem_parameters(small_radius: float, strain: float, engine: dict = ENGINE, friction_model: int = 1) -> str:
    """LF_DEM's parameter file for ``engine``'s physics (module docstring; keys kn, kt, mu, h_out,
    delta, eta_f, rate), hydrodynamic units; friction_model 2: critical-load friction."""
    kn_small_pairs = engine["kn"] / (6.0 * math.pi * engine["eta_f"] * engine["rate"] * small_radius)
    return "\n".join(
        [
            "lubrication_model = tangential;",
            f"lub_max_gap = {engine['h_out']};",
            f"lub_reduce_parameter = {engine['delta']};",
            "contact_relaxation_time = -1h;",
            "contact_relaxation_time_tan = -1h;",
            f"friction_model = {friction_model};",
            f"mu_static = {engine['mu']};",
            f"mu_dynamic = {engine['mu']};",
            "mu_rolling = 0;",
            f"kn = {kn_small_pairs:.6g}h;",
            f"kt = {engine['kt'] / engine['kn']:.12g}kn;",
            "kr = 0kn;",
            "sd_coeff = 1;",
            "integration_method = 1;",
            "disp_max = 1e-3;",
            f"time_end = {strain}h;",
            "time_interval_output_data = 0.01h;",
            "time_interval_output_config = 0.1h;",
            "out_data_particle = true;",
            "out_data_interaction = true;",
            "origin_zero_flow = false;",
            "",
        ]
    )


def write_lfdem_inputs(packing: Path, folder: Path, strain: float, engine: dict = ENGINE, friction_model: int = 1):
    """LF_DEM's configuration (conf.dat) of ``packing`` and its parameters (shear.txt) in ``folder``."""
    _, small_radius = write_lfdem_configuration(packing, folder / "conf.dat")
    (folder / "shear.txt").write_text(lfdem_parameters(small_radius, strain, engine, friction_model))


def snapshots(path: Path):
    """(strain, rows) of each snapshot of an LF_DEM par_/int_ file."""
    strain, rows = None, []
    with open(path) as handle:
        for line in handle:
            if line.startswith("# cumulated strain"):
                if strain is not None:
                    yield strain, np.array(rows, dtype=float).reshape(len(rows), -1)
                strain, rows = float(line.split(":")[1]), []
            elif not line.startswith("#") and line.strip() and strain is not None:
                rows.append(line.split())
    if strain is not None:
        yield strain, np.array(rows, dtype=float).reshape(len(rows), -1)


def start_lfdem(binary: Path, folder: Path, out, rate: str = "1h", inputs: list[str] | None = None) -> subprocess.Popen:
    """LF_DEM on ``folder``'s conf.dat and shear.txt at shear rate ``rate`` (its ``-r`` argument; 1h:
    1 in hydrodynamic units), one thread, its output to the open file ``out``; ``inputs`` replace the
    configuration and parameter files (a checkpoint restart's ``-n -c <checkpoint> <configuration> shear.txt``)."""
    return subprocess.Popen(
        [str(binary), "-f", "-r", rate, *(inputs or ["conf.dat", "shear.txt"])],
        cwd=folder,
        stdout=out,
        stderr=subprocess.STDOUT,
        env={**os.environ, "OMP_NUM_THREADS": "1"},
    )


def run_lfdem(binary: Path, packing: Path, folder: Path, strain: float = STRAIN) -> Path:
    write_lfdem_inputs(packing, folder, strain)
    with open(folder / "lfdem.out", "w") as out:
        returncode = start_lfdem(binary, folder, out).wait()
    if returncode != 0:
        raise RuntimeError(f"{packing}: LF_DEM failed ({returncode}); see {folder}/lfdem.out")
    return folder


def data_columns(path: Path) -> dict[str, int]:
    """LF_DEM's data file header ``#k: name`` as name -> 0-based column."""
    columns = {}
    for line in path.read_text().splitlines():
        if not line.startswith("#"):
            break
        number, _, name = line[1:].partition(":")
        if number.strip().isdigit():
            columns[name.strip()] = int(number) - 1
    return columns


def reached_strain(folder: Path) -> float:
    """The cumulated shear strain of the last complete row of LF_DEM's data table in ``folder``, read
    from the tail of the file as LF_DEM writes it (0 without a row)."""
    path = next(folder.glob("data_*.dat"), None)
    if path is None:
        return 0.0
    with open(path, "rb") as handle:
        handle.seek(0, os.SEEK_END)
        handle.seek(max(handle.tell() - 8192, 0))
        tail = handle.read().decode(errors="replace")
    lines = [line for line in tail.split("\n")[:-1] if line.strip() and not line.startswith("#")]
    return float(lines[-1].split()[data_columns(path)["cumulated shear strain"]]) if lines else 0.0


def lfdem_observables(folder: Path, window=WINDOW) -> dict[str, float]:
    """Window means of one LF_DEM run (data_, st_, par_ and int_ files; columns as in their headers)."""
    data = np.loadtxt(next(folder.glob("data_*.dat")))
    inside = (data[:, 1] >= window[0]) & (data[:, 1] <= window[1])
    mean = lambda column: float(data[inside, column - 1].mean())  # noqa: E731 (1-based as in the header)
    stress = np.loadtxt(next(folder.glob("st_*.dat")))
    st_inside = (stress[:, 1] >= window[0]) & (stress[:, 1] <= window[1])
    hydro = stress[st_inside, 21:27].mean(axis=0)  # xx xy xz yz yy zz
    # hydro: the lubrication stresslets of the velocities not driven by contacts, and the solvent
    out = {
        "eta": mean(4),
        "N1": mean(10),
        "N2": mean(11),
        "Pi": mean(12),
        "contact": mean(5),
        "dashpot": mean(6),
        "hydro": mean(7) - 1.0 + mean(6),
        "hydro Pi": float(-(hydro[0] + hydro[4] + hydro[5]) / 3.0),
        "Z (overlapping pairs)": mean(18),
    }
    _, particles = next(snapshots(next(folder.glob("par_*.dat"))))
    radii = particles[:, 1]
    fabrics, near_z = [], []
    for strain, pairs in snapshots(next(folder.glob("int_*.dat"))):
        if not window[0] <= strain <= window[1] + 1e-9:
            continue
        i, j = pairs[:, 0].astype(int), pairs[:, 1].astype(int)
        # xi = 2h/(a_i + a_j) < EPS min(d_i, d_j) 2/(a_i + a_j)
        near = pairs[:, 6] < 4.0 * EPS * np.minimum(radii[i], radii[j]) / (radii[i] + radii[j])
        normals = pairs[near, 3:6]
        fabrics.append(TO_PAPER @ (normals.T @ normals / len(radii)) @ TO_PAPER.T)
        near_z.append(2.0 * near.sum() / len(radii))
    fabric = np.mean(fabrics, axis=0)
    out.update({f"n{a + 1}{b + 1}": float(fabric[a, b]) for a, b in ((0, 0), (1, 1), (2, 2), (0, 1))})
    out["Z"] = float(np.mean(near_z))
    return out


def project_observables(folder: Path, window=WINDOW) -> dict[str, float]:
    """Window means of one project run (stress table and trajectory)."""
    table = read_stress_table(folder / "stress.txt")
    rows = (table["strain"] >= window[0]) & (table["strain"] <= window[1])
    analysis = FabricAnalysis.from_dump(
        folder / "trajectory.dump",
        dt=ENGINE["dt"],
        shear_rate=ENGINE["rate"],
        shear_start_step=int(table["step"][0]),
        flow_angle_deg=0.0,
        eps=EPS,
    ).run()
    frames = (analysis.results.strain >= window[0] - 1e-9) & (analysis.results.strain <= window[1] + 1e-9)
    parts = {
        name: value[rows].mean(axis=0)
        for name, value in stress_parts(table, eta_f=ETA_F, rate=ENGINE["rate"], phi=0.0, theta_deg=0.0).items()
    }
    stresslet_total = parts["total"] - parts["lubrication"] + parts["stresslet"]
    fabric = analysis.results.fabric[frames].mean(axis=0)
    out = {
        "eta": parts["total"][0, 1],
        "N1": parts["total"][0, 0] - parts["total"][1, 1],
        "N2": parts["total"][1, 1] - parts["total"][2, 2],
        "Pi": -np.trace(parts["contact"] + parts["lubrication"] + parts["kinetic"]) / 3.0,
        "eta stresslets": stresslet_total[0, 1],
        "N1 stresslets": stresslet_total[0, 0] - stresslet_total[1, 1],
        "N2 stresslets": stresslet_total[1, 1] - stresslet_total[2, 2],
        "contact": parts["contact"][0, 1],
        "lubrication": parts["lubrication"][0, 1],
        "stresslet": parts["stresslet"][0, 1],
        "lubrication Pi": -np.trace(parts["lubrication"]) / 3.0,
    }
    out.update({f"n{a + 1}{b + 1}": float(fabric[a, b]) for a, b in ((0, 0), (1, 1), (2, 2), (0, 1))})
    out["Z"] = float(np.mean(analysis.results.coordination[frames]))
    return {name: float(value) for name, value in out.items()}


#: The table's rows: label, the project's value, LF_DEM's value (None: that code has no such value).
ROWS = (
    ("Z, near contacts", "Z", "Z"),
    *((f"<nn>_{c}", f"n{c}", f"n{c}") for c in ("11", "22", "33", "12")),
    ("Z, overlapping pairs", None, "Z (overlapping pairs)"),
    ("eta_r - 2.5 phi (project: dipoles)", "eta", "eta"),
    ("eta_r - 2.5 phi (project: stresslets)", "eta stresslets", "eta"),
    ("N1 (project: dipoles)", "N1", "N1"),
    ("N1 (project: stresslets)", "N1 stresslets", "N1"),
    ("N2 (project: dipoles)", "N2", "N2"),
    ("N2 (project: stresslets)", "N2 stresslets", "N2"),
    ("Pi (project: dipoles; LF_DEM: stresslets with their trace)", "Pi", "Pi"),
    ("contact_12: project springs; LF_DEM springs + dashpots + the lubrication they drive", "contact", "contact"),
    ("lubrication_12: project all pair dipoles; LF_DEM hydro - 1 + dashpot group", "lubrication", "hydro"),
    ("lubrication_12: project all pair stresslets; LF_DEM as above", "stresslet", "hydro"),
    ("LF_DEM dashpot group alone", None, "dashpot"),
    ("lubrication Pi: project dipoles; LF_DEM hydro group", "lubrication Pi", "hydro Pi"),
)


def compare(binary: Path, packing: Path, keep: Path | None, strain: float, window) -> tuple[dict, dict]:
    folder = Path(tempfile.mkdtemp(prefix="lfdem_", dir=keep))
    try:
        (folder / "peer").mkdir()
        (folder / "project").mkdir()
        with ThreadPoolExecutor(max_workers=1) as pool:  # the peer on one core, the project on the other
            peer = pool.submit(run_lfdem, binary, packing, folder / "peer", strain)
            project = project_observables(startup_run(packing, folder / "project", strain, dump_strain=0.1), window)
            peer_values = lfdem_observables(peer.result(), window)
        return project, peer_values
    finally:
        if keep is None:
            shutil.rmtree(folder, ignore_errors=True)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("packings", nargs="+", type=Path)
    parser.add_argument(
        "--lfdem",
        type=Path,
        default=os.environ.get("LF_DEM") or shutil.which("LF_DEM"),
        help="the LF_DEM binary (default: $LF_DEM or LF_DEM on the PATH)",
    )
    parser.add_argument("--keep", type=Path, help="keep each run's files under this folder")
    parser.add_argument("--strain", type=float, default=STRAIN, help=f"startup strain (default {STRAIN:g})")
    parser.add_argument(
        "--window",
        type=float,
        nargs=2,
        default=WINDOW,
        help=f"strain window of the means (default {WINDOW[0]:g} {WINDOW[1]:g})",
    )
    args = parser.parse_args(argv)
    if args.lfdem is None or not Path(args.lfdem).is_file():
        print(BUILD_HELP)
        sys.exit(0)
    version = subprocess.run([str(args.lfdem)], capture_output=True, text=True).stdout.split("version")[-1].split()[0]
    print(f"LF_DEM version {version}; strain {args.strain:g}, window {args.window}")
    results = []
    for packing in args.packings:
        results.append(compare(Path(args.lfdem).resolve(), packing, args.keep, args.strain, args.window))
        print(
            packing,
            {k: round(v, 4) for k, v in results[-1][0].items()},
            {k: round(v, 4) for k, v in results[-1][1].items()},
            flush=True,
        )
    print(
        f"\n| quantity (eta_f gammadot, strain {args.window[0]:g}-{args.window[1]:g}; mean +- s.e. over {len(results)} "
        "packings) | project | LF_DEM | project - LF_DEM (paired) |"
    )
    print("|---|--:|--:|--:|")
    for label, ours_name, theirs_name in ROWS:
        ours = [r[0][ours_name] if ours_name else np.nan for r in results]
        theirs = [r[1][theirs_name] if theirs_name else np.nan for r in results]
        print(f"| {label} | {mean_se(ours)} | {mean_se(theirs)} | {mean_se(np.subtract(ours, theirs))} |")


if __name__ == "__main__":
    main()

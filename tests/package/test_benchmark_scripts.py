"""The benchmark scripts behind BENCHMARKS.md's figures and the engine's defaults, each run for real at a
tiny size (tens of particles, about a thousand steps) through its command line or its functions, so that
none rots unnoticed between the full-size runs (the commands in BENCHMARKS.md). Every output goes to a
temporary folder: none of these writes into benchmarks/data or results/.

The scripts that run the peer code LF_DEM are tested without it (its input files, the reading of its
outputs on small synthetic ones, the build help printed when it is missing) and, where the binary is
found ($LF_DEM, LF_DEM on the PATH, or a checkout beside the repository, ../peer/LF_DEM), against the
real program at a tenth of a unit of strain.

The other scripts of benchmarks/ (chaos.py, fault_suite.py, mpi_accuracy.py, mpi_scaling.py, suite_cpu.py)
are exercised by other tests (tests/workflow/test_chaos.py, tests/quoted_numbers.py)."""

from __future__ import annotations

import json
import math
import os
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from quoted_numbers import benchmark_script
from suspension_fabric.simulation.lammps import RUN_FILES, ForceModel, pack

pytestmark = pytest.mark.lammps

REPO = Path(__file__).resolve().parents[2]
N = 30  # particles of the tiny packings
PEER_CHECKOUT = REPO.parent / "peer" / "LF_DEM" / "LF_DEM" / "LF_DEM"
LFDEM = next(
    (Path(p) for p in (os.environ.get("LF_DEM"), shutil.which("LF_DEM"), PEER_CHECKOUT) if p and Path(p).is_file()),
    None,
)
needs_lfdem = pytest.mark.skipif(
    LFDEM is None,
    reason="LF_DEM not found ($LF_DEM, PATH, ../peer/LF_DEM); benchmarks/lfdem_comparison.py prints its build",
)


def markdown_rows(text: str, head: str) -> list[list[str]]:
    """The cells of the rows of the Markdown table whose head line starts with ``head`` in ``text``."""
    lines = text.splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith(head))
    rows = []
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip().strip("|").split("|")])
    return rows


def mean_and_error(cell: str) -> tuple[float, float]:
    """A ``mean +- s.e.`` cell of the scripts' tables (mean_se) as two numbers."""
    mean, error = cell.split(" +- ")
    return float(mean), float(error)


@pytest.fixture(scope="module")
def packings(tmp_path_factory) -> list[Path]:
    """Two packings of N particles at phi = 0.45 (the pack rule's LAMMPS data files)."""
    root = tmp_path_factory.mktemp("packings")
    return [pack(root / f"seed{seed}", N, phi=0.45, seed=seed).data_file for seed in (1, 2)]


# -- bench_engine.py: the engine's cost per particle and unit strain (BENCHMARKS.md, "Engine speed") -----------

#: continuations of 1000 steps of each method's dt (the trajectory stride of bench_engine's runs)
TINY_STRAIN = {"default": 0.1, "jacobi": 0.1, "dilu_tol1e-5": 0.1, "implicit": 0.02, "explicit": 2e-4, "stock": 2e-4}
ENGINE_HEAD = "| method | N | dt | steps per unit strain | strain | loop s | core-s per particle per unit strain |"


@pytest.fixture(scope="module")
def bench_engine(tmp_path_factory):
    """bench_engine.py at N = N, its prepared state at strain 0.1 (1000 steps) in a temporary folder."""
    script = benchmark_script("bench_engine")
    with pytest.MonkeyPatch.context() as patch:
        for name, value in {
            "ROOT": tmp_path_factory.mktemp("bench_engine"),
            "SIZES": (N,),
            "BASE_N": N,
            "PREPARE_STRAIN": 0.1,
            "STRAIN": TINY_STRAIN,
            "LADDER_DTS": (1e-4,),
        }.items():
            patch.setattr(script, name, value)
        script.main(["prepare"])
        yield script


def engine_rows(text: str) -> list[dict]:
    return [
        {
            "label": cells[0],
            "n": int(cells[1]),
            "dt": float(cells[2]),
            "steps": int(cells[3]),
            "strain": float(cells[4]),
            "cost": float(cells[6]),
            "iterations": float(cells[7]) if cells[7] else None,
        }
        for cells in markdown_rows(text, ENGINE_HEAD)
    ]


def test_bench_engine_measure_prints_each_engines_cost(bench_engine, capsys):
    assert (bench_engine.checkpoint(N)).is_file()
    bench_engine.main(["measure"])
    out = capsys.readouterr().out
    rows = engine_rows(out)
    starts = ["default engine", "the same with block Jacobi", "springs explicit", "dilu to", "explicit plugin", "stock"]
    assert len(rows) == 6 and all(row["label"].startswith(start) for row, start in zip(rows, starts)), out
    for row, strain in zip(rows, ("default", "jacobi", "implicit", "dilu_tol1e-5", "explicit", "stock")):
        assert row["n"] == N and row["steps"] == round(1 / row["dt"]) and row["strain"] == TINY_STRAIN[strain]
        assert math.isfinite(row["cost"]) and row["cost"] > 0, row
        # CG iterations for the implicit engines only; the tighter tolerance takes more of them
        assert (row["iterations"] is None) == row["label"].startswith(("explicit", "stock")), row
    assert rows[3]["iterations"] > rows[0]["iterations"] > 0
    # the explicit engines need 500 times the steps per unit strain: far costlier per unit strain
    assert rows[4]["cost"] > 10 * rows[0]["cost"] and rows[5]["cost"] > 10 * rows[0]["cost"]
    ratios = out.split(f"at N = {N}: ")[1].split(";")[0]
    assert [part.split(" / ")[0] for part in ratios.split(", ")] == [
        "implicit",
        "jacobi",
        "dilu_tol1e-5",
        "explicit",
        "stock",
    ]


def test_bench_engine_ladder_and_alternate_time_both_preconditioners(bench_engine, capsys):
    bench_engine.main(["ladder", "--kn", "1.25e8"])
    bench_engine.alternate(sizes=(N,), repeats=1)
    out = capsys.readouterr().out
    ladder, alternate = out.split("alternating")
    ladder_rows, alternate_rows = engine_rows(ladder), engine_rows(alternate)
    assert [row["label"] for row in ladder_rows] == ["implicit springs, jacobi", "implicit springs, dilu"]
    assert [row["label"] for row in alternate_rows] == [
        "default engine, jacobi (run 1)",
        "default engine, dilu (run 1)",
    ]
    for row in ladder_rows + alternate_rows:
        assert row["cost"] > 0 and row["iterations"] > 0, row
    # the ladder's strain: at least 0.1 and 2000 steps
    assert {row["strain"] for row in ladder_rows} == {0.2}


def test_bench_engine_work_counts_the_solves_iterations_per_unit_strain(bench_engine, tmp_path, monkeypatch, capsys):
    """iterations per unit strain = CG iterations per step (every step's) / dt, a row per engine, in the table"""
    tiny = {"WORK_N": N, "WORK_STRAIN": 0.05, "WORK_NEWTON_DTS": (5e-4,), "WORK_TABLE": tmp_path / "w.csv"}
    for name, value in tiny.items():
        monkeypatch.setattr(bench_engine, name, value)
    bench_engine.main(["work"])
    table = pd.read_csv(tmp_path / "w.csv")
    assert list(table["contact_solve"]) == ["lagged", "newton"] and list(table["dt"]) == [1e-4, 5e-4]
    assert table["iterations_per_strain"].to_numpy() == pytest.approx(table["iterations_per_step"] / table["dt"])
    assert (table["iterations_per_step"] > 0).all() and (table["max_overlap"] > 0).all()
    rows = markdown_rows(capsys.readouterr().out, "| contact solve | dt |")
    assert [row[:2] for row in rows] == [["lagged", "0.0001"], ["newton", "0.0005"]]


# -- bench_fabric.py and bench_models.py: the analysis and the models' cost ----------------------------------


@pytest.fixture
def one_thread(monkeypatch):
    """bench_fabric.py (bench_models.py imports it) sets one BLAS thread in os.environ as it loads: undone
    after the test."""
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        monkeypatch.setenv(name, os.environ.get(name, "1"))


def test_bench_fabric_kernel_agrees_with_brute_force(one_thread, capsys):
    script = benchmark_script("bench_fabric")
    positions, radii, box = script.relaxed_configuration(40, seed=3)
    overlaps = script.near_contact_pairs(positions, radii, box.mdanalysis_dimensions(), eps=0.0)
    assert len(overlaps) == 0 or -overlaps.gaps.min() < 1e-3
    script.main(["--sizes", "40"])  # exits if the kernel and the brute force disagree
    rows = markdown_rows(capsys.readouterr().out, "| N | method |")
    assert [row[1] for row in rows] == [
        "fabric_tensor",
        "brute force (27 images)",
        "FabricAnalysis (dump read + kernel)",
    ]
    for n, _, ms, per_second, pairs, z, _ in rows:
        assert int(n) == 40 and float(ms) > 0 and float(per_second) > 0
        assert int(pairs) > 0 and float(z) == pytest.approx(2 * int(pairs) / 40, abs=1e-3)
    assert float(rows[0][6]) >= 1  # brute force / kernel


def test_bench_models_expm_grid_matches_solve_ivp(one_thread, capsys):
    benchmark_script("bench_models").main(["--angles", "3"])
    out = capsys.readouterr().out
    assert "# grid: 3 angles x 200 strain points" in out
    rows = markdown_rows(out, "| model |")
    assert [row[0] for row in rows] == ["G-W (beta=10.9)", "modified (beta=9.4, A=42.4)"]
    for _, fast, peer, speedup, difference in rows:
        assert float(fast) > 0 and float(peer) > 0 and float(speedup.rstrip("x")) > 1
        assert float(difference) < 1e-6  # both integrate the same ODE (rtol 1e-8 for solve_ivp)


# -- dataset_cost.py and float_configs.py: the committed datasets and their rebuilds ----------------------


def write_dataset(folder: Path, n: int, runs: list[tuple[float, float]]) -> None:
    """A dataset record with one run.json (wall seconds, strain) per run."""
    files = {}
    for k, (wall, strain) in enumerate(runs):
        key = f"seed{k + 1}/startup/run.json"
        (folder / key).parent.mkdir(parents=True)
        (folder / key).write_text(json.dumps({"wall_time_s": wall, "results": {"strain": strain}}))
        files[key] = "0" * 64
        files[f"seed{k + 1}/startup/fabric.csv"] = "0" * 64
    config = {
        "seeds": list(range(1, len(runs) + 1)),
        "particles": {"n": n, "phi": 0.45},
        "forces": {"mu": 0.5, "kn": 1.25e8},
        "run": {"dt": 1e-4},
    }
    record = {"format": 2, "config": config, "files": files, "runs_missing": []}
    (folder / "dataset.json").write_text(json.dumps(record))


def test_dataset_cost_sums_the_run_records(tmp_path, capsys):
    write_dataset(tmp_path / "campaign" / "point_a", 100, [(3600.0, 2.0), (1800.0, 1.0)])
    write_dataset(tmp_path / "campaign" / "point_b", 50, [(900.0, 3.0)])
    write_dataset(tmp_path / "single", 10, [(36.0, 1.5)])
    (tmp_path / "campaign" / "notes").mkdir()  # not a dataset: skipped
    benchmark_script("dataset_cost").main([str(tmp_path / "campaign"), str(tmp_path / "single")])
    out = capsys.readouterr().out
    header = [cell.strip() for cell in out.splitlines()[0].strip("|").split("|")]
    assert header == list(benchmark_script("dataset_cost").dataset_cost(tmp_path / "single"))
    table = pd.DataFrame(markdown_rows(out, "| dataset"), columns=header).set_index("dataset")
    assert [Path(name).name for name in table.index] == ["point_a", "point_b", "single"]
    numbers = table.apply(pd.to_numeric)
    assert numbers["N"].tolist() == [100, 50, 10] and numbers["runs"].tolist() == [2, 1, 1]
    assert numbers["strain"].tolist() == [3.0, 3.0, 1.5]
    assert numbers["core_hours"].tolist() == pytest.approx([1.5, 0.25, 0.01], rel=1e-3)
    # wall / (N strain): 5400 / 300, 900 / 150, 36 / 15
    assert numbers["core_s_per_particle_strain"].tolist() == pytest.approx([18.0, 6.0, 2.4], rel=1e-3)
    assert out.strip().endswith("all: 1.76 core-hours")


def test_float_configs_counts_the_digits_that_move(tmp_path, monkeypatch, capsys):
    script = benchmark_script("float_configs")
    for configs, data, _ in script.STUDIES.values():  # what each rebuild needs is in the repository
        assert all((REPO / path).is_file() for path in configs) and all((REPO / path).is_dir() for path in data)
    native, second = tmp_path / "native", tmp_path / "second"
    for tree, last, far, value in ((native, "1.234", "2.00", 0.5), (second, "1.235", "2.50", 0.5 + 1e-9)):
        (tree / "fragments").mkdir(parents=True)
        (tree / "fragments" / "fit.md").write_text(f"beta = {last} and A = {far}, N = 1000\n")
        (tree / "same.md").write_text("nothing moves: 3.14\n")
        pd.DataFrame({"angle": [0, 15], "n12": [-0.1, value]}).to_csv(tree / "table.csv", index=False)
        (tree / "empty.csv").write_text("")
    fragments, tables = script.compare(native, second)
    # 3 numbers, 2 of them moved, one (2.00 -> 2.50) by more than a unit of its last digit
    assert fragments == ["| fragments/fit.md | 3 | 2 | 1 |", "| same.md | 1 | 0 | 0 |"]
    assert tables == ["| table.csv | 2.0e-09 |"]  # 1e-9 against the column's largest value, 0.5

    monkeypatch.setattr(script, "rebuild", lambda study, env, where: (native if env is None else second, 1.0))
    script.main(["--studies", "map"])
    out = capsys.readouterr().out
    assert "map: rebuilt in 1 s (native) and 1 s (second configuration)" in out
    assert markdown_rows(out, "| fragment |") == [row.strip("| ").split(" | ") for row in fragments]
    assert markdown_rows(out, "| table whose numbers differ |") == [["table.csv", "2.0e-09"]]


# -- stresslet_vs_dipole.py: the lubrication stress two ways (BENCHMARKS.md, "Pair stresslets ...") ---------


def test_stresslet_vs_dipole_on_two_packings(packings, capsys):
    benchmark_script("stresslet_vs_dipole").main([*map(str, packings), "--strain", "0.05", "--window", "0.02", "0.05"])
    out = capsys.readouterr().out
    rows = {name: mean_and_error(cell) for name, cell in markdown_rows(out, "| quantity")}
    assert list(rows) == ["dipole_12", "stresslet_12", "contact_12", "dipole_pressure", "stresslet_trace"]
    assert rows["dipole_12"][0] > 0 and rows["dipole_pressure"][0] > 0 and rows["dipole_12"][1] > 0
    assert abs(rows["stresslet_trace"][0]) < 1e-9  # the stresslets are traceless
    # the stresslet is the dipole at contact distance: smaller in shear by O(h / (a_i + a_j))
    ratios = json.loads(out.split("stresslet_12 / dipole_12 per packing: ")[1].splitlines()[0])
    assert len(ratios) == 2 and all(0.8 < ratio < 1.0 for ratio in ratios), ratios


# -- the LF_DEM scripts without LF_DEM: its inputs, the reading of its outputs, the build help ---------------


def test_lfdem_inputs_of_a_packing(packings, tmp_path):
    script = benchmark_script("lfdem_comparison")
    positions, diameters, lengths = script.read_packing(packings[0])
    script.write_lfdem_inputs(packings[0], tmp_path, 0.05, friction_model=2)
    lines = (tmp_path / "conf.dat").read_text().splitlines()
    assert lines[0] == "# np1 np2 vf lx ly lz vf1 vf2 disp"
    np1, np2, vf, lx, ly, lz, vf1, vf2, _ = map(float, lines[1][1:].split())
    assert (np1, np2) == (N // 2, N // 2)  # bidisperse 50:50 by number
    assert vf == pytest.approx(0.45, abs=1e-6) and vf1 + vf2 == pytest.approx(vf)
    assert [lx, ly, lz] == pytest.approx(2 * lengths)  # LF_DEM's length unit: the small radius
    rows = np.loadtxt(lines[2:])
    assert rows.shape == (N, 4) and sorted(set(rows[:, 3])) == pytest.approx([1.0, 1.4])
    assert np.all(rows[:, :3] >= 0) and np.all(rows[:, :3] < 2 * lengths)
    assert rows[:, :3] == pytest.approx(2 * positions)
    parameters = dict(
        line.rstrip(";").split(" = ") for line in (tmp_path / "shear.txt").read_text().splitlines() if line
    )
    # kn matched on small-small pairs: kn / (6 pi eta_f gammadot a_small), hydrodynamic units
    assert float(parameters["kn"].rstrip("h")) == pytest.approx(1.25e8 / (6 * math.pi * 223 * 0.5), rel=1e-5)
    assert parameters["kt"] == f"{2 / 7:.12g}kn" and parameters["mu_static"] == "0.5"
    assert parameters["friction_model"] == "2" and parameters["time_end"] == "0.05h"
    assert parameters["lub_max_gap"] == "0.05" and parameters["lub_reduce_parameter"] == "0.001"
    tilted = tmp_path / "tilted.data"
    tilted.write_text(packings[0].read_text().replace("\n0 0 0 xy xz yz\n", "\n0.5 0 0 xy xz yz\n"))
    with pytest.raises(ValueError, match="tilted box"):
        script.read_packing(tilted)


#: the columns of LF_DEM's data file (00fa7cc0), #1 to #23 of 29
DATA_HEADER = (
    "time,cumulated shear strain,shear rate,viscosity,Viscosity(contact),Viscosity(dashpot),Viscosity(hydro),"
    "inviscid function 0th,inviscid function 3rd,N1 viscosity,N2 viscosity,particle pressure,"
    "particle pressure contact,energy,min gap,max tangential displacement,max rolling displacement,contact number,"
    "frictional contact number,number of interaction,max velocity,max angular velocity,dt"
).split(",")


def write_lfdem_outputs(folder: Path, partial_row: bool = False) -> None:
    """A small LF_DEM output set (data_, st_, par_, int_ files as LF_DEM 00fa7cc0 writes them) of 4
    particles: strain 0 to 0.2 every 0.05, viscosity 3 + strain, step 1e-3; at strain 0.1 one near pair
    along z (LF_DEM's gradient) and one far pair along x (the same pairs at strain 0)."""
    folder.mkdir(parents=True, exist_ok=True)
    header = "# LF_DEM version 00fa7cc0\n# np 4\n" + "".join(f"#{k + 1}: {n}\n" for k, n in enumerate(DATA_HEADER))
    rows = []
    for strain in (0.0, 0.05, 0.1, 0.15, 0.2):
        values = {"time": strain, "cumulated shear strain": strain, "shear rate": 1.0, "viscosity": 3.0 + strain}
        values |= {"Viscosity(contact)": 0.5, "Viscosity(dashpot)": 0.25, "Viscosity(hydro)": 2.0}
        values |= {"N1 viscosity": 0.1, "N2 viscosity": -0.2, "particle pressure": 1.5, "dt": 1e-3}
        values |= {"contact number": 2.0, "frictional contact number": 1.0}
        row = [values.get(name, 0.0) for name in DATA_HEADER] + [0.0] * 6
        rows.append(" ".join(f"{v:g}" for v in row))
    text = header + "\n".join(rows) + "\n" + ("0.25 0.25 1 3.2" if partial_row else "")
    (folder / "data_conf.dat").write_text(text)
    stress = np.zeros((5, 30))
    stress[:, 1] = (0.0, 0.05, 0.1, 0.15, 0.2)
    stress[:, 21:27] = [-1.0, 0.0, 0.5, 0.0, -2.0, -3.0]  # hydro xx xy xz yz yy zz
    np.savetxt(folder / "st_conf.dat", stress, header="stress")
    snapshot = "# cumulated strain : {}\n# shear disp : 0\n# shear rate : 1\n"
    (folder / "par_conf.dat").write_text(
        "# np 4\n" + snapshot.format(0) + "".join(f"{k} {a} 0 0 0\n" for k, a in enumerate((1, 1, 1.4, 1.4)))
    )
    pairs = "0 1 0 0 0 1 0.001 0 0 0 0 0 0 0 0 0 0\n2 3 0 1 0 0 0.5 0 0 0 0 0 0 0 0 0 0\n"
    (folder / "int_conf.dat").write_text("# np 4\n" + snapshot.format(0) + pairs + snapshot.format(0.1) + pairs)


def test_lfdem_outputs_are_read_by_name_in_the_paper_frame(tmp_path):
    comparison = benchmark_script("lfdem_comparison")
    write_lfdem_outputs(tmp_path / "run", partial_row=True)
    columns = comparison.data_columns(tmp_path / "run" / "data_conf.dat")
    assert columns["cumulated shear strain"] == 1 and columns["viscosity"] == 3 and columns["dt"] == 22
    assert comparison.reached_strain(tmp_path / "run") == 0.2  # the last complete row, not the partial one
    assert comparison.reached_strain(tmp_path / "none") == 0.0
    write_lfdem_outputs(tmp_path / "run")  # LF_DEM done: no partial row
    values = comparison.lfdem_observables(tmp_path / "run", window=(0.05, 0.15))
    assert [values[k] for k in ("eta", "N1", "N2", "Pi", "contact", "dashpot")] == pytest.approx(
        [3.1, 0.1, -0.2, 1.5, 0.5, 0.25]
    )
    assert values["hydro"] == pytest.approx(2.0 - 1.0 + 0.25) and values["hydro Pi"] == pytest.approx(2.0)
    # the near pair's normal is LF_DEM's z, the gradient: the paper's e2; per particle, 4 particles
    assert [values[k] for k in ("n11", "n22", "n33", "n12")] == [0.0, 0.25, 0.0, 0.0]
    assert values["Z"] == 0.5 and values["Z (overlapping pairs)"] == 2.0
    assert comparison.mean_se([1.0, 2.0, 3.0]) == "2 +- 0.58" and comparison.mean_se([np.nan]) == ""

    critical = benchmark_script("lfdem_critical_load")
    assert critical.lfdem_observables(tmp_path / "run", (0.1, 0.2)) == pytest.approx(
        {
            "eta_r - 1 - 2.5 phi": 2.15,
            "contacts per particle": 2.0,
            "frictional contacts per particle": 1.0,
            "strain per step": 1e-3,  # dt 1e-3 at shear rate 1
        }
    )
    table = tmp_path / "stress.csv"
    pd.DataFrame(
        {"strain": [1.0, 2.0, 3.0], "eta_r": [9, 5, 7], "Z_touching": [3, 4, 5], "Z_frictional": [1, 2, 2]}
    ).to_csv(table, index=False)
    assert critical.project_observables(table, 0.5, (2.0, 3.0)) == pytest.approx(
        {"eta_r - 1 - 2.5 phi": 3.75, "contacts per particle": 4.5, "frictional contacts per particle": 2.0}
    )
    # a finished run of the same input, or a running one past the strain asked, is read, not run again
    run = tmp_path / "run"
    packing = tmp_path / "packing.data"
    assert critical.lfdem_run(Path("/no/LF_DEM"), packing, run, 0.1, {}, 4.0, read_until=0.15) == run
    with pytest.raises(RuntimeError, match="reached strain 0.2, not 2"):
        critical.lfdem_run(Path("/no/LF_DEM"), packing, run, 0.1, {}, 4.0, read_until=2.0)
    (run / "finished").write_text(f"{packing.resolve()} 0.1cl 4\n")
    assert critical.lfdem_run(Path("/no/LF_DEM"), packing, run, 0.1, {}, 4.0) == run

    speed = benchmark_script("peer_speed")
    assert speed.lfdem_steps_per_strain(run / "data_conf.dat", (0.05, 0.15)) == pytest.approx(1000.0)
    strain = np.linspace(0.0, 3.0, 31)
    assert speed.window_slope(strain, 2.5 * strain + 7.0, (1.5, 2.5)) == pytest.approx(2.5)
    with pytest.raises(RuntimeError, match="fewer than 3"):
        speed.window_slope([1.5, 2.0], [1.0, 2.0], (1.5, 2.5))


def test_without_lfdem_the_scripts_print_how_to_build_it(packings, tmp_path, monkeypatch, capsys):
    monkeypatch.delenv("LF_DEM", raising=False)
    missing = str(tmp_path / "LF_DEM")
    for name, argv, code in (
        ("lfdem_comparison", [str(packings[0]), "--lfdem", missing], 0),
        ("lfdem_critical_load", ["--lfdem", missing], 0),
        ("peer_speed", ["run", "--point", "phi0.45_mu0.5", "--lfdem", missing], 1),
    ):
        with pytest.raises(SystemExit) as stopped:
            benchmark_script(name).main(argv)
        assert stopped.value.code == code, name
        out = capsys.readouterr().out
        assert out.startswith("LF_DEM was not found") and "git checkout 00fa7cc0" in out, (name, out)


def test_peer_speed_points_engines_and_report(capsys):
    script = benchmark_script("peer_speed")
    study = script.point_study("phi0.45_mu0.5")
    assert study["particles"]["phi"] == 0.45 and study["forces"]["mu"] == 0.5
    newton = script.point_study("phi0.45_mu0.5", "newton")
    assert newton["run"]["contact_solve"] == "newton" and newton["run"]["dt"] == 10 * study["run"]["dt"]
    with pytest.raises(SystemExit, match="no point 'phi0.99_mu0'"):
        script.point_study("phi0.99_mu0")
    engine = script.lfdem_engine(ForceModel())
    assert engine["kt"] == pytest.approx(2 / 7 * engine["kn"]) and engine["rate"] == 1.0
    assert set(engine) == {"kn", "kt", "mu", "h_out", "delta", "eta_f", "rate"}
    row = {
        "point": "phi0.45_mu0.5",
        "n": N,
        "kn": 1.25e8,
        "engine": "lagged dt 0.0001",
        "window": "1.5-2.5",
        "project_s_per_strain": 2.0,
        "peer_s_per_strain": 60.0,
        "ratio": 30.0,
        "project_steps_per_strain": 10000.0,
        "peer_steps_per_strain": 1500.0,
        "project_ms_per_step": 0.2,
        "peer_ms_per_step": 40.0,
        "step_cost_ratio": 200.0,
    }
    text = script.report(pd.DataFrame([row]))
    assert markdown_rows(text, "| point |") == [
        ["phi0.45_mu0.5", "30", "1.25e+08", "lagged dt 0.0001", "1.5-2.5", "2.0", "60", "30", "10000", "1500"]
        + ["0.2", "40", "200"]
    ]
    script.main(["report"])  # the committed table (read only)
    committed = pd.read_csv(script.TABLE)
    assert len(markdown_rows(capsys.readouterr().out, "| point |")) == len(committed) > 0


# -- the LF_DEM scripts against the real LF_DEM --------------------------------------------------------------


@needs_lfdem
def test_lfdem_comparison_with_lfdem(packings, capsys):
    script = benchmark_script("lfdem_comparison")
    script.main([*map(str, packings), "--lfdem", str(LFDEM), "--strain", "0.1", "--window", "0.05", "0.1"])
    out = capsys.readouterr().out
    assert out.startswith("LF_DEM version 00fa7cc0; strain 0.1")
    rows = {label: cells for label, *cells in markdown_rows(out, "| quantity")}
    assert list(rows) == [label for label, _, _ in script.ROWS]
    ours, theirs = (mean_and_error(cell) for cell in rows["eta_r - 2.5 phi (project: dipoles)"][:2])
    # the same packings, the same physics: the viscosities agree within 10% (2% on these)
    assert ours[0] > 1 and theirs[0] > 1 and abs(ours[0] - theirs[0]) < 0.1 * theirs[0], rows
    pi = [mean_and_error(cell)[0] for cell in rows["Pi (project: dipoles; LF_DEM: stresslets with their trace)"][:2]]
    assert pi[0] > 0 and abs(pi[0] - pi[1]) < 0.1 * pi[1], rows
    n12 = [mean_and_error(cell)[0] for cell in rows["<nn>_12"][:2]]
    assert n12[0] < 0 and n12[1] < 0, rows  # near contacts along the compressional axis in both codes


@needs_lfdem
def test_lfdem_critical_load_with_lfdem(packings, tmp_path, capsys):
    script = benchmark_script("lfdem_critical_load")
    point = "phi0.54_mu1_rate0.1"  # config/thickening.yaml: mu 1
    for seed, packing in enumerate(packings, start=1):
        run = tmp_path / "study" / point / f"seed{seed}"
        (run / "packing").mkdir(parents=True)
        (run / "startup").mkdir()
        shutil.copy(packing, run / "packing" / "packing.data")
        frame = {"strain": [0.0, 0.02, 0.04, 0.06, 0.08], "eta_r": [4.0, 5.0, 6.0, 6.0, 6.0]}
        frame |= {"Z_touching": 1.0, "Z_frictional": 0.5}
        pd.DataFrame(frame).to_csv(run / "startup" / "stress.csv", index=False)
    arguments = ["--lfdem", str(LFDEM), "--study", str(tmp_path / "study"), "--keep", str(tmp_path / "runs")]
    arguments += ["--seeds", "1", "2", "--ratios", "0.1", "--strain", "0.05", "--window", "0.02", "0.05"]
    saved = tmp_path / "critical_load.csv"
    script.main([*arguments, "--save", str(saved)])
    out = capsys.readouterr().out
    assert "phi 0.54, mu 1; strain 0.05" in out
    rows = {name: cells for name, *cells in markdown_rows(out, "| gammadot/gammadot_0 = 0.1 (mean +- s.e. over 2")}
    assert list(rows) == [
        "eta_r - 1 - 2.5 phi",
        "contacts per particle",
        "frictional contacts per particle",
        "LF_DEM's strain per step",
    ]
    assert 0 < mean_and_error(rows["LF_DEM's strain per step"][1])[0] < 1e-2
    assert mean_and_error(rows["eta_r - 1 - 2.5 phi"][0]) == pytest.approx((5.5 - 1 - 2.5 * 0.54, 0.0))
    peer_eta = mean_and_error(rows["eta_r - 1 - 2.5 phi"][1])[0]
    assert 0 < peer_eta < 20, rows  # LF_DEM's viscosity less its solvent, at strain 0.02-0.05
    for seed in (1, 2):
        folder = tmp_path / "runs" / point / f"seed{seed}"
        assert "friction_model = 2;" in (folder / "shear.txt").read_text()
        assert script.reached_strain(folder) == pytest.approx(0.05)
        assert (folder / "finished").read_text().endswith(" 0.1cl 0.05\n")
    # the saved table: a row per run, code and quantity at the config's kn; saved again, replaced, not doubled
    table = pd.read_csv(saved)
    assert len(table) == 2 * (3 + 4) and set(table["kn"]) == {5e9} and set(table["window"]) == {"0.02-0.05"}
    project = table[(table["code"] == "project") & (table["quantity"] == "eta_r - 1 - 2.5 phi")]
    assert project["value"].to_numpy() == pytest.approx([5.5 - 1 - 2.5 * 0.54] * 2)
    script.main([*arguments, "--save", str(saved)])
    assert pd.read_csv(saved).equals(table)
    # continued from the runs' checkpoints with the step capped: the earlier rows kept, the later ones at
    # most the cap in strain, a row set of their own in the table
    continued = ["--lfdem", str(LFDEM), "--study", str(tmp_path / "study"), "--keep", str(tmp_path / "capped")]
    continued += ["--seeds", "1", "2", "--ratios", "0.1", "--strain", "0.08", "--window", "0.06", "0.08"]
    script.main([*continued, "--continue-from", str(tmp_path / "runs"), "--dt-max", "1e-4", "--save", str(saved)])
    for seed in (1, 2):
        source, folder = (tmp_path / name / point / f"seed{seed}" for name in ("runs", "capped"))
        assert "dt_max = 0.0001h;" in (folder / "shear.txt").read_text()
        assert (folder / "finished").read_text().endswith(f" 0.1cl 0.08 from {source.resolve()} dt_max 0.0001\n")
        before, after = (np.loadtxt(next(f.glob("data_*.dat"))) for f in (source, folder))
        assert np.array_equal(after[: len(before)], before)  # LF_DEM appends after its checkpoint
        strain, step = after[len(before) :, 1], after[len(before) :, 22] * after[len(before) :, 2]
        assert strain[-1] == pytest.approx(0.08) and np.all(step <= 1e-4 * (1 + 1e-9)), step
    capped = pd.read_csv(saved, dtype={"lfdem_dt_max": str})
    assert set(capped["lfdem_dt_max"]) == {"own", "0.0001"} and len(capped) == 2 * len(table)


@needs_lfdem
def test_peer_speed_with_lfdem(tmp_path, monkeypatch):
    script = benchmark_script("peer_speed")
    monkeypatch.setattr(script, "POLL_S", 0.01)  # LF_DEM's rows come every few ms at this size
    row = script.measure(LFDEM, "phi0.45_mu0.5", (0.05, 0.15), tmp_path, n=N)
    assert row["n"] == N and row["point"] == "phi0.45_mu0.5" and row["window"] == "0.05-0.15"
    assert row["project_steps_per_strain"] == pytest.approx(1e4)
    for key in ("project_s_per_strain", "peer_s_per_strain", "peer_steps_per_strain", "step_cost_ratio"):
        assert math.isfinite(row[key]) and row[key] > 0, row
    assert row["ratio"] == pytest.approx(row["peer_s_per_strain"] / row["project_s_per_strain"])
    assert (next(tmp_path.glob("peer_speed_*")) / "project" / RUN_FILES["checkpoint"]).is_file()


@needs_lfdem
def test_peer_speed_times_several_engines_against_one_lfdem_run(tmp_path, monkeypatch):
    script = benchmark_script("peer_speed")
    monkeypatch.setattr(script, "POLL_S", 0.01)
    rows = script.measure_engines(LFDEM, "phi0.45_mu0.5", (0.05, 0.15), tmp_path, ["lagged", "newton"], N, 5.0)
    assert [row["engine"] for row in rows] == ["lagged dt 0.0001", "newton dt 0.0005"]
    assert rows[0]["peer_s_per_strain"] == rows[1]["peer_s_per_strain"]  # one LF_DEM run
    assert [row["project_steps_per_strain"] for row in rows] == pytest.approx([1e4, 2e3])
    folder = next(tmp_path.glob("peer_speed_*"))
    assert all((folder / name / RUN_FILES["checkpoint"]).is_file() for name in ("project", "project2"))


def test_lfdem_critical_load_reads_a_refused_run_from_its_files(study, tmp_path):
    """A run whose stress table the workflow refused (a kn below the stiff limit, chosen on purpose) is
    read from its own files by the function that writes the table: the numbers of the table."""
    critical = benchmark_script("lfdem_critical_load")
    run, copy = study / "results/test/seed1/startup", tmp_path / "startup"
    copy.mkdir()
    for name in ("stress.txt", "run_complete.json", "fabric.csv"):
        shutil.copy(run / name, copy / name)
    window = (0.1, 0.3)
    from_files = critical.project_observables(copy / "stress.csv", 0.45, window)
    assert not (copy / "stress.csv").exists()
    assert from_files == pytest.approx(critical.project_observables(run / "stress.csv", 0.45, window), rel=1e-6)
    assert from_files["contacts per particle"] > 0

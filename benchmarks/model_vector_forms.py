"""The fabric models' right-hand sides on 6-vectors (``FabricModel.vector_form``) against the
same models through their tensor ``rhs``, in the same run.

    .venv/bin/python benchmarks/model_vector_forms.py [--rounds 5] [--save benchmarks/data/model_vector_forms.csv]
        [--leaderboard results/reference [--save-leaderboard benchmarks/data/model_vector_forms_leaderboard.csv]]

For the two models that the ODE solver integrates (G-W with the hybrid closure, and the sparse
model of data/models/sparse_reference.json), on the reference study's grids (config/reference.yaml:
startup to strain 5, then its 13 rotation angles to strain 3, outputs every 0.005 strain):

- the CPU per call of the right-hand side on the batch of 13 fabrics, tensor path and vector form;
- the CPU of one evaluation of the model's curves (the startup, then every angle; what a global
  fit's residual computes), with the vector form and with it removed, and the largest difference
  between the two sets of curves (the solver's tolerance is rtol 1e-10).

With ``--leaderboard``, the rule benchmark_models' computation on a reference build's tables (its
``tables/startup_runs.csv``, ``tables/rotation_runs.csv`` and ``fits.json``, with config/reference.yaml's
settings: every model's global fit with jackknife errors, held-out fits on 4 folds of angles), once
with the vector forms removed and once with them, and the largest change in the leaderboard's
numbers, relative to each number's own t-interval width (the scores' statistical resolution).

The two paths alternate within each round; each figure is the smallest over the rounds. CPU is the
process's user + system time (BLAS single-threaded), so another job on the machine slows it less
than a wall clock, but does not leave it untouched.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import csv  # noqa: E402
import dataclasses  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from suspension_fabric.analysis.frames import rotation_about_gradient, simple_shear_gradient, sym_to_vec  # noqa: E402
from suspension_fabric.models import fabric_models as fm  # noqa: E402
from suspension_fabric.study.config import load_config  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
MODELS = {"gw_hybrid": {"beta": 66.0}, str(REPO / "data/models/sparse_reference.json"): {"rate": 1.34}}
CALLS = 2000


def cpu() -> float:
    return time.process_time()


def per_call(function, vectors) -> float:
    start = cpu()
    for _ in range(CALLS):
        function(vectors)
    return (cpu() - start) / CALLS


def curves(fabric_model, params, phi, thetas, startup, rotation):
    start = cpu()
    before = fm.startup_shear(fabric_model, startup, params, phi)
    after = fm.rotated_shear(fabric_model, before[-1], np.radians(thetas), rotation, params, phi)
    return cpu() - start, np.concatenate([before.ravel(), after.ravel()])


def measure(rounds: int) -> list[dict]:
    config = load_config(REPO / "config/reference.yaml")
    run, phi, thetas = config["run"], config["particles"]["phi"], np.asarray(config["angles_deg"], dtype=float)
    startup = np.arange(0.0, run["startup_strain"] + 1e-9, run["table_strain"])
    rotation = np.arange(0.0, run["rotation_strain"] + 1e-9, run["table_strain"])
    rows = []
    for spec, params in MODELS.items():
        (fast,) = fm.resolve_models([spec]).values()
        slow = dataclasses.replace(fast, vector_form=None)
        # the batch the solver sees after a rotation: the startup's end turned to each angle
        end = fm.startup_shear(fast, [run["startup_strain"]], params, phi)[0]
        turned = rotation_about_gradient(np.radians(thetas))
        vectors = sym_to_vec(turned @ end @ np.swapaxes(turned, -1, -2))
        flow = fm.flow_of(np.broadcast_to(simple_shear_gradient(), (len(thetas), 3, 3)))
        best = {"call_tensor": np.inf, "call_vector": np.inf, "curves_tensor": np.inf, "curves_vector": np.inf}
        difference = 0.0
        for _ in range(rounds):
            best["call_tensor"] = min(best["call_tensor"], per_call(fm.vector_rhs(slow, flow, params, phi), vectors))
            best["call_vector"] = min(best["call_vector"], per_call(fm.vector_rhs(fast, flow, params, phi), vectors))
            seconds_slow, values_slow = curves(slow, params, phi, thetas, startup, rotation)
            seconds_fast, values_fast = curves(fast, params, phi, thetas, startup, rotation)
            best["curves_tensor"] = min(best["curves_tensor"], seconds_slow)
            best["curves_vector"] = min(best["curves_vector"], seconds_fast)
            difference = max(difference, float(np.abs(values_fast - values_slow).max()))
        rows.append(
            {
                "model": fast.key,
                "batch": len(thetas),
                "call_tensor_us": round(best["call_tensor"] * 1e6, 1),
                "call_vector_us": round(best["call_vector"] * 1e6, 1),
                "call_ratio": round(best["call_tensor"] / best["call_vector"], 2),
                "curves_tensor_s": round(best["curves_tensor"], 3),
                "curves_vector_s": round(best["curves_vector"], 3),
                "curves_ratio": round(best["curves_tensor"] / best["curves_vector"], 2),
                "max_difference": f"{difference:.1e}",
            }
        )
    return rows


def leaderboard_cost(reference: Path) -> list[dict]:
    """benchmark_models' leaderboard on ``reference``'s tables without and with the vector forms."""
    from suspension_fabric.analysis import tables
    from suspension_fabric.evaluation import model_benchmark
    from suspension_fabric.models.fits_file import read_fits

    config = load_config(REPO / "config/reference.yaml")
    fits = read_fits(reference / "fits.json")
    curves = model_benchmark.seed_curves(
        tables.read_fabric_table(reference / "tables/startup_runs.csv"),
        tables.read_fabric_table(reference / "tables/rotation_runs.csv"),
        config["verdicts"]["window"],
        config["analysis"]["steady_window"],
    )
    with_forms = fm.resolve_models(
        [str(REPO / spec) if spec.endswith(".json") else spec for spec in config["models"]["fabric"]]
    )
    without = {key: dataclasses.replace(model, vector_form=None) for key, model in with_forms.items()}
    boards, rows = {}, []
    for name, models in (("tensor rhs", without), ("vector forms", with_forms)):
        start = cpu()
        boards[name] = model_benchmark.leaderboard(
            models,
            fits["models"],
            curves,
            fits["phi"],
            config["run"]["startup_strain"],
            config["models"]["held_out_folds"],
            reference=config["verdicts"]["models"]["reference"],
            level=config["verdicts"]["level"],
        ).table
        rows.append({"path": name, "leaderboard_cpu_s": round(cpu() - start, 1)})
    before, after = boards["tensor rhs"], boards["vector forms"]
    changes = []
    for score in ("in_sample_mse", "held_out_mse", "held_out_difference_vs_gw"):
        low, high = (
            ("held_out_difference_low_vs_gw", "held_out_difference_high_vs_gw")
            if "difference" in score
            else (
                score.replace("mse", "low"),
                score.replace("mse", "high"),
            )
        )
        width = (before[high] - before[low]).abs()
        changes.append(((after[score] - before[score]).abs() / width).max())
    rows[-1]["largest_change_per_interval_width"] = f"{np.nanmax(changes):.1e}"
    return rows


def write_csv(rows: list[dict], path: Path) -> None:
    fields = list(dict.fromkeys(key for row in rows for key in row))
    with path.open("w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)


def print_table(rows: list[dict]) -> None:
    fields = list(dict.fromkeys(key for row in rows for key in row))
    print(" | ".join(fields))
    for row in rows:
        print(" | ".join(str(row.get(field, "")) for field in fields))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--save", type=Path, help="write the table as CSV")
    parser.add_argument("--leaderboard", type=Path, help="a reference build's results folder (results/reference)")
    parser.add_argument("--save-leaderboard", type=Path, help="write the leaderboard's table as CSV")
    args = parser.parse_args()
    rows = measure(args.rounds)
    print_table(rows)
    if args.save:
        write_csv(rows, args.save)
    if args.leaderboard:
        board = leaderboard_cost(args.leaderboard)
        print_table(board)
        if args.save_leaderboard:
            write_csv(board, args.save_leaderboard)


if __name__ == "__main__":
    main()

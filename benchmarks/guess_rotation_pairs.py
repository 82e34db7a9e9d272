"""The 90-degree rotation at the map's corner from the same states with the two solves (BENCHMARKS.md,
"The corner with the first iterate extrapolated").

Against the corner point's first dataset (benchmarks/data/engine_validation/engine_newton_dt8e-6_phi0.55_mu1,
once data/campaign/phi0.55_mu1), the corner rerun with the first iterate extrapolated and local solves
(benchmarks/configs/engine_guess_phi0.55_mu1.yaml) agrees in every steady quantity, but three strain bins
after its 90-degree rotation lie beyond the normal-theory Sidak bound of engine_validation.py. Its
trajectories and the dataset's are independent from the startup on (four seeds each), so a transient
that differs can come from the states the rotations start from as much as from the solve. Here each
state, the end of a startup of the point's engine (seeds 1 and 2 of the idle-cost check, seeds 5-8 of its
step check), is rotated by 90 degrees with both solves: the old velocities as the first iterate and global
iterations only (the dataset's), and the quadratic extrapolation with local solves at 0.02 (the rerun's).
Per state, the difference of each strain bin's mean of <nn>'_12, <nn>'_23, sigma'_12 and sigma'_23
(engine_ladder.BINS up to the rotation's strain); over the states, its mean and 95% t-interval, and the same
bins' seed-to-seed spread in the dataset for scale.

    .venv/bin/python benchmarks/guess_rotation_pairs.py run      # 12 runs, two at a time
    .venv/bin/python benchmarks/guess_rotation_pairs.py report

`run` writes each run's fabric and stress tables to benchmarks/data/engine_validation/guess_rotation_pairs/
<solve>/seed<s>/rotation_theta90/ (the trajectories stay in results/guess_rotation_pairs/).
"""

from __future__ import annotations

import argparse
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
from engine_ladder import BINS, binned_seed_means
from scipy import stats

from suspension_fabric.analysis.stress import STRESS_FLOAT_FORMAT, run_stress_table
from suspension_fabric.analysis.tables import run_fabric_table, write_fabric_table
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, run_rotation
from suspension_fabric.simulation.lammps.runner import RUN_FILES
from suspension_fabric.study.config import load_config

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
CONFIG = HERE / "configs" / "engine_guess_phi0.55_mu1.yaml"
IDLE_COST, LATER_SEEDS = "engine_newton_dt8e-6_phi0.55_mu1_idle_cost", "engine_newton_dt8e-6_phi0.55_mu1_seeds5-8"
STATES = {
    seed: REPO / "results" / folder / f"seed{seed}" / "startup" / RUN_FILES["checkpoint"]
    for seed, folder in [(1, IDLE_COST), (2, IDLE_COST), (5, LATER_SEEDS), (6, LATER_SEEDS), (7, LATER_SEEDS)]
    + [(8, LATER_SEEDS)]
}
#: solve name -> (run.initial_guess, run.local_solve_fraction)
SOLVES = {"previous": ("previous", 0.0), "quadratic_local": ("quadratic", 0.02)}
ANGLE = 90
STRAIN = 0.5
RUNS = REPO / "results" / "guess_rotation_pairs"
TABLES = HERE / "data" / "engine_validation" / "guess_rotation_pairs"
TRANSIENTS = (("fabric", "n12", "<nn>'_12"), ("fabric", "n23", "<nn>'_23"))
TRANSIENTS += (("stress", "total_12", "sigma'_12"), ("stress", "total_23", "sigma'_23"))
DATASET = HERE / "data" / "engine_validation" / "engine_newton_dt8e-6_phi0.55_mu1"


def rotate(solve: str, seed: int) -> None:
    study = load_config(CONFIG)
    guess, fraction = SOLVES[solve]
    solve_run = {**study["run"], "initial_guess": guess, "local_solve_fraction": fraction}
    model = ForceModel.from_config({**study, "run": solve_run})
    run = run_rotation(
        RUNS / solve / f"seed{seed}" / f"rotation_theta{ANGLE}",
        STATES[seed],
        ANGLE,
        STRAIN,
        force_model=model,
        settings=ShearSettings.from_config(study),
        progress=None,
    )
    target = TABLES / solve / f"seed{seed}" / f"rotation_theta{ANGLE}"
    target.mkdir(parents=True, exist_ok=True)
    marker = run.output_dir / "run_complete.json"
    fabric = write_fabric_table(
        run_fabric_table(run.dump_file, marker, seed=seed, eps=study["analysis"]["eps"]), target / "fabric.csv"
    )
    stress = run_stress_table(run.table_file, marker, fabric)
    stress.to_csv(target / "stress.csv", index=False, float_format=STRESS_FLOAT_FORMAT)


def run_all() -> None:
    missing = [str(path) for path in STATES.values() if not path.is_file()]
    if missing:
        raise SystemExit(f"missing startup checkpoints (make them with their configs first): {', '.join(missing)}")
    with ThreadPoolExecutor(2) as pool:
        list(pool.map(lambda job: rotate(*job), [(solve, seed) for seed in STATES for solve in SOLVES]))


def bins() -> list[tuple[float, float]]:
    """engine_ladder.BINS up to the rotations' strain."""
    return [b for b in BINS if b[1] <= STRAIN + 1e-9]


def state_differences(kind: str, column: str) -> np.ndarray:
    """Per state (rows) and strain bin, the new solve's bin mean less the old one's."""
    old, new = (TABLES / name for name in SOLVES)
    with warnings.catch_warnings():  # the bins beyond the rotation's strain are empty
        warnings.simplefilter("ignore", RuntimeWarning)
        a = binned_seed_means(new, ANGLE, kind, column)[:, : len(bins())]
        b = binned_seed_means(old, ANGLE, kind, column)[:, : len(bins())]
    return a - b


def report(level: float = 0.95) -> str:
    lines = [
        f"{ANGLE}-degree rotation from the same {len(STATES)} states, {STRAIN:g} strain: "
        f"{' - '.join(reversed(SOLVES))} per state, mean [{level:.0%} t-interval over states]; "
        "dataset spread: the seed-to-seed standard deviation of the bin in "
        f"{DATASET.relative_to(REPO)}\n",
        "| quantity | " + " | ".join(f"{a:g}-{b:g}" for a, b in bins()) + " |",
        "|---|" + "---|" * len(bins()),
    ]
    for kind, column, label in TRANSIENTS:
        difference = state_differences(kind, column)
        spread = binned_seed_means(DATASET, ANGLE, kind, column)[:, : len(bins())].std(axis=0, ddof=1)
        mean = difference.mean(axis=0)
        t = stats.t.ppf(0.5 + level / 2, len(difference) - 1)
        half = t * difference.std(axis=0, ddof=1) / np.sqrt(len(difference))
        cells = [
            f"{m:+.4g} [{m - h:+.3g}, {m + h:+.3g}] (spread {s:.3g})"
            for m, h, s in zip(mean, half, spread, strict=True)
        ]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("command", choices=("run", "report"))
    args = parser.parse_args(argv)
    if args.command == "run":
        run_all()
    print(report())


if __name__ == "__main__":
    main()

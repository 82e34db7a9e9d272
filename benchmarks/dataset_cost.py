"""What a committed dataset cost to make, from its run records (each run's LAMMPS wall time,
``run.json``): per dataset, the engine settings, the core-seconds of all its runs (one core each),
the strain simulated and the cost per particle per unit strain. A folder of datasets (a
campaign's ``data/campaign``) gives one row per point. The wall times were measured by the runs
themselves, two at a time on the 2-core machine (so each run shared the machine with one other).

    .venv/bin/python benchmarks/dataset_cost.py data/reference data/reference_n2000 data/campaign
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pandas as pd

from suspension_fabric.study.dataset import DATASET_FILE, read_dataset


def dataset_cost(folder: Path) -> dict:
    record = read_dataset(folder)
    config = record["config"]
    wall = strain = 0.0
    for key in record["files"]:
        if key.endswith("/run.json"):
            run = json.loads((folder / key).read_text())
            wall += run["wall_time_s"]
            strain += run["results"]["strain"]
    n = config["particles"]["n"]
    return {
        "dataset": str(folder),
        "N": n,
        "phi": config["particles"]["phi"],
        "mu": config["forces"]["mu"],
        "kn": config["forces"]["kn"],
        "dt": config["run"]["dt"],
        "seeds": len(config["seeds"]),
        "runs": sum(key.endswith("/run.json") for key in record["files"]),
        "strain": strain,
        "core_hours": wall / 3600.0,
        "core_s_per_particle_strain": wall / (n * strain),
    }


def folders(paths: list[Path]) -> list[Path]:
    """The dataset folders among paths, a folder of datasets expanded into its datasets."""
    found = []
    for path in paths:
        if (path / DATASET_FILE).is_file():
            found.append(path)
        else:
            found += sorted(p.parent for p in path.glob(f"*/{DATASET_FILE}"))
    return found


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", type=Path, nargs="+", help="dataset folders or folders of datasets")
    args = parser.parse_args(argv)
    table = pd.DataFrame([dataset_cost(folder) for folder in folders(args.paths)])
    print(table.to_markdown(index=False, floatfmt=".3g"))
    print(f"\nall: {table['core_hours'].sum():.2f} core-hours")


if __name__ == "__main__":
    main()

"""Does a fabric model found at one state point transfer to the map's others? A model (a sparse
model file of rule discover_model, or any models.fabric entry such as gw_hybrid) refits only what
G-W refits, its parameters on each point's steady components it names (a sparse model: its rate r
on the steady <nn>_12, as G-W refits beta there); each point's rotations are then predicted from
the models' own state and scored per seed as the model benchmark scores (units of
(<nn>_12^ss)^2), with the paired difference from G-W fitted on the steady state (95% t-interval
over the point's seeds). With ``--max-order 1`` the model is first found again on the reference
with terms of order <= 1 in <nn> only (affine, as G-W).

    .venv/bin/python benchmarks/model_transfer.py data/models/sparse_reference.json data/campaign
    .venv/bin/python benchmarks/model_transfer.py --max-order 1 results/reference data/campaign
    .venv/bin/python benchmarks/model_transfer.py gw_hybrid data/campaign
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import pandas as pd

from suspension_fabric.analysis.seed_statistics import t_interval
from suspension_fabric.evaluation import model_benchmark, model_discovery
from suspension_fabric.models import fabric_models
from suspension_fabric.models.sparse_fabric import write_model_file
from suspension_fabric.study.dataset import load


def found_again(results: Path, max_order: int) -> Path:
    """The sparse model of a finished study's tables (results/<study>) with terms up to ``max_order``."""
    loaded = load(results)
    window = loaded.fits["steady_window"]
    curves = model_benchmark.seed_curves(loaded.fabric_startup, loaded.fabric_rotation, 2.0, window)
    found = model_discovery.discover(
        loaded.fabric_startup, loaded.fabric_rotation, curves, loaded.fits["phi"], 5.0, 4, window, max_order=max_order
    )
    path = Path(tempfile.mkdtemp()) / f"sparse_order{max_order}.json"
    return write_model_file(path, found["coefficients"], found["errors"], {}, found["steady_fabric"])


def transfer(model_spec: str, campaign: Path) -> pd.DataFrame:
    model = fabric_models.load_model(model_spec)
    rows = []
    for folder in sorted(p for p in campaign.iterdir() if (p / "dataset.json").is_file()):
        loaded = load(folder)
        config, fits = loaded.config, loaded.fits
        phi, startup = config["particles"]["phi"], config["run"]["startup_strain"]
        curves = model_benchmark.seed_curves(
            loaded.fabric_startup, loaded.fabric_rotation, 2.0, config["analysis"]["steady_window"]
        )
        _, gw = model_benchmark.model_curves(fabric_models.GW, fits["models"]["gw"]["parameters"], phi, curves, startup)
        reference = model_benchmark.seed_errors(gw, curves)
        row = {"point": folder.name, "seeds": len(curves.seeds)}
        try:
            wanted = {c: fits["targets"][f"n{c}"]["mean"] for c in model.steady_targets}
            params = fabric_models.fit_steady(model, wanted, phi)
            _, predicted = model_benchmark.model_curves(model, params, phi, curves, startup)
            errors = model_benchmark.seed_errors(predicted, curves)
        except (fabric_models.ModelError, ValueError) as failure:
            rows.append({**row, "parameters": "", "failure": str(failure)[:80]})
            continue
        row["parameters"] = ", ".join(f"{name} {value:.4g}" for name, value in params.items())
        for c, name in ((3, "n12"), (5, "n23")):
            difference = t_interval(errors[:, c] - reference[:, c])
            row[f"{name}_model"], row[f"{name}_gw"] = errors[:, c].mean(), reference[:, c].mean()
            row[f"{name}_difference"] = f"{difference.mean:+.4f} [{difference.low:+.4f}, {difference.high:+.4f}]"
        rows.append(row)
    return pd.DataFrame(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "model", help="a models.fabric entry (a key or a model file), or with --max-order a study's results folder"
    )
    parser.add_argument("campaign", type=Path, help="a folder of datasets, one per state point")
    parser.add_argument("--max-order", type=int, help="find the model again on the study with terms up to this order")
    args = parser.parse_args()
    model = str(found_again(Path(args.model), args.max_order)) if args.max_order else args.model
    with pd.option_context("display.width", 250, "display.max_columns", 20):
        print(transfer(model, args.campaign).to_string(index=False, float_format=lambda x: f"{x:.4g}"))


if __name__ == "__main__":
    main()

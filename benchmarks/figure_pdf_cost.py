"""The polar figures' PDFs: the maps' cells written as vector paths or as one image, in the same run.

    .venv/bin/python benchmarks/figure_pdf_cost.py results/reference [--rounds 1]
        [--save benchmarks/data/figure_pdf_cost.csv]

Paper Fig. 2 (`figures.figure_rotation`) and Fig. 4 (`figures.figure_stress_rotation`) from a
reference build's tables (the files their rules read: `tables/rotation_aggregate.csv`,
`tables/predictions.csv` and `fits.json`; `tables/stress_rotation_aggregate.csv`,
`tables/stress_predictions.csv`, `tables/stress_viscosity_transients.csv` and
`tables/stress_steady_state.csv`), each built and saved as PDF and PNG (`figures.save_figure`)
twice per round: as the workflow makes it (the `pcolormesh` maps rasterized in the PDF), and with
the maps' rasterization turned off after building, as the figures were before. Prints per figure
and variant the CPU seconds of building and saving (the smallest over the rounds), the number of
map cells and the sizes of the PDF and the PNG.
"""

from __future__ import annotations

import argparse
import csv
import tempfile
import time
from pathlib import Path

import pandas as pd
from matplotlib.collections import QuadMesh

from suspension_fabric.evaluation.stress_model import steady_value
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting import figures


def fig2(results: Path):
    tables = results / "tables"
    return figures.figure_rotation(
        pd.read_csv(tables / "rotation_aggregate.csv"),
        pd.read_csv(tables / "predictions.csv"),
        read_fits(results / "fits.json"),
    )


def fig4(results: Path):
    tables = results / "tables"
    return figures.figure_stress_rotation(
        pd.read_csv(tables / "stress_rotation_aggregate.csv"),
        pd.read_csv(tables / "stress_predictions.csv"),
        pd.read_csv(tables / "stress_viscosity_transients.csv"),
        steady_value(pd.read_csv(tables / "stress_steady_state.csv"), "eta_r")[0],
    )


FIGURES = {"fig2_rotation": fig2, "fig4_stress_rotation": fig4}


def maps(fig) -> list[QuadMesh]:
    return [artist for ax in fig.axes for artist in ax.collections if isinstance(artist, QuadMesh)]


def measure(results: Path, name: str, rasterized: bool, folder: Path) -> dict:
    start = time.process_time()
    fig = FIGURES[name](results)
    meshes = maps(fig)
    if not rasterized:
        for mesh in meshes:
            mesh.set_rasterized(False)
    cells = sum(int(mesh.get_array().size) for mesh in meshes)
    pdf, png = figures.save_figure(fig, folder / name)
    return {
        "figure": name,
        "maps": "rasterized" if rasterized else "vector cells",
        "cpu_s": time.process_time() - start,
        "cells": cells,
        "pdf_mb": round(pdf.stat().st_size / 1e6, 2),
        "png_mb": round(png.stat().st_size / 1e6, 2),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", type=Path, help="a reference build's results folder (results/reference)")
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--save", type=Path, help="write the table as CSV")
    args = parser.parse_args()
    best: dict[tuple, dict] = {}
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(args.rounds):
            for name in FIGURES:
                for rasterized in (False, True):
                    row = measure(args.results, name, rasterized, Path(folder))
                    key = (name, rasterized)
                    if key not in best or row["cpu_s"] < best[key]["cpu_s"]:
                        best[key] = row
    rows = [{**row, "cpu_s": round(row["cpu_s"], 1)} for row in best.values()]
    print(" | ".join(rows[0]))
    for row in rows:
        print(" | ".join(str(value) for value in row.values()))
    if args.save:
        with args.save.open("w", newline="") as out:
            writer = csv.DictWriter(out, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()

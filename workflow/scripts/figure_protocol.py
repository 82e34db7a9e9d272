"""Snakemake: the figure of one protocol (rule figure_protocol)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.analysis.protocol_tables import read_protocol_table
from suspension_fabric.io.protocols import Protocol, Segment
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting import figures, protocol_figures
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    protocol = Protocol(sm.wildcards.protocol, tuple(Segment(**fields) for fields in sm.params.segments))
    fabric = read_protocol_table(sm.input.fabric)
    fits = read_fits(sm.input.fits)
    fig = protocol_figures.figure_protocol(
        protocol,
        fabric,
        read_protocol_table(sm.input.stress),
        pd.read_csv(sm.input.predictions),
        {key: entry["label"] for key, entry in fits["models"].items()},
        protocol_figures.seed_count(fabric),
    )
    print(figures.save_figure(fig, Path(sm.output.pdf).with_suffix("")))

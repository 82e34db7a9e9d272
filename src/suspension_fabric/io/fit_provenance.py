"""What each fit saw, and whether a score is held out.

A score is *held out* only if no fit behind it saw its seed: not the fit of the model's parameters
(model_parameters.csv records, per row, the study it was fitted on, its seeds and its runs), nor
the search that chose a model file's terms (the file's ``source``). Seeds are the unit: two
datasets of the same physics that share a seed number share its packing and its startup (the
protocols of data/protocols continue the runs of data/reference), and a later segment continues
from a run of the same seed, so a seed that any fit saw makes every score on it in-sample. The
test is conservative: it may call a score in-sample whose seed was only seen at another state
point, never the reverse.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import pandas as pd

__all__ = [
    "PROVENANCE_COLUMNS",
    "seeds_text",
    "seeds_of",
    "check_provenance",
    "seen_seeds",
    "held_out_label",
]

#: The columns of model_parameters.csv that say what each fit saw.
PROVENANCE_COLUMNS = ("fitted_on", "fitted_seeds", "fitted_runs")


def seeds_text(seeds: Iterable[int]) -> str:
    """Seeds as a table cell: '1 2 3'."""
    return " ".join(str(int(seed)) for seed in sorted(set(int(s) for s in seeds)))


def seeds_of(text) -> set[int]:
    """The seeds of a `seeds_text` cell."""
    return {int(part) for part in str(text).split()}


def check_provenance(parameters: pd.DataFrame, where: str) -> None:
    """A parameters table must say what its fits saw; ``where`` names the file in the error."""
    missing = [column for column in PROVENANCE_COLUMNS if column not in parameters.columns]
    if missing:
        raise ValueError(
            f"{where}: no column {missing}; a parameters table must record the study, seeds and runs each fit saw "
            "(rule benchmark_models writes them), or no score on it could be called held out"
        )


def seen_seeds(parameters: pd.DataFrame, model_sources: Mapping[str, Mapping] | None = None) -> dict:
    """{(model, mode): the seeds its fit saw}, with the seeds of a model file's ``source`` (the search
    that chose its terms) added to both modes of that model."""
    check_provenance(parameters, "model parameters")
    seen = {}
    for (model, mode), rows in parameters.groupby(["model", "mode"]):
        seeds = set().union(*(seeds_of(text) for text in rows["fitted_seeds"]))
        source = (model_sources or {}).get(model)
        if source:
            seeds |= {int(seed) for seed in source.get("seeds", ())}
        seen[(model, mode)] = seeds
    return seen


def held_out_label(held_out: bool) -> str:
    """How a table prints a score's provenance."""
    return "held out" if held_out else "in-sample seeds"

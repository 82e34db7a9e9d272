"""Held out means no fit saw the seed (suspension_fabric.io.fit_provenance): the protocol
leaderboard labels a score held out only when none of its seeds is among those the model's fit
(or the search behind a model file) saw, and a parameters table that does not say what its fits
saw is refused."""

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.evaluation import protocol_benchmark
from suspension_fabric.io.fit_provenance import held_out_label, seeds_of, seeds_text, seen_seeds
from suspension_fabric.io.protocols import Protocol, Segment
from suspension_fabric.models.fabric_models import protocol_fabric, resolve_models

PHI = 0.45
PARAMS = {"beta": 11.0}


def _curves(seeds) -> protocol_benchmark.ProtocolCurves:
    """A reversal whose 'measured' fabric is G-W's own plus a per-seed offset."""
    protocol = Protocol("reversal", (Segment(3.0), Segment(1.0, 180.0)))
    grids = [np.linspace(0.0, 3.0, 31), np.linspace(0.0, 1.0, 11)]
    model = resolve_models(["gw"])["gw"]
    exact = protocol_fabric(model, protocol, grids, PARAMS, PHI, np.eye(3) * 0.1)
    offsets = 1e-3 * np.arange(len(seeds))
    fabric = [np.stack([e + o for o in offsets]) for e in exact]
    totals = [grids[0], grids[1] + 3.0]
    return protocol_benchmark.ProtocolCurves(protocol, np.array(seeds), grids, totals, fabric, None)


def _parameters(fitted_seeds) -> pd.DataFrame:
    return pd.DataFrame(
        [
            {"model": "gw", "mode": mode, "parameter": "beta", "value": 11.0, "error": 0.1}
            | {"fitted_on": "reference", "fitted_seeds": seeds_text(fitted_seeds), "fitted_runs": "startup"}
            for mode in ("steady", "global")
        ]
    )


def _board(scored_seeds, fitted_seeds, sources=None) -> pd.DataFrame:
    board, _ = protocol_benchmark.fabric_protocol_leaderboard(
        resolve_models(["gw"]),
        {mode: {"gw": PARAMS} for mode in ("steady", "global")},
        {"reversal": _curves(scored_seeds)},
        PHI,
        0.1,
        seen=seen_seeds(_parameters(fitted_seeds), sources),
        reference="gw",
    )
    return board


def test_seeds_round_trip_through_a_table_cell():
    assert seeds_text([3, 1, 2, 2]) == "1 2 3" and seeds_of("1 2 3") == {1, 2, 3}


def test_a_score_on_a_seed_the_fit_saw_is_in_sample():
    board = _board([1, 2, 3], fitted_seeds=range(1, 17))
    assert not board["held_out"].any() and (board["seeds_seen"] == 3).all()
    assert held_out_label(False) == "in-sample seeds"


def test_one_seen_seed_among_fresh_ones_makes_the_score_in_sample():
    board = _board([101, 102, 16], fitted_seeds=range(1, 17))
    assert not board["held_out"].any() and (board["seeds_seen"] == 1).all()


def test_fresh_seeds_are_held_out():
    board = _board([101, 102, 103], fitted_seeds=range(1, 17))
    assert board["held_out"].all() and (board["seeds_seen"] == 0).all()
    assert held_out_label(True) == "held out"


def test_the_seeds_a_model_file_was_found_on_count_as_seen():
    """A model file's terms were chosen on its source's seeds: fitting its rate elsewhere does not
    make those seeds held out."""
    board = _board([101, 102, 103], fitted_seeds=[1, 2], sources={"gw": {"seeds": [101]}})
    assert not board["held_out"].any() and (board["seeds_seen"] == 1).all()


def test_a_parameters_table_without_provenance_is_refused():
    bare = _parameters([1]).drop(columns=["fitted_seeds"])
    with pytest.raises(ValueError, match="fitted_seeds"):
        seen_seeds(bare)

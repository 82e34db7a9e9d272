"""A fabric model given only in the config runs through every rule (suspension_fabric.models.fabric_models).

On a copy of the session's finished test study, a toy model in a Python file of the work folder
is added to models.fabric with --config: only the model rules and those downstream rerun (no
simulation), and the toy model appears in the fits, the predictions, the model errors, the stress
relation and the figures. The toy model relaxes the fabric towards s phi (I/3 - Eh) at unit rate,

    d<nn>/dgamma = -(<nn> - s phi (I/3 - Eh)),

so in simple shear its steady <nn>_12 = -s phi / 2 and the steady fit gives s = -2 <nn>_12^ss / phi;
it is declared not affine, so it runs through the general ODE path.

A toy stress relation in the same file, added to models.stress, reaches the stress-relation
leaderboard: H = C = -<nn> (1 + k Tr<nn>) (shape parameter k), so that at the fitted
coefficients it reproduces the steady lubrication and contact sigma_12."""

import json
import shutil

import numpy as np
import pandas as pd
import pytest

from workflow_helpers import RESULTS, TEST_CONFIG, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow

TOY = """
import numpy as np
from suspension_fabric.models.fabric_models import FabricModel, Parameter

TOY = FabricModel(
    key="toy", label="toy relaxation", parameters=(Parameter("s", 0.0, 10.0, 0.5),), steady_targets=("12",),
    rhs=lambda fabric, flow, p, phi: -(np.asarray(fabric) - p["s"] * phi * (np.eye(3) / 3.0 - flow.e_hat)),
    affine=False,
)

from suspension_fabric.models.stress_relations import StressRelation


def toy_forms(fabric, p):
    form = -np.asarray(fabric) * (1 + p["k"] * np.trace(fabric, axis1=-2, axis2=-1))[..., None, None]
    return form, form


TOY_RELATION = StressRelation(key="toy_relation", label="toy stress relation", forms=toy_forms,
                              parameters=(Parameter("k", 0.0, 5.0, 1.0),))
"""
MODELS = "models={fabric: [gw, modified, toy.py:TOY], stress: [gw, toy.py:TOY_RELATION]}"


@pytest.fixture(scope="module")
def with_toy(study, tmp_path_factory):
    workdir = tmp_path_factory.mktemp("toy_model") / "study"
    shutil.copytree(study, workdir, symlinks=True)
    (workdir / "toy.py").write_text(TOY)
    plan = snakemake(workdir, *TEST_CONFIG, "--config", MODELS, "-n")
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    result = snakemake(workdir, *TEST_CONFIG, "--config", MODELS)
    assert result.returncode == 0, result.stderr[-3000:]
    return workdir, {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}


def test_a_model_in_the_config_reruns_the_model_rules_only(with_toy):
    _, rules = with_toy
    assert {
        "fit_models",
        "predict",
        "model_errors",
        "stress_relation",
        "benchmark_models",
        "benchmark_stress_relations",
    } <= rules
    assert not rules & {"pack", "shear_segment", "fabric_table", "stress_table"}


def test_the_toy_model_flows_through_fits_predictions_errors_and_stress(with_toy):
    workdir, _ = with_toy
    results = workdir / RESULTS
    fits = json.loads((results / "fits.json").read_text())
    assert list(fits["models"]) == ["gw", "modified", "toy"]
    n12 = fits["targets"]["n12"]["mean"]
    assert fits["models"]["toy"]["parameters"]["s"] == pytest.approx(-2 * n12 / fits["phi"], rel=1e-7)
    predictions = pd.read_csv(results / "tables/predictions.csv")
    toy = predictions[(predictions["model"] == "toy") & (predictions["protocol"] == "startup")].sort_values("strain")
    s, phi = fits["models"]["toy"]["parameters"]["s"], fits["phi"]
    n12_0 = toy["n12"].iloc[0]  # exact solution: n12 = -s phi/2 + (n12(0) + s phi/2) exp(-gamma)
    expected = -s * phi / 2 + (n12_0 + s * phi / 2) * np.exp(-toy["strain"].to_numpy())
    np.testing.assert_allclose(toy["n12"].to_numpy(), expected, rtol=1e-6, atol=1e-9)
    assert set(pd.read_csv(results / "tables/model_errors.csv")["model"]) == {"gw", "modified", "toy"}
    assert "rms_toy" in pd.read_csv(results / "tables/model_errors_summary.csv")
    assert set(pd.read_csv(results / "tables/stress_relation_fits.csv")["source"]) == {
        "simulation",
        "gw",
        "modified",
        "toy",
    }
    assert "toy relaxation" in (results / "tables/fits.html").read_text()
    board = pd.read_csv(results / "tables/leaderboard.csv")
    assert set(zip(board["model"], board["mode"])) == {
        (m, f) for m in ("gw", "modified", "toy") for f in ("steady", "global")
    }
    assert "toy relaxation" in (results / "tables/leaderboard.html").read_text()


def test_the_toy_stress_relation_reaches_the_stress_leaderboard(with_toy):
    """The toy relation is fitted (k within its bounds, a_H and a_C from the steady sigma_12 parts)
    and scored beside G-W, with the paired held-out difference from G-W."""
    workdir, _ = with_toy
    tables = workdir / RESULTS / "tables"
    board = pd.read_csv(tables / "stress_leaderboard.csv")
    assert set(zip(board["relation"], board["mode"])) == {("gw", "steady"), ("toy_relation", "global")}
    rotation = board[board["quantity"] == "eta_r rotation"].set_index("relation")
    assert np.isfinite(rotation.loc["toy_relation", ["held_out_mse", "held_out_difference_vs_gw"]].astype(float)).all()
    parameters = pd.read_csv(tables / "stress_relation_parameters.csv")
    toy = parameters[parameters["relation"] == "toy_relation"].set_index("parameter")["value"]
    assert set(toy.index) == {"a_H", "a_C", "k"} and 0.0 <= toy["k"] <= 5.0
    assert "toy stress relation" in (tables / "stress_leaderboard.html").read_text()

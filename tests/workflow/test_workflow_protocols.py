"""A new protocol is a config entry: added to the finished test study (a copy of it), it simulates
only its own new segments (the startup and the paper's rotation it starts from are shared), and
gets its tables, its leaderboard rows and its figure; a bad segment is refused before any job,
naming the key. The example is the one docs/workflow.md gives ("Protocols")."""

import shutil

import pandas as pd
import pytest

from workflow_helpers import RESULTS, TEST_CONFIG, dry_run_jobs, job_counts, snakemake

pytestmark = pytest.mark.workflow

# docs/workflow.md, "Protocols": a reversal after the paper's rotation by 90 degrees, and rotary shear
PROTOCOLS = (
    "protocols={"
    "back_from_90: [{strain: 0.3}, {strain: 0.1, flow_angle_deg: 90}, {strain: 0.1, flow_angle_deg: -90}], "
    "rotary: [{strain: 0.3}, {strain: 0.1, turning_deg_per_strain: 180}]"
    "}"
)


@pytest.fixture(scope="module")
def with_protocols(study, tmp_path_factory):
    copy = tmp_path_factory.mktemp("protocols") / "study"
    shutil.copytree(study, copy, symlinks=True)
    plan = snakemake(copy, *TEST_CONFIG, "--config", PROTOCOLS, "-n")
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    result = snakemake(copy, *TEST_CONFIG, "--config", PROTOCOLS)
    assert result.returncode == 0, (result.stdout + result.stderr)[-3000:]
    return copy, plan.stdout


def test_only_the_new_segments_are_simulated(with_protocols):
    """The startup and the rotation by 90 degrees exist: per seed, one segment reverses from the
    rotation and one turns after the startup; nothing else is simulated again."""
    _, plan = with_protocols
    shears = {job["wildcards"] for job in dry_run_jobs(plan) if job["rule"] == "shear_segment"}
    assert shears == {
        f"seed={seed}, run={run}"
        for seed in (1, 2)
        for run in ("rotation_theta90_thetam90for0.1", "startup_theta0turn180for0.1")
    }
    counts = job_counts(plan)
    assert "pack" not in counts and counts["fabric_table"] == 4


def test_protocol_tables_follow_the_flow_history(with_protocols):
    copy, _ = with_protocols
    table = pd.read_csv(copy / RESULTS / "tables/protocol_aggregate.csv")
    reversal = table[table["protocol"] == "back_from_90"]
    assert sorted(reversal["segment"].unique()) == [0, 1, 2]
    assert reversal["strain"].max() == pytest.approx(0.5) and set(reversal["frame"]) == {"flow"}
    # at a segment boundary the same frame is kept twice, in the old and in the new flow's frame
    boundary = reversal[reversal["strain"].round(9) == 0.4]
    assert sorted(boundary["theta"]) == [-90.0, 90.0]
    # the reversal of the flow direction flips the sign of <nn>_12 and keeps <nn>_11 (a frame change)
    before, after = (boundary[boundary["theta"] == t].iloc[0] for t in (90.0, -90.0))
    assert after["n12_mean"] == pytest.approx(-before["n12_mean"])
    assert after["n11_mean"] == pytest.approx(before["n11_mean"])
    rotary = table[(table["protocol"] == "rotary") & (table["segment"] == 1)]
    assert rotary["theta"].to_numpy() == pytest.approx(180.0 * rotary["segment_strain"].to_numpy())


def test_leaderboards_have_a_protocol_column(with_protocols):
    copy, _ = with_protocols
    board = pd.read_csv(copy / RESULTS / "tables/protocol_leaderboard.csv")
    assert set(board["protocol"]) == {"back_from_90", "rotary"}
    assert set(board["mode"]) == {"steady", "global"} and set(board["model"]) == {"gw", "modified", "separate_rates"}
    reference = board[(board["model"] == "gw") & (board["mode"] == "steady")]
    assert (reference["difference_vs_gw"] == 0.0).all()
    # the study's own fits saw every seed it scores: no score may be called held out
    assert not board["held_out"].any() and (board["seeds_seen"] == board["n_seeds"]).all()
    parameters = pd.read_csv(copy / RESULTS / "tables/model_parameters.csv")
    assert set(parameters["fitted_seeds"]) == {"1 2"} and set(parameters["fitted_on"]) == {"test"}
    stress = pd.read_csv(copy / RESULTS / "tables/protocol_stress_leaderboard.csv")
    assert set(stress["protocol"]) == {"back_from_90", "rotary"} and set(stress["quantity"]) == {"eta_r", "N1", "N2"}
    assert not stress["held_out"].any()
    for name in ("back_from_90", "rotary"):
        assert (copy / RESULTS / f"figures/protocol_{name}.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    ("segment", "key"),
    [
        ("{strain: -0.1, flow_angle_deg: 90}", "protocols.bad.1"),
        ("{strain: 0.1, angle: 90}", "protocols.bad.1"),
        ("{turning_deg_per_strain: 90}", "protocols.bad.1"),
    ],
)
def test_a_bad_segment_is_refused_before_any_job(study, segment, key):
    """Negative strain, an unknown key, a turning rate without a strain: an error naming the key."""
    result = snakemake(study, *TEST_CONFIG, "--config", f"protocols={{bad: [{{strain: 0.3}}, {segment}]}}", "-n")
    assert result.returncode != 0
    assert f"config key '{key}" in result.stdout + result.stderr
    assert "shear_segment" not in result.stdout

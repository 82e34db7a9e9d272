"""Which jobs a config change reruns: every rule receives exactly the settings that change its
result. On the finished test study (seeds 1, 2; angles 0, 90), each case changes config keys
with --config on top of --configfile config/test.yaml (the override idiom docs/workflow.md gives),
dry-runs, and checks (a) the jobs rerun for a reason of their own (their params, a missing
output, a changed set of inputs), not merely because an upstream job reruns, and (b) every
simulation job (pack; shear_segment: startup, rotations) in the plan. Everything else in the plan is downstream
of (a). Snakemake names only the first reason of a job whose inputs an upstream job updates,
so a key read by two rules in a chain (the force model and time step: a segment and the next;
run.startup_strain: startup and predict; particles.phi: pack and fit_models) shows the
upstream one (models.fabric: fit_models, not predict or benchmark_models);
test_params_of_downstream_rules checks the downstream rule on its own. The table is the rerun matrix of
docs/workflow.md."""

import re

import pytest

from suspension_fabric.study.config import SIMULATION_RUN_KEYS
from workflow_helpers import REPO, RESULTS, TEST_CONFIG, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow

SEEDS, ANGLES = (1, 2), (0, 90)
PACK = {("pack", f"seed={s}") for s in SEEDS}
STARTUP = {("shear_segment", f"seed={s}, run=startup") for s in SEEDS}
ROTATE = {("shear_segment", f"seed={s}, run=rotation_theta{a}") for s in SEEDS for a in ANGLES}
FABRIC = {
    ("fabric_table", f"seed={s}, run={run}")
    for s in SEEDS
    for run in ["startup"] + [f"rotation_theta{a}" for a in ANGLES]
}
SIMULATIONS = {"pack", "shear_segment"}

CASES = {
    # key(s) changed: (--config arguments, jobs with a reason of their own, simulation jobs)
    "run.rotation_strain": (["run={rotation_strain: 0.2}"], ROTATE, ROTATE),
    "run.startup_strain": (["run={startup_strain: 0.4}"], STARTUP, STARTUP | ROTATE),
    "run.dt": (["run={dt: 5.0e-5}"], STARTUP, STARTUP | ROTATE),
    "run.dump_strain": (["run={dump_strain: 0.02}"], STARTUP, STARTUP | ROTATE),
    "run.table_strain": (["run={table_strain: 0.005}"], STARTUP, STARTUP | ROTATE),
    "run.integrator, run.solver_tol": (["run={solver_tol: 1.0e-6}"], STARTUP, STARTUP | ROTATE),
    "run.initial_guess": (["run={initial_guess: linear}"], STARTUP, STARTUP | ROTATE),
    # at its default the key stays out of the simulations' settings: runs made before it keep
    "run.initial_guess at its default": (["run={initial_guess: previous}"], set(), set()),
    "forces.kn": (["forces={kn: 5.0e+5}"], STARTUP, STARTUP | ROTATE),
    "forces.eta_f": (["forces={eta_f: 1.1}"], STARTUP, STARTUP | ROTATE),
    "forces.mu": (["forces={mu: 0.4}"], STARTUP, STARTUP | ROTATE),
    "particles.n": (["particles={n: 50}"], PACK, PACK | STARTUP | ROTATE),
    "particles.phi": (["particles={phi: 0.44}"], PACK, PACK | STARTUP | ROTATE),
    "analysis.eps": (["analysis={eps: 0.02}"], FABRIC, set()),
    "analysis.steady_window": (
        ["analysis={steady_window: [0.15, 0.3]}"],
        {("aggregate_startup", ""), ("aggregate_stress_startup", ""), ("closure_tests", "")},
        set(),
    ),
    "models.polar_angle_step_deg": (["models={polar_angle_step_deg: 10}"], {("predict", "")}, set()),
    "models.fabric": (["models={fabric: [gw, modified]}"], {("fit_models", "")}, set()),
    "angles_deg (one added)": (
        ["angles_deg=[0, 90, 45]"],
        {("shear_segment", f"seed={s}, run=rotation_theta45") for s in SEEDS}
        | {(table, f"seed={s}, run=rotation_theta45") for s in SEEDS for table in ("fabric_table", "stress_table")}
        | {("aggregate_rotation", ""), ("aggregate_stress_rotation", ""), ("closure_tests", "")},
        {("shear_segment", f"seed={s}, run=rotation_theta45") for s in SEEDS},
    ),
    "seeds (one added)": (
        ["seeds=[1, 2, 3]"],
        {
            ("pack", "seed=3"),
            ("shear_segment", "seed=3, run=startup"),
            ("shear_segment", "seed=3, run=rotation_theta0"),
            ("shear_segment", "seed=3, run=rotation_theta90"),
            *(
                (table, f"seed=3, run={run}")
                for table in ("fabric_table", "stress_table")
                for run in ("startup", "rotation_theta0", "rotation_theta90")
            ),
            ("aggregate_startup", ""),
            ("aggregate_rotation", ""),
            ("aggregate_stress_startup", ""),
            ("aggregate_stress_rotation", ""),
            ("closure_tests", ""),
        },
        {
            ("pack", "seed=3"),
            ("shear_segment", "seed=3, run=startup"),
            ("shear_segment", "seed=3, run=rotation_theta0"),
            ("shear_segment", "seed=3, run=rotation_theta90"),
        },
    ),
    "verdicts.level": (
        ["verdicts={level: 0.9}"],
        {
            ("verdicts", ""),
            ("figure_claims", ""),
            ("stress_relation", ""),
            ("benchmark_models", ""),
            ("benchmark_stress_relations", ""),
            ("closure_tests", ""),
            ("error_decomposition", ""),
            ("discover_model", ""),
            ("nested_selection", ""),
        },
        set(),
    ),
    "verdicts.window": (
        ["verdicts={window: 0.05}"],
        {
            ("claims", ""),
            ("stress_relation", ""),
            ("benchmark_models", ""),
            ("benchmark_stress_relations", ""),
            ("closure_tests", ""),
            ("error_decomposition", ""),
            ("discover_model", ""),
            ("nested_selection", ""),
        },
        set(),
    ),
    "verdicts.models": (
        ["verdicts={models: {reference: modified, challenger: gw}}"],
        {("claims", ""), ("model_errors", ""), ("benchmark_models", ""), ("discover_model", "")},
        set(),
    ),
    "models.held_out_folds": (
        ["models={held_out_folds: 3}"],
        {
            ("benchmark_models", ""),
            ("benchmark_stress_relations", ""),
            ("discover_model", ""),
            ("nested_selection", ""),
        },
        set(),
    ),
    "models.stress": (["models={stress: [gw]}"], {("benchmark_stress_relations", "")}, set()),
    "analysis.lubrication_stress": (
        ["analysis={steady_window: [0.1, 0.3], lubrication_stress: stresslet}"],
        {("aggregate_stress_startup", ""), ("aggregate_stress_rotation", "")},
        set(),
    ),
    "checks, thermo and restart intervals": (
        [
            "run={thermo_strain: 0.02, restart_strain: 0.05, max_overlap: 0.02, max_stress_jitter: 0.6, "
            "max_contact_relaxation_strain: 0.02}"
        ],
        set(),
        set(),
    ),
}


def own_reason(reason: str) -> bool:
    """True unless the job reruns only because an upstream job does."""
    parts = [part.strip() for part in reason.split(";") if part.strip()]
    return any(not part.startswith("Input files updated by another job") for part in parts)


@pytest.mark.parametrize("case", list(CASES))
def test_a_config_change_reruns_exactly_the_jobs_that_depend_on_it(study, case):
    overrides, expected_roots, expected_simulations = CASES[case]
    result = snakemake(study, *TEST_CONFIG, "--config", *overrides, "-n")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    jobs = [job for job in dry_run_jobs(result.stdout + result.stderr) if job["rule"] != "all"]
    roots = {(job["rule"], job["wildcards"]) for job in jobs if own_reason(job["reason"])}
    simulations = {(job["rule"], job["wildcards"]) for job in jobs if job["rule"] in SIMULATIONS}
    assert roots == expected_roots, (sorted(roots - expected_roots), sorted(expected_roots - roots))
    assert simulations == expected_simulations, sorted(simulations ^ expected_simulations)
    if not expected_roots:
        assert "Nothing to be done" in result.stdout + result.stderr


@pytest.mark.parametrize(
    "rule, override",
    [
        ("predict", "run={startup_strain: 0.4}"),
        ("fit_models", "particles={phi: 0.44}"),
        ("predict", "models={fabric: [gw, modified]}"),
        ("benchmark_models", "models={fabric: [gw, modified]}"),
        ("benchmark_models", "run={startup_strain: 0.4}"),
        ("benchmark_models", "analysis={steady_window: [0.15, 0.3]}"),
        ("shear_segment", "forces={kn: 5.0e+5}"),
        ("shear_segment", "run={dt: 5.0e-5}"),
        ("shear_segment", "run={table_strain: 0.005}"),
    ],
)
def test_params_of_downstream_rules(study, rule, override):
    """A key read by a rule downstream of another that reads it too: planning one output of
    that rule alone with the changed key shows 'Params have changed' for it."""
    target = {
        "predict": "tables/predictions.csv",
        "fit_models": "fits.json",
        "benchmark_models": "tables/leaderboard.csv",
        "shear_segment": "seed1/startup/trajectory.dump",
    }[rule]
    result = snakemake(
        study, *TEST_CONFIG, "--config", override, "-n", "--allowed-rules", rule, "--", f"{RESULTS}/{target}"
    )
    reasons = {job["rule"]: job["reason"] for job in dry_run_jobs(result.stdout + result.stderr)}
    assert "Params have changed" in reasons.get(rule, ""), (result.stdout + result.stderr)[-2000:]


@pytest.mark.parametrize("override", ["forces={kn: 5.0e+5}", "run={dt: 5.0e-5}", "run={table_strain: 0.005}"])
def test_a_segment_after_another_has_the_changed_params_itself(study, override):
    """A dry run names only the first reason of a rotation whose startup reruns; Snakemake's list of
    outputs whose params changed shows that the rotation's own params change too (one rule runs every
    segment, each with the study's simulation settings)."""
    result = snakemake(study, *TEST_CONFIG, "--config", override, "--list-changes", "params")
    assert result.returncode == 0, (result.stdout + result.stderr)[-2000:]
    changed = set(result.stdout.split())
    for seed in (1, 2):
        for run in ("startup", "rotation_theta0", "rotation_theta90"):
            assert f"{RESULTS}/seed{seed}/{run}/trajectory.dump" in changed, (run, result.stdout[-2000:])


def test_the_docs_rerun_table_names_every_run_key_a_simulation_depends_on():
    """docs/workflow.md's rerun table names each run key in config.SIMULATION_RUN_KEYS (each reruns every
    simulation; the cases above check some of them)."""
    text = (REPO / "docs" / "workflow.md").read_text()
    table = text[text.index("| key changed |") :].split("\n\n")[0]
    named = set(re.findall(r"`run\.(\w+)`", table))
    assert set(SIMULATION_RUN_KEYS) <= named, sorted(set(SIMULATION_RUN_KEYS) - named)

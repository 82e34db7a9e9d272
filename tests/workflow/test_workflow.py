"""The Snakemake workflow end to end: a real run of config/test.yaml (real LAMMPS, real
MDAnalysis, real fits), the rerun commands of docs/workflow.md as dry runs, the DAG, the report,
the linter and the schema errors.

The workflow files are copied into a temporary folder so the test never touches the
repository's results/.
"""

import json
import re
import shutil

import pandas as pd
import pytest
import yaml

from workflow_helpers import REPO, RESULTS, TEST_CONFIG, copy_workflow, dry_run_jobs, job_counts, snakemake

pytestmark = pytest.mark.workflow


def test_study_produces_figures_fits_and_error_table(study):
    results = study / RESULTS
    for stem in ("fig1_startup", "fig2_rotation", "fig5_claims"):
        for ext in ("pdf", "png"):
            assert (results / "figures" / f"{stem}.{ext}").stat().st_size > 10_000
    fits = json.loads((results / "fits.json").read_text())
    assert fits["format"] == 2
    gw, modified = (fits["models"][key]["parameters"] for key in ("gw", "modified"))
    assert gw["beta"] > 0 and modified["beta"] > 0 and modified["A"] >= 0
    assert fits["targets"]["n12"]["mean"] < 0  # contacts along the compression axis
    assert fits["provenance"]["seeds"] == [1, 2]
    errors = pd.read_csv(results / "tables" / "model_errors.csv")
    rotation = errors[errors["protocol"] == "rotation"]
    assert sorted(rotation["theta"].unique()) == [0.0, 90.0]
    assert set(rotation["model"]) == {"gw", "modified", "separate_rates"}  # models.fabric (default list)
    runs = pd.read_csv(results / "tables" / "rotation_runs.csv")
    assert sorted(runs["seed"].unique()) == [1, 2]
    # the closures against the measured fourth moment: every closure, both measures, both seeds
    closures = pd.read_csv(results / "tables" / "closure_errors.csv")
    assert set(closures["closure"]) == {"linear", "quadratic", "hybrid"} and set(closures["measure"]) == {
        "full",
        "drive",
    }
    assert set(zip(closures["protocol"], closures["theta"])) == {
        ("startup", 0.0),
        ("rotation", 0.0),
        ("rotation", 90.0),
    }
    assert (closures["n_seeds"] == 2).all() and (closures["mean"] > 0).all()
    assert (results / "figures" / "closures.png").stat().st_size > 10_000


def test_study_produces_the_stress_tables_figures_and_relation(study):
    """The stress (issue: tables/stress_*.csv, fig3_stress, fig4_stress_rotation): per-run tables
    on the fabric's frames, seed aggregates, the steady state, the G-W stress relation fitted per
    fabric source (reproducing the steady lubrication and contact sigma_12 it was fitted to, so
    eta_r but for the kinetic part) and its error table over both protocols and every angle."""
    import numpy as np

    results = study / RESULTS
    for stem in ("fig3_stress", "fig4_stress_rotation"):
        for ext in ("pdf", "png"):
            assert (results / "figures" / f"{stem}.{ext}").stat().st_size > 10_000
    for seed in (1, 2):
        for run in ("startup", "rotation_theta0", "rotation_theta90"):
            fabric = pd.read_csv(results / f"seed{seed}/{run}/fabric.csv")
            stress = pd.read_csv(results / f"seed{seed}/{run}/stress.csv")
            assert stress["step"].tolist() == fabric["step"].tolist()
            assert (stress["n_rows"] >= 1).all()
            np.testing.assert_allclose(stress["solvent_12"], 1.0)
            np.testing.assert_allclose(stress["einstein_12"], 2.5 * fabric["phi"])
            parts = sum(stress[f"{p}_12"] for p in ("contact", "lubrication", "kinetic", "solvent", "einstein"))
            np.testing.assert_allclose(stress["total_12"], parts, rtol=1e-8)  # 9 digits written
    steady = pd.read_csv(results / "tables/stress_steady_state.csv").set_index("quantity")
    assert steady.loc["eta_r", "mean"] > 1 + 2.5 * 0.45 and steady.loc["Pi", "mean"] > 0
    aggregate = pd.read_csv(results / "tables/stress_rotation_aggregate.csv")
    assert sorted(aggregate["theta"].unique()) == [0.0, 90.0] and (aggregate["n_seeds"] == 2).all()
    relation = pd.read_csv(results / "tables/stress_relation_fits.csv")
    assert relation["source"].tolist() == ["simulation", "gw", "modified", "separate_rates"]
    assert (relation["a_H"] > 0).all() and (relation["a_C"] > 0).all()
    # the relation reproduces the steady contact and lubrication sigma_12 it was fitted to; it
    # has no kinetic part (O(1/eta_f), larger in this study's eta_f = 1)
    np.testing.assert_allclose(
        relation["eta_r_predicted"], steady.loc["eta_r", "mean"] - steady.loc["kinetic_12", "mean"], rtol=1e-6
    )
    errors = pd.read_csv(results / "tables/stress_model_errors.csv")
    assert set(errors["source"]) == {"simulation", "gw", "modified", "separate_rates"}
    assert sorted(errors[errors["protocol"] == "rotation"]["theta"].unique()) == [0.0, 90.0]
    transients = pd.read_csv(results / "tables/stress_viscosity_transients.csv")
    assert transients["theta"].tolist() == [0.0, 90.0]
    # the deficit over verdicts.window = 0.1 per seed, each against its own steady eta_r
    assert (transients["window"] == 0.1).all() and (transients["level"] == 0.95).all()
    assert (transients["n_seeds"] == 2).all()
    assert (transients["deficit_low"] <= transients["deficit"]).all()
    assert (transients["deficit"] <= transients["deficit_high"]).all()
    for name in ("minimum", "strain_at_min", "recovery_strain"):
        assert (transients[f"{name}_low"] <= transients[f"{name}_high"]).all()
    deficits = pd.read_csv(results / "tables/stress_viscosity_deficit_per_seed.csv")
    assert list(deficits.columns) == ["seed", "theta", "window", "eta_ss_seed", "deficit"]
    assert len(deficits) == 4 and (deficits["window"] == 0.1).all()
    np.testing.assert_allclose(deficits.groupby("theta")["deficit"].mean(), transients["deficit"], rtol=1e-12)
    np.testing.assert_allclose(
        deficits.groupby("seed")["eta_ss_seed"].first().mean(), steady.loc["eta_r", "mean"], rtol=1e-12
    )


def test_lubrication_stress_choice_reaches_the_relation(study, tmp_path):
    """analysis.lubrication_stress = stresslet (on a copy of the finished study): only the stress
    aggregates and what follows rerun; the steady lubrication_12 is then the seed mean of the
    runs' stresslet_12, the relation is fitted on it, and the particle pressure Pi loses the
    dipoles' trace (the stresslets are traceless, so Pi = contact + kinetic only)."""
    import numpy as np

    copy = tmp_path / "study"
    shutil.copytree(study, copy, symlinks=True)
    override = ["--config", "analysis={steady_window: [0.1, 0.3], lubrication_stress: stresslet}"]
    counts = job_counts(snakemake(copy, *TEST_CONFIG, *override, "-n").stdout)
    assert counts["aggregate_stress_startup"] == 1 and counts["stress_relation"] == 1
    for rule in ("shear_segment", "stress_table", "fabric_table", "aggregate_startup", "fit_models"):
        assert rule not in counts
    result = snakemake(
        copy,
        *TEST_CONFIG,
        *override,
        "--allowed-rules",
        "aggregate_stress_startup",
        "aggregate_stress_rotation",
        "stress_relation",
        "--",
        f"{RESULTS}/tables/stress_relation_fits.csv",
    )
    assert result.returncode == 0, result.stderr[-3000:]
    tables = copy / RESULTS / "tables"
    steady = pd.read_csv(tables / "stress_steady_state.csv").set_index("quantity")
    dipole = pd.read_csv(study / RESULTS / "tables/stress_steady_state.csv").set_index("quantity")
    runs = pd.read_csv(tables / "stress_startup_runs.csv")
    inside = runs[(runs["strain"] >= 0.1) & (runs["strain"] <= 0.3)]
    np.testing.assert_allclose(
        steady.loc["lubrication_12", "mean"], inside.groupby("seed")["stresslet_12"].mean().mean(), rtol=1e-9
    )
    assert steady.loc["lubrication_12", "mean"] != dipole.loc["lubrication_12", "mean"]
    np.testing.assert_allclose(steady.loc["contact_12", "mean"], dipole.loc["contact_12", "mean"], rtol=1e-12)
    particle_trace = sum(inside[f"{p}_{c}"] for p in ("contact", "kinetic") for c in ("11", "22", "33"))
    np.testing.assert_allclose(
        steady.loc["Pi", "mean"], (-particle_trace / 3).groupby(inside["seed"]).mean().mean(), rtol=1e-6, atol=1e-9
    )
    relation = pd.read_csv(tables / "stress_relation_fits.csv").set_index("source")
    np.testing.assert_allclose(
        relation.loc["simulation", "eta_r_predicted"],
        steady.loc["eta_r", "mean"] - steady.loc["kinetic_12", "mean"],
        rtol=1e-6,
    )


def test_study_decides_the_claims_per_seed(study):
    """Rule claims: per seed and angle, the statistics and T of every claim under every choice the
    test study allows (its window 0.1 is the whole rotation run, so no other window); rule
    verdicts: each claim's T averaged over its angles within a seed, then the t-interval over
    the 2 seeds (t_{0.975,1} = 12.706), per angle, and the choices table."""
    import numpy as np
    from scipy import stats

    tables = study / RESULTS / "tables"
    values = pd.read_csv(tables / "claims_values.csv")
    assert list(dict.fromkeys(values["choice"])) == [
        "primary",
        "state: simulated",
        "state: model steady",
        "fit: startup curve",
        "fit: paper's values",
        "baseline: theta = 0",
    ]
    primary = values[values["choice"] == "primary"]
    assert sorted(primary["seed"].unique()) == [1, 2]
    assert set(primary[primary["claim"] == "C2"]["theta"]) == {90.0}  # 0 (and 180) left out of the 23 claims
    fits = pd.read_csv(tables / "claims_seed_fits.csv")
    assert len(fits) == 2 * 6 and (fits["reference_beta"] > 0).all() and set(fits["challenger"]) == {"modified"}
    verdicts = pd.read_csv(tables / "verdicts.csv").set_index("claim")
    c1 = primary[(primary["claim"] == "C1") & (primary["theta"] == 90.0)].set_index("seed")["T"]
    half = stats.t.ppf(0.975, 1) * c1.std(ddof=1) / np.sqrt(2)
    assert verdicts.loc["C1", "angles"] == "90"
    np.testing.assert_allclose(
        verdicts.loc["C1", ["mean", "low", "high"]].to_numpy(dtype=float),
        [c1.mean(), c1.mean() - half, c1.mean() + half],
        rtol=1e-9,
    )
    assert verdicts.loc["C2", "angles"] == "90" and verdicts.loc["C3'", "angles"] == "0, 90"
    choices = pd.read_csv(tables / "verdict_choices.csv")
    assert set(choices["choice"]) == set(values["choice"]) and choices["robust"].notna().all()
    per_angle = pd.read_csv(tables / "claims_per_angle.csv")
    assert set(per_angle[per_angle["claim"] == "C1"]["theta"]) == {0.0, 90.0}
    for name in ("recovery_table", "rotation_rms_errors", "overshoot_table", "claims_range_edges"):
        assert (tables / f"{name}.csv").is_file()


def test_nothing_left_to_do_after_a_run(study):
    result = snakemake(study, *TEST_CONFIG, "-n")
    assert result.returncode == 0
    assert "Nothing to be done" in result.stdout + result.stderr


def test_rerun_one_angle_one_seed(study):
    """docs/workflow.md: rerun theta = 90 for seed 1 and everything downstream; no startup, no other angle."""
    result = snakemake(study, *TEST_CONFIG, "-n", "-R", f"{RESULTS}/seed1/rotation_theta90/trajectory.dump")
    counts = job_counts(result.stdout)
    assert counts["shear_segment"] == 1 and counts["fabric_table"] == 1
    assert counts["aggregate_rotation"] == 1 and counts["figure_rotation"] == 1 and counts["figure_startup"] == 1
    for rule in ("pack", "aggregate_startup", "fit_models"):
        assert rule not in counts
    wildcards = {job["wildcards"] for job in dry_run_jobs(result.stdout) if job["wildcards"]}
    assert wildcards == {"seed=1, run=rotation_theta90"}, wildcards


def test_rerun_one_angle_all_seeds(study):
    targets = [f"{RESULTS}/seed{s}/rotation_theta90/trajectory.dump" for s in (1, 2)]
    result = snakemake(study, *TEST_CONFIG, "-n", "-R", *targets)
    counts = job_counts(result.stdout)
    assert counts["shear_segment"] == 2 and counts["fabric_table"] == 2
    assert "pack" not in counts
    shears = {job["wildcards"] for job in dry_run_jobs(result.stdout) if job["rule"] == "shear_segment"}
    assert shears == {"seed=1, run=rotation_theta90", "seed=2, run=rotation_theta90"}


def test_regenerate_figures_only(study):
    """docs/workflow.md: regenerate the figures from existing results, nothing else."""
    counts = job_counts(snakemake(study, *TEST_CONFIG, "-n", "-R", "figure_startup", "figure_rotation").stdout)
    assert set(counts) == {"figure_startup", "figure_rotation", "all", "total"}


def test_every_figure_depends_on_every_stage(study):
    """In the rule graph, each figure rule has all simulation and analysis rules as ancestors."""
    dot = snakemake(study, *TEST_CONFIG, "--rulegraph").stdout
    names = dict(re.findall(r'(\d+)\[label = "(\w+)"', dot))
    parents = {}
    for src, dst in re.findall(r"(\d+) -> (\d+)", dot):
        parents.setdefault(names[dst], set()).add(names[src])

    def ancestors(rule):
        seen, todo = set(), [rule]
        while todo:
            for parent in parents.get(todo.pop(), ()):
                if parent not in seen:
                    seen.add(parent)
                    todo.append(parent)
        return seen

    upstream = {
        "pack",
        "shear_segment",
        "fabric_table",
        "aggregate_startup",
        "aggregate_rotation",
        "fit_models",
        "predict",
    }
    for figure in ("figure_startup", "figure_rotation"):
        assert upstream <= ancestors(figure), upstream - ancestors(figure)
    stress_upstream = upstream | {
        "stress_table",
        "aggregate_stress_startup",
        "aggregate_stress_rotation",
        "stress_relation",
    }
    for figure in ("figure_stress_startup", "figure_stress_rotation"):
        assert stress_upstream <= ancestors(figure), stress_upstream - ancestors(figure)


def test_report_has_both_figures(study):
    result = snakemake(study, *TEST_CONFIG, "--report", "report.html", timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]
    html = (study / "report.html").read_text(errors="replace")
    for stem in ("fig1_startup", "fig2_rotation", "fig3_stress", "fig4_stress_rotation"):
        assert f"{stem}.png" in html, stem


def test_lint_is_clean():
    result = snakemake(REPO, *TEST_CONFIG, "--lint")
    assert result.returncode == 0, result.stdout[-3000:]


def test_every_rule_the_slurm_profile_sizes_is_a_rule_of_the_workflow():
    """A rule renamed without its profile entry would run with the default 10-minute limit and,
    with several MPI ranks, wrapped in the executor's srun, where mpirun's own srun never starts."""
    profile = yaml.safe_load((REPO / "profiles" / "slurm" / "config.yaml").read_text())
    sources = [REPO / "Snakefile", *sorted((REPO / "workflow" / "rules").glob("*.smk"))]
    rules = {name for path in sources for name in re.findall(r"^rule (\w+):", path.read_text(), flags=re.M)}
    assert "shear_segment" in rules
    assert set(profile["set-resources"]) <= rules, set(profile["set-resources"]) - rules


@pytest.mark.parametrize(
    "section, value, message",
    [
        ("particles", {"n": "many"}, "config key 'particles.n'"),
        ("run", {"dtt": 1.0}, "'dtt' was unexpected"),
        ("angles_deg", [0, 270], "config key 'angles_deg.1'"),
        ("analysis", {"steady_window": [3.0, 9.0]}, "config key 'analysis.steady_window'"),
    ],
)
def test_bad_config_stops_before_any_job(tmp_path, section, value, message):
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((workdir / "config" / "test.yaml").read_text())
    config[section] = value
    (workdir / "config" / "bad.yaml").write_text(yaml.safe_dump(config))
    result = snakemake(workdir, "--configfile", "config/bad.yaml")
    assert result.returncode != 0
    assert message in result.stdout + result.stderr
    assert not (workdir / "results").exists()


def test_report_shows_the_tables(study):
    """The report holds fits.json, the steady state and the error summary as captioned HTML tables."""
    import base64
    import html as html_module

    from suspension_fabric.reporting.html_tables import format_value_error

    result = snakemake(study, *TEST_CONFIG, "--report", "report_tables.html", timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]
    html = (study / "report_tables.html").read_text(errors="replace")
    pages = {
        name: base64.b64decode(data).decode("utf-8")
        for name, data in re.findall(r"data:text/html;charset=utf-?8;filename=([\w.]+);base64,([A-Za-z0-9+/=]+)", html)
    }
    assert set(pages) == {
        "fits.html",
        "steady_state.html",
        "model_errors_summary.html",
        "verdicts.html",
        "stress.html",
        "stress_leaderboard.html",
        "leaderboard.html",
    }, set(pages)
    for caption in (
        "Fitted model parameters (fits.json)",
        "Steady state of startup shear",
        "Model versus simulation (tables/model_errors_summary.csv)",
    ):
        assert caption in html  # the report captions (workflow/report/table_*.rst)
    fits = json.loads((study / RESULTS / "fits.json").read_text())
    for model, parameter in (("gw", "beta"), ("modified", "beta"), ("modified", "A")):
        entry = fits["models"][model]
        fitted = entry["parameters"][parameter]
        shown = format_value_error(fitted, entry["errors"][parameter])
        assert f"<td>{shown}</td>" in pages["fits.html"], (shown, pages["fits.html"])
        value, error = shown.split(" ± ")  # the fitted value itself, rounded to its error's last digit
        tolerance = 1e-3 * abs(fitted) if error == "—" else 0.1 * float(error)  # "—": null error
        assert abs(float(value) - fitted) <= tolerance, shown
    assert "<caption>Every model of models.fabric fitted to the steady state</caption>" in pages["fits.html"]
    assert "<caption>Simulated steady state" in pages["steady_state.html"]
    assert "<td>⟨nn⟩₁₂</td>" in pages["steady_state.html"]
    assert "<caption>Angle-averaged rms error" in pages["model_errors_summary.html"]
    verdicts = pd.read_csv(study / RESULTS / "tables/verdicts.csv")
    assert "<caption>Each claim of the paper" in pages["verdicts.html"]
    for claim, text in zip(verdicts["claim"], verdicts["text"]):
        assert f"<td>{html_module.escape(claim)}</td>" in pages["verdicts.html"], claim
        assert html_module.escape(text) in pages["verdicts.html"], text
    assert set(verdicts["verdict"].fillna("")) <= {"", "confirmed", "refuted", "undecided"}
    assert "<caption>The choices each verdict may hinge on" in pages["verdicts.html"]
    relation = pd.read_csv(study / RESULTS / "tables/stress_relation_fits.csv")
    assert "<caption>G-W stress relation" in pages["stress.html"]
    for value, error in zip(relation["a_H"], relation["a_H_err"]):
        assert f"<td>{format_value_error(value, error)}</td>" in pages["stress.html"]


def fabric_tensor(row):
    import numpy as np

    return np.array(
        [
            [row["n11"], row["n12"], row["n13"]],
            [row["n12"], row["n22"], row["n23"]],
            [row["n13"], row["n23"], row["n33"]],
        ]
    )


@pytest.mark.parametrize("theta_deg", [0, 90])
def test_a_rotation_is_analysed_in_its_own_frame(study, theta_deg):
    """The first frame after a rotation by theta is the checkpoint itself, seen in the rotated
    paper frame e1' = cos(theta) e1 - sin(theta) e3, e2' = e2, e3' = sin(theta) e1 + cos(theta) e3:
    <nn>' = R <nn> R^T with those rows as R, for every component (so n12' = cos(theta) n12 -
    sin(theta) n23 and n23' = sin(theta) n12 + cos(theta) n23), from the last startup frame of
    the same seed. A rotation analysed in the wrong frame, or with the wrong sign of theta,
    fails for theta = 90 (there n12' = -n23 and n23' = n12)."""
    import numpy as np

    c, s = np.cos(np.radians(theta_deg)), np.sin(np.radians(theta_deg))
    rotation = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
    for seed in (1, 2):
        startup = pd.read_csv(study / RESULTS / f"seed{seed}/startup/fabric.csv")
        rotated = pd.read_csv(study / RESULTS / f"seed{seed}/rotation_theta{theta_deg}/fabric.csv")
        last, first = startup.iloc[-1], rotated.iloc[0]
        assert first["strain"] == 0.0 and first["step"] == last["step"]
        expected = rotation @ fabric_tensor(last) @ rotation.T
        np.testing.assert_allclose(fabric_tensor(first), expected, rtol=0, atol=1e-9)
        assert abs(last["n12"]) > 0.01 and first["Z"] == last["Z"]


def test_command_line_overrides_on_the_default_study(tmp_path):
    """`--config` without `--configfile` overrides the default study (config/config.yaml)
    key by key, nested sections too, validated like a file: the default study's 4 seeds x
    13 angles plan survives a run.rotation_strain override; run.startup_strain = 3 meets the
    default study's own analysis.steady_window [2, 5] in the cross-key check (so the override
    took effect and the rest of config.yaml was kept); a bad value names its key."""
    workdir = copy_workflow(tmp_path)
    shutil.copytree(REPO / "data", workdir / "data")  # the datasets the default study compares with
    result = snakemake(workdir, "-n", "--config", "run={rotation_strain: 2.5}")
    assert result.returncode == 0, (result.stdout + result.stderr)[-3000:]
    counts = job_counts(result.stdout)
    assert counts["shear_segment"] == 4 + 52
    merged = snakemake(workdir, "-n", "--config", "run={startup_strain: 3}")
    assert merged.returncode != 0
    assert (
        "config key 'analysis.steady_window': need 0 <= min < max <= run.startup_strain (3), got [2.0, 5.0]"
    ) in merged.stdout + merged.stderr
    bad = snakemake(workdir, "-n", "--config", "run={rotation_strain: -1}")
    assert bad.returncode != 0 and "config key 'run.rotation_strain'" in bad.stdout + bad.stderr

"""Configs refused early and precisely: every case below passed validation (or failed with a message
naming no file, line or key) and could only fail late, after simulations ran; now each is refused
before any job, naming the file (or --config), the key and what was expected. The files are real
YAML in tmp_path, read as the workflow reads them: Snakemake's own parse (load_configfile,
parse_config) for the config, the study module's strict reading for the sources."""

import re

import pytest
import yaml
from snakemake.cli import parse_config
from snakemake.common.configfile import load_configfile
from snakemake.utils import update_config

from suspension_fabric.study.campaign import campaign_points, is_flow_curve_campaign, study_configs
from suspension_fabric.study.config import (
    ConfigError,
    check_comparison,
    check_complete_study,
    frames_between,
    load_config,
    read_config_file,
    read_config_sources,
    study_run_tree,
    validate_config,
)
from suspension_fabric.study.validate import main
from workflow_helpers import REPO, copy_workflow, snakemake

#: config/test.yaml: dt 1e-4, startup 0.3, rotations 0.1, a frame every 0.01, steady window [0.1, 0.3]
TEST_STUDY = (REPO / "config" / "test.yaml").read_text()


@pytest.fixture(autouse=True)
def in_tmp_path(tmp_path, monkeypatch):
    """Files are named relative to the working directory, as a user gives them."""
    monkeypatch.chdir(tmp_path)


def study_file(tmp_path, text=TEST_STUDY, name="study.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def workflow_config(files, *entries):
    """The config as the Snakefile gets it (Snakemake's parse of the files, then --config) and its
    sources read strictly (Snakefile: read_config_sources), validated with them."""
    sources = read_config_sources(files, list(entries))
    config = {}
    for path in files:
        update_config(config, load_configfile(str(path)))
    update_config(config, parse_config(list(entries)))
    return validate_config(config, sources=sources), sources


def refused(files, *entries, complete=False):
    """The message of the ConfigError the workflow stops with before any job."""
    with pytest.raises(ConfigError) as caught:
        config, sources = workflow_config(files, *entries)
        for study in study_configs(config, sources).values():
            if complete:  # the default target (rule all's input function)
                check_complete_study(study, sources)
    return str(caught.value)


def with_keys(text, **sections):
    """``text`` (a study file) with the given top-level sections merged in, as YAML."""
    config = yaml.safe_load(text)
    update_config(config, sections)
    return yaml.safe_dump(config, sort_keys=False)


# ----------------------------------------------------------------------------- 1. repeated keys
@pytest.mark.fault("refused")
def test_a_section_given_twice_is_refused_naming_file_and_both_lines(tmp_path):
    """The user's case: a second `forces:` section replaced the first, so the study ran with the
    default kn and eta_f; now both lines are named."""
    path = study_file(tmp_path, TEST_STUDY + "forces:\n  mu: 0.3\n")
    first = TEST_STUDY.splitlines().index("forces:") + 1
    second = len(TEST_STUDY.splitlines()) + 1
    message = refused([path])
    assert message.startswith(f"study.yaml, line {second}, column 1: config key 'forces' is given twice")
    assert f"first at line {first}, column 1" in message
    assert load_configfile(str(path))["forces"] == {"mu": 0.3}  # what Snakemake alone would have run


@pytest.mark.fault("refused")
def test_a_nested_key_given_twice_is_refused_with_its_path(tmp_path):
    path = study_file(tmp_path, TEST_STUDY.replace("  dt: 1.0e-4", "  dt: 1.0e-4\n  dt: 5.0e-5"))
    message = refused([path])
    assert re.match(r"study\.yaml, line \d+, column 3: config key 'run\.dt' is given twice \(first at line", message)


def test_the_same_key_in_two_mappings_is_no_repetition(tmp_path):
    """`n` in particles and in a protocol name, `strain` in every segment: not repeated keys."""
    protocols = {"back": [{"strain": 0.3}, {"strain": 0.1, "flow_angle_deg": 180}]}
    config, _ = workflow_config([study_file(tmp_path, with_keys(TEST_STUDY, protocols=protocols))])
    assert config["protocols"]["back"][1]["strain"] == 0.1


# ----------------------------------------------------------------------------- 2. YAML errors
@pytest.mark.fault("refused")
def test_a_yaml_syntax_error_names_file_line_and_column(tmp_path, capsys):
    """Snakemake's own message for this file names neither file nor line, and comes before the
    Snakefile runs for a --configfile (so `python -m suspension_fabric.study.validate` is the way
    there); the default config/config.yaml is read strictly before Snakemake reads it."""
    path = study_file(tmp_path, TEST_STUDY.replace("seeds: [1, 2]", "seeds: [1, 2"))
    line = TEST_STUDY.splitlines().index("seeds: [1, 2]") + 1
    with pytest.raises(ConfigError) as caught:
        read_config_file(path)
    message = str(caught.value)
    # the parser notices at the next line's colon; the bracket it opened is named too
    assert message.startswith(f"study.yaml, line {line + 1}, column 11: not valid YAML: expected ',' or ']'")
    assert f"(while parsing a flow sequence at line {line}, column 8)" in message
    with pytest.raises(ConfigError, match=r"^study\.yaml, line"):
        load_config(path)
    assert main(["study.yaml"]) == 1  # the check for a --configfile Snakemake cannot parse
    assert capsys.readouterr().err.startswith(f"study.yaml, line {line + 1}, column 11: not valid YAML")


@pytest.mark.fault("refused")
def test_a_malformed_command_line_value_names_config_and_column(tmp_path):
    """Snakemake keeps a --config value it cannot parse as text; where the schema wants a mapping
    that text is refused naming --config, the key and the column; for a text key it stays text."""
    files = [study_file(tmp_path)]
    message = refused(files, "run={rotation_strain: 0.1")
    assert message.startswith("--config run, column 22 of the value: not valid YAML: expected ',' or '}'")
    config, _ = workflow_config(files, "dataset={not yaml")
    assert config["dataset"] == "{not yaml"  # text, as Snakemake gives it (the dataset check names it)


@pytest.mark.fault("refused")
def test_a_key_repeated_on_the_command_line_is_refused(tmp_path):
    files = [study_file(tmp_path)]
    message = refused(files, "run={dt: 1.0e-4, dt: 5.0e-5}")
    assert message.startswith("--config run, column 14 of the value: config key 'run.dt' is given twice")
    message = refused(files, "run={rotation_strain: 0.2}", "run={rotation_strain: 0.1}")
    assert message.startswith("--config: config key 'run.rotation_strain' is given twice")
    config, _ = workflow_config(files, "run={rotation_strain: 0.2}", "analysis={eps: 0.02}")
    assert config["run"]["rotation_strain"] == 0.2 and config["analysis"]["eps"] == 0.02


@pytest.mark.parametrize(
    "text, message",
    [("# only a comment\n", "holds no config keys"), ("- study: x\n", "top level must be a mapping")],
)
@pytest.mark.fault("refused")
def test_an_empty_or_list_file_is_refused_naming_it(tmp_path, text, message):
    with pytest.raises(ConfigError, match=f"^study.yaml: .*{message}"):
        read_config_file(study_file(tmp_path, text))


@pytest.mark.fault("refused")
def test_a_validation_error_names_the_file_or_the_command_line_that_set_the_key(tmp_path):
    files = [study_file(tmp_path, TEST_STUDY.replace("n: 40", "n: many"))]
    assert refused(files).startswith("study.yaml: config key 'particles.n': 'many' is not of type 'integer'")
    assert refused([study_file(tmp_path, name="ok.yaml")], "run={rotation_strain: -1}").startswith(
        "--config: config key 'run.rotation_strain'"
    )


@pytest.mark.workflow
@pytest.mark.fault("refused")
def test_the_workflow_stops_on_a_repeated_section_before_any_job(tmp_path):
    """The one Snakemake run: the Snakefile reads its --configfile again strictly."""
    workdir = copy_workflow(tmp_path)
    (workdir / "config" / "twice.yaml").write_text(TEST_STUDY + "forces:\n  mu: 0.3\n")
    first, second = TEST_STUDY.splitlines().index("forces:") + 1, len(TEST_STUDY.splitlines()) + 1
    result = snakemake(workdir, "-n", "--configfile", "config/twice.yaml", timeout=300)
    output = result.stdout + result.stderr
    assert result.returncode != 0
    assert (
        f"config/twice.yaml, line {second}, column 1: config key 'forces' is given twice (first at line {first},"
    ) in output
    assert not (workdir / "results").exists()


# ----------------------------------------------------------------------------- 3. paths
@pytest.mark.parametrize("name", ["..", ".", "a/b", "/tmp/x", ".hidden", "../up"])
@pytest.mark.fault("refused")
def test_a_study_name_must_stay_inside_results(tmp_path, name):
    message = refused([study_file(tmp_path, with_keys(TEST_STUDY, study=name))])
    assert message.startswith("study.yaml: config key 'study':") and "folder name inside results/" in message


@pytest.mark.fault("refused")
def test_a_campaign_override_may_not_move_or_rename_a_point(tmp_path):
    """Point names (phi<phi>_mu<mu>) are made from numbers, so they stay inside results/<study>/;
    an override of the point's study, phi or mu was dropped or belied the name."""
    grid = {"phi": [0.4, 0.45], "mu": [0.5]}
    for override, key in [
        ({"study": ".."}, "study"),
        ({"particles": {"phi": 0.5}}, "particles.phi"),
        ({"forces": {"mu": 1.0}}, "forces.mu"),
    ]:
        text = with_keys(TEST_STUDY, campaign={**grid, "overrides": {"phi0.45_mu0.5": override}})
        message = refused([study_file(tmp_path, text)])
        assert message.startswith(f"study.yaml: config key 'campaign.overrides.phi0.45_mu0.5.{key}'"), message
    text = with_keys(
        TEST_STUDY, campaign={**grid, "datasets": "data/x", "overrides": {"phi0.40_mu0.5": {"dataset": "y"}}}
    )
    assert "campaign.overrides.phi0.40_mu0.5.dataset" in refused([study_file(tmp_path, text)])
    text = with_keys(TEST_STUDY, campaign={**grid, "overrides": {"phi0.45_mu0.5": {"run": {"rotation_strain": 0.2}}}})
    config, _ = workflow_config([study_file(tmp_path, text)])
    assert list(campaign_points(config)) == ["phi0.40_mu0.5", "phi0.45_mu0.5"]


@pytest.mark.fault("refused")
def test_a_comparison_label_may_not_replace_the_study_or_a_verdict_choice(tmp_path):
    """The labels are no paths, but they share the verdict-choices and dataset-comparison tables
    with the study's name and its choices: 'primary' replaced the study's own verdicts."""
    config, _ = workflow_config([study_file(tmp_path)])
    dataset = load_config(REPO / "config" / "test.yaml")
    taken = ["test", "primary", "state: simulated"]
    for label in ("primary", "test"):
        with pytest.raises(ConfigError, match=f"^config key 'verdicts.comparisons': '{label}' is also the name"):
            check_comparison(config, label, dataset, taken=taken)
    check_comparison(config, "N = 40 again", dataset, taken=taken)


# ----------------------------------------------------------------------------- 4. combinations
@pytest.mark.fault("refused")
def test_one_seed_is_refused_for_the_full_study_only(tmp_path):
    """The model benchmarks fit over >= 2 seeds (rule benchmark_models failed after every simulation);
    one seed still validates, for single targets (a seed's startup, as tests/simulation/test_resume.py runs)."""
    files = [study_file(tmp_path, with_keys(TEST_STUDY, seeds=[1]))]
    config, _ = workflow_config(files)
    assert config["seeds"] == [1]
    message = refused(files, complete=True)
    assert message.startswith(
        "study.yaml: config key 'seeds' ([1]) of study test: its full set of outputs needs at least 2"
    )


@pytest.mark.fault("refused")
def test_one_angle_is_refused_for_the_full_study_only(tmp_path):
    """The held-out folds are capped at the number of angles and need two (benchmark_models failed late)."""
    message = refused([study_file(tmp_path, with_keys(TEST_STUDY, angles_deg=[0]))], complete=True)
    assert (
        message.startswith("study.yaml: config key 'angles_deg' ([0]) of study test") and "at least 2 angles" in message
    )


@pytest.mark.fault("refused")
@pytest.mark.parametrize(
    ("table", "message"),
    [
        (None, "file not found"),
        ("model,mode,parameter,value\ngw,steady,beta,11\n", "no column ['fitted_on', 'fitted_seeds', 'fitted_runs']"),
        (
            "model,mode,parameter,value,fitted_on,fitted_seeds,fitted_runs\ngw,steady,beta,11,ref,1 2,startup\n",
            "no fits of the models ['modified', 'separate_rates']",
        ),
    ],
)
def test_parameters_from_must_say_what_its_fits_saw_and_fit_every_model(tmp_path, table, message):
    """models.parameters_from: another study's fits are taken only with their provenance (else no
    score could be called held out) and for every model the study scores."""
    if table is not None:
        (tmp_path / "fits.csv").write_text(table)
    text = with_keys(TEST_STUDY, models={"parameters_from": "fits.csv"})
    found = refused([study_file(tmp_path, text)])
    assert "config key 'models.parameters_from' (fits.csv)" in found and message in found, found


@pytest.mark.fault("refused")
@pytest.mark.parametrize(
    ("sections", "message"),
    [
        ({"seeds": [1.0, 2.0]}, "config key 'seeds': whole numbers without a decimal point expected, got [1.0, 2.0]"),
        ({"analysis": {"eps": 0}}, "analysis.eps"),
        ({"particles": {"n": 40, "phi": 0.63}}, "config key 'particles.phi' (0.63): above 0.62"),
    ],
)
def test_decimal_seeds_a_zero_near_contact_gap_and_an_unpackable_phi_are_refused(tmp_path, sections, message):
    """seeds: [1.0, 2.0] named a run folder seed1.0 (a MissingInputException after validation);
    analysis.eps: 0 simulated everything and failed in the claims fit; particles.phi: 0.63 failed in
    the packing with an overlap message naming no key."""
    found = refused([study_file(tmp_path, with_keys(TEST_STUDY, **sections))])
    assert message in found, found


@pytest.mark.fault("refused")
@pytest.mark.parametrize(
    ("turning", "run", "message"),
    [
        (600.0, {"dump_strain": 0.02}, "turns 12 degrees per fabric frame (run.dump_strain = 0.02), more than the 10"),
        (2e4, {}, "turns 2 degrees per time step (run.dt = 0.0001), more than the 0.1"),
    ],
)
def test_a_rotary_segment_the_step_or_the_frames_cannot_follow_is_refused(tmp_path, turning, run, message):
    """The flow direction of a rotary segment must turn by at most 0.1 degree per step and 10 per
    fabric frame; beyond that the run was accepted and its fabric could not follow the flow."""
    rotary = [{"strain": 0.3}, {"strain": 0.1, "turning_deg_per_strain": turning}]
    text = with_keys(TEST_STUDY, protocols={"rotary": rotary}, run=run)
    found = refused([study_file(tmp_path, text)])
    assert "config key 'protocols.rotary.1.turning_deg_per_strain'" in found and message in found, found


@pytest.mark.fault("adapted")
def test_more_folds_than_angles_adapt(tmp_path):
    """models.held_out_folds above the number of angles is capped (model_benchmark.angle_folds)."""
    from suspension_fabric.evaluation.model_benchmark import angle_folds

    config, sources = workflow_config([study_file(tmp_path, with_keys(TEST_STUDY, models={"held_out_folds": 9}))])
    check_complete_study(config, sources)
    assert len(angle_folds(config["angles_deg"], config["models"]["held_out_folds"])) == 2


@pytest.mark.fault("refused")
def test_a_steady_window_without_two_frames_is_refused(tmp_path):
    """Frames every 0.01 at strains (100 k) x 1e-4, as the fabric tables compute them, and 0.29 is
    0.29000000000000004 there: [0.285, 0.29] holds none, [0.275, 0.285] one (aggregate_startup
    failed after the startups)."""
    run = yaml.safe_load(TEST_STUDY)["run"]
    assert frames_between(run, 0.3, 0.285, 0.29) == 0 and frames_between(run, 0.3, 0.275, 0.285) == 1
    assert frames_between(run, 0.3, 0.1, 0.3) == 21
    for window, frames in (([0.285, 0.29], 0), ([0.275, 0.285], 1)):
        text = with_keys(TEST_STUDY, analysis={"steady_window": window})
        message = refused([study_file(tmp_path, text)])
        assert message.startswith(f"study.yaml: config key 'analysis.steady_window' ([{window[0]:g}, {window[1]:g}])")
        assert f"holds {frames} fabric frame(s)" in message
    workflow_config([study_file(tmp_path, with_keys(TEST_STUDY, analysis={"steady_window": [0.28, 0.3]}))])


@pytest.mark.fault("refused")
def test_a_verdict_window_without_a_frame_is_refused(tmp_path):
    """The claims and benchmarks average over the frames of (0, window]: none gave NaN late."""
    message = refused([study_file(tmp_path, with_keys(TEST_STUDY, verdicts={"window": 0.005}))])
    assert message.startswith("study.yaml: config key 'verdicts.window' (0.005) holds no fabric frame after a rotation")


@pytest.mark.parametrize(
    "sections, key, limit",
    [
        ({"particles": {"n": 12}}, "particles.n", "use n >= 15"),
        ({"analysis": {"eps": 0.6}}, "analysis.eps", "use eps < 0.4"),
    ],
)
@pytest.mark.fault("refused")
def test_a_box_too_small_for_the_near_contact_search_is_refused(tmp_path, sections, key, limit):
    """The fabric table of every run refused a box under twice the near-contact distance, after the
    simulation: 40 particles at phi 0.45 fill a box 4.43 wide, 3.96 across when sheared."""
    message = refused([study_file(tmp_path, with_keys(TEST_STUDY, **sections))])
    assert message.startswith(f"study.yaml: config key '{key}'") and limit in message


@pytest.mark.fault("refused")
def test_all_large_spheres_by_volume_are_refused(tmp_path):
    """pack.lmp divides by 1 - fraction_large for split = volume (a LAMMPS error in the pack job)."""
    text = with_keys(TEST_STUDY, particles={"split": "volume", "fraction_large": 1.0})
    assert refused([study_file(tmp_path, text)]).startswith("study.yaml: config key 'particles.fraction_large' (1)")


@pytest.mark.fault("refused")
def test_a_seed_lammps_cannot_read_is_refused(tmp_path):
    """LAMMPS reads the seeds seed and seed + 7919 of pack.lmp as 32-bit integers."""
    message = refused([study_file(tmp_path, with_keys(TEST_STUDY, seeds=[1, 2**31 - 1]))])
    assert message.startswith("study.yaml: config key 'seeds.1': 2147483647 is greater than the maximum of 2147475728")


@pytest.mark.fault("refused")
def test_a_run_longer_than_lammps_runs_in_one_go_is_refused(tmp_path):
    """`run N upto` takes at most 2^31 - 1 steps: startup 5 at dt 1e-9 is 5e9 (grids divide it)."""
    study = {"dt": 1.0e-9, "startup_strain": 5.0, "rotation_strain": 2.0, "dump_strain": 0.02, "table_strain": 0.02}
    text = with_keys(TEST_STUDY, run=study, analysis={"steady_window": [2.0, 5.0]}, verdicts={"window": 2.0})
    message = refused([study_file(tmp_path, text)])
    assert message.startswith("study.yaml: config key 'run.dt': run.startup_strain (5) takes 5e+09 steps")


@pytest.mark.fault("refused")
def test_protocols_the_analysis_cannot_score_are_refused(tmp_path):
    """One segment: the protocol benchmark scored no frame (it scores the segments after the first);
    a first segment ending before the steady window: no steady state to compare with."""
    one = with_keys(TEST_STUDY, protocols={"rotary": [{"strain": 0.3, "turning_deg_per_strain": 90}]})
    assert refused([study_file(tmp_path, one)]).startswith("study.yaml: config key 'protocols.rotary': one segment")
    short = with_keys(TEST_STUDY, protocols={"early": [{"strain": 0.05}, {"strain": 0.1, "flow_angle_deg": 90}]})
    message = refused([study_file(tmp_path, short)])
    assert message.startswith(
        "study.yaml: config key 'protocols.early.0.strain' (0.05): the first segment holds no frame"
    )


@pytest.mark.fault("adapted")
def test_a_protocol_of_many_segments_gets_run_names_that_fit_a_file_name(tmp_path):
    """A run is named by its flow history; 40 segments would make a folder name above 255
    characters (refused before), so a long name is shortened to a digest of the history
    (io.protocols.RUN_NAME_MAX) and the protocol runs."""
    segments = [{"strain": 0.3}] + [{"strain": 0.01, "flow_angle_deg": 90 * (k % 2)} for k in range(1, 40)]
    config, _ = workflow_config([study_file(tmp_path, with_keys(TEST_STUDY, protocols={"zigzag": segments}))])
    names = study_run_tree(config)
    assert len(names) > 40 and max(len(name) for name in names) <= 200


@pytest.mark.fault("refused")
def test_a_comparison_dataset_the_study_cannot_use_is_refused(tmp_path):
    """A dataset shorter after its rotations than verdicts.window failed rule verdicts; one whose
    startups hold < 2 frames of the study's steady window failed rule compare_datasets."""
    config, _ = workflow_config([study_file(tmp_path)])
    dataset = load_config(REPO / "config" / "test.yaml")
    short = {**dataset, "run": {**dataset["run"], "rotation_strain": 0.05}}
    with pytest.raises(ConfigError, match=r"^config key 'verdicts.comparisons': 'short' runs 0.05 strain"):
        check_comparison(config, "short", short)
    early = {**dataset, "run": {**dataset["run"], "startup_strain": 0.1}}
    with pytest.raises(ConfigError, match=r"'early': its startups \(to strain 0.1, .* fewer than 2 frames"):
        check_comparison(config, "early", early)
    check_comparison(config, "early", early, stress=False)  # no compare_datasets without stress tables


@pytest.mark.fault("refused")
def test_a_campaign_volume_fraction_is_bounded_like_the_study_one(tmp_path):
    """campaign.phi allowed up to 0.74 and each point then failed as 'campaign.overrides.<point> or
    the base study'; now the schema names campaign.phi, with particles.phi's bound."""
    text = with_keys(TEST_STUDY, campaign={"phi": [0.45, 0.66], "mu": [0.5]})
    assert refused([study_file(tmp_path, text)]).startswith("study.yaml: config key 'campaign.phi.1': 0.66")


@pytest.mark.parametrize(
    "sections, key",
    [
        ({"analysis": {"steady_window": [0.1, 0.5]}}, "analysis.steady_window"),
        ({"verdicts": {"window": 0.2}}, "verdicts.window"),
        ({"verdicts": {"models": {"challenger": "nope"}}}, "verdicts.models.challenger"),
        ({"run": {"dump_strain": 0.5}}, "run.dump_strain"),
    ],
)
@pytest.mark.fault("refused")
def test_cases_refused_before_still_name_file_and_key(tmp_path, sections, key):
    """Refused early already (steady window beyond the startup, verdict window beyond the rotations,
    an unknown compared model, a frame stride beyond a run); now with the file."""
    assert refused([study_file(tmp_path, with_keys(TEST_STUDY, **sections))]).startswith(
        f"study.yaml: config key '{key}'"
    )


#: Shipped configs that are read only on top of another (a rebuild from committed datasets).
LAYERED_ON = {
    "map.yaml": "campaign.yaml",
    "thickening_reference.yaml": "thickening.yaml",
    "thickening_rotation_reference.yaml": "thickening_rotation.yaml",
    "thickening_stress_reference.yaml": "thickening_stress.yaml",
    "thickening_stress_fresh_reference.yaml": "thickening_stress_fresh.yaml",
}


def test_the_shipped_studies_pass_every_new_check(monkeypatch):
    monkeypatch.chdir(REPO)  # their model files and datasets are named relative to the repository
    for path in sorted((REPO / "config").glob("*.yaml")):
        if path.name != "schema.yaml" and path.name not in LAYERED_ON:
            config = load_config(path)
            if not is_flow_curve_campaign(config):  # its points' target is the steady state alone
                for study in study_configs(config).values():
                    check_complete_study(study)
    for layer, base in LAYERED_ON.items():
        assert main([f"config/{base}", f"config/{layer}"]) == 0


@pytest.mark.fault("refused")
def test_only_symmetric_angles_are_refused_for_the_full_study_only(tmp_path):
    """Angles 0 and 180 alone simulated and then failed in the verdicts (KeyError: 'angles'): the claims
    decide on rotations strictly between 0 and 180 degrees. The full study is refused naming the key;
    the angles still validate, for single targets."""
    files = [study_file(tmp_path, with_keys(TEST_STUDY, angles_deg=[0, 180]))]
    assert workflow_config(files)[0]["angles_deg"] == [0, 180]
    message = refused(files, complete=True)
    assert message.startswith("study.yaml: config key 'angles_deg' ([0, 180]) of study test"), message
    assert "strictly between 0 and 180" in message


@pytest.mark.parametrize(("angles", "folded"), [([0, -180, 90, 180], [0, 180, 90]), ([-180, 45], [180, 45])])
def test_minus_180_is_the_rotation_by_180_simulated_once(tmp_path, angles, folded):
    """-180 and 180 turn the flow to the same direction: read as one rotation, run once (they failed in
    a figure with KeyError: 'theta' after simulating both)."""
    config, _ = workflow_config([study_file(tmp_path, with_keys(TEST_STUDY, angles_deg=angles))])
    assert config["angles_deg"] == folded

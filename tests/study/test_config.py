"""Config validation: schema defaults, cross-key checks, shipped study files."""

import math

import pytest

from suspension_fabric.simulation.lammps import ForceModel, ShearSettings
from suspension_fabric.simulation.scales import max_dt_explicit, max_dt_implicit
from suspension_fabric.study.config import ConfigError, angle_label, load_config, simulation_settings, validate_config

MINIMAL = {"study": "s", "seeds": [1], "angles_deg": [0, 90]}


def test_defaults_are_filled_at_every_level():
    config = validate_config(dict(MINIMAL))
    assert config["particles"]["phi"] == 0.45 and config["forces"]["kn"] == 1.25e8
    assert config["run"]["contact_springs"] == "implicit" and config["run"]["dt"] == 1.0e-4
    assert config["analysis"]["eps"] == 0.01 and config["run"]["startup_strain"] == 5.0


@pytest.mark.parametrize("name", ["config", "paper", "test"])
def test_shipped_configs_are_valid(name):
    config = load_config(f"config/{name}.yaml")
    assert config["study"] == {"config": "default"}.get(name, name)


@pytest.mark.parametrize(
    "change, key",
    [
        ({"seeds": []}, "seeds"),
        ({"particles": {"phi": -0.1}}, "particles.phi"),
        ({"forces": {"eta_f": "x"}}, "forces.eta_f"),
        ({"run": {"dump_strain": 10.0}}, "run.dump_strain"),
        ({"particles": {"d_large": 0.5}}, "particles.d_large"),
        ({"angles_deg": [-0.0, 0.0]}, "angles_deg"),
        ({"study": "a/b"}, "study"),
        ({"forces": {"kn": 1.25e5}}, "forces.kn"),
        ({"run": {"dt": 2.0e-4}}, "run.dt"),
        ({"run": {"contact_springs": "explicit", "dt": 4.0e-4}}, "run.dt"),
        ({"run": {"integrator": "explicit", "dt": 1.0e-6}}, "run.dt"),
        ({"run": {"integrator": "verlet"}}, "run.integrator"),
        ({"run": {"mpi_ranks": 0}}, "run.mpi_ranks"),
        ({"run": {"initial_guess": "cubic"}}, "run.initial_guess"),
    ],
)
def test_bad_values_name_their_key(change, key):
    with pytest.raises(ConfigError, match=f"'{key}"):
        validate_config({**MINIMAL, **change})


def test_missing_file_is_named(tmp_path):
    with pytest.raises(ConfigError, match="not found"):
        load_config(tmp_path / "nope.yaml")


def test_angle_labels():
    assert [angle_label(a) for a in (0, 45.0, 22.5, -30)] == ["0", "45", "22.5", "m30"]


def test_paper_kn_is_rejected_as_too_soft_with_the_relaxation_strain():
    """The paper's printed kn = 1.25e5 at eta_f = 223, delta = 1e-3: a large-large contact
    unloads in tau = (X + c/2)/kn = 5.9 strain (suspension_fabric.simulation.scales), far from stiff."""
    with pytest.raises(ConfigError, match=r"forces.kn' \(125000\).*5\.9\d* strain"):
        validate_config({**MINIMAL, "forces": {"kn": 1.25e5}})
    loosened = {**MINIMAL, "forces": {"kn": 1.25e5}, "run": {"max_contact_relaxation_strain": 10.0}}
    assert validate_config(loosened)["forces"]["kn"] == 1.25e5


def test_a_default_config_runs_what_the_python_defaults_run():
    """A minimal config filled with the schema's defaults gives the same force model and
    shear settings as the Python defaults (both read config/schema.yaml; the .lmp scripts
    are checked against it in test_defaults), so a workflow run and a run from Python agree."""
    config = validate_config(dict(MINIMAL))
    assert ForceModel.from_config(config) == ForceModel()
    assert ShearSettings.from_config(config) == ShearSettings()


def test_the_first_iterate_enters_a_simulations_settings_only_when_extrapolated():
    """run.initial_guess came after finished simulations: at its default (the old velocities,
    what those ran) it stays out of simulation_settings, the Snakemake param that reruns a
    simulation when it changes; an extrapolated first iterate is a setting like any other."""
    default = simulation_settings(validate_config(dict(MINIMAL)))
    assert "initial_guess" not in default["run"] and "solver_tol" in default["run"]
    quadratic = simulation_settings(validate_config({**MINIMAL, "run": {"initial_guess": "quadratic"}}))
    assert quadratic["run"] == {**default["run"], "initial_guess": "quadratic"}


def test_time_step_limit_follows_the_integrator():
    """implicit with the springs explicit (kn = 1.25e9, the engine of the reference data): dt up
    to the tangential-spring limit (scales.max_dt_implicit, 3.65e-5) passes, above it fails
    naming the limit; explicit: the squeeze limit (scales.max_dt_explicit, 2.5e-7) applies instead."""
    implicit_limit = max_dt_implicit(1.0, 223.0, 1e-3, 2.0 / 7.0 * 1.25e9)
    explicit_limit = max_dt_explicit(1.0, 223.0, 1e-3)
    assert 3e-5 < implicit_limit < 4e-5 and 2e-7 < explicit_limit < 3e-7
    springs_explicit = {"forces": {"kn": 1.25e9}, "run": {"contact_springs": "explicit", "preconditioner": "jacobi"}}
    for dt in (2.0e-5, 3.125e-5):  # 3.125e-5: just below the limit, on the output grid
        config = {**MINIMAL, **springs_explicit, "run": {**springs_explicit["run"], "dt": dt}}
        assert validate_config(config)["run"]["dt"] == dt
    with pytest.raises(ConfigError, match=rf"run.dt' \(4e-05\).*tangential contact spring.*{implicit_limit:.3g}"):
        validate_config({**MINIMAL, **springs_explicit, "run": {**springs_explicit["run"], "dt": 4.0e-5}})
    explicit = {"integrator": "explicit", "contact_springs": "explicit"}
    assert validate_config({**MINIMAL, "run": {**explicit, "dt": 2.0e-7}})
    with pytest.raises(ConfigError, match=rf"run.dt' \(5e-07\).*lubrication squeeze.*{explicit_limit:.3g}"):
        validate_config({**MINIMAL, "run": {**explicit, "dt": 5.0e-7}})


def test_implicit_springs_step_resolves_the_contact_relaxation_time():
    """With the contact springs implicit (the default) dt <= run.max_dt_per_relaxation x tau,
    tau = (X(delta) + c/2)/kn of two small spheres (scales.contact_relaxation_time): at the
    defaults X = 6 pi eta_f (1/4)^2 / (delta/2) = 5.254e5, c/2 = 3 pi eta_f / 2 = 1051, so
    tau = 4.211e-3 at kn = 1.25e8 and the bound is 0.025 tau = 1.053e-4: 1e-4 passes, 1.25e-4
    fails naming the key, and raising the key (a step-error study) lets it through; implicit
    springs with the explicit integrator are refused, naming the key."""
    tau = (6 * math.pi * 223 * 0.25**2 / 0.5e-3 + 1.5 * math.pi * 223) / 1.25e8
    assert tau == pytest.approx(4.211e-3, rel=1e-3)
    assert validate_config(dict(MINIMAL))["run"]["dt"] == 1.0e-4 < 0.025 * tau
    with pytest.raises(ConfigError, match=rf"run.dt' \(0.000125\).*tau = {tau:.3g}.*max_dt_per_relaxation"):
        validate_config({**MINIMAL, "run": {"dt": 1.25e-4}})
    loosened = {**MINIMAL, "run": {"dt": 2.0e-4, "max_dt_per_relaxation": 0.05}}
    assert validate_config(loosened)["run"]["dt"] == 2.0e-4
    with pytest.raises(ConfigError, match=r"run.contact_springs' \(implicit\) needs run.integrator = implicit"):
        validate_config({**MINIMAL, "run": {"integrator": "explicit", "dt": 2.0e-7}})


def test_local_solves_on_several_ranks_are_refused_naming_the_key():
    """Local solves pay on one rank only: on two each rank solves its patches without the other's
    couplings and the global iterations grow (measured: docs/physics.md, "How the
    engine's defaults were chosen"), so the pair is refused."""
    assert validate_config({**MINIMAL, "run": {"local_solve_fraction": 0.02}})["run"]["mpi_ranks"] == 1
    assert validate_config({**MINIMAL, "run": {"mpi_ranks": 2}})["run"]["local_solve_fraction"] == 0
    with pytest.raises(ConfigError, match=r"run.local_solve_fraction' \(0.02\) needs run.mpi_ranks = 1"):
        validate_config({**MINIMAL, "run": {"local_solve_fraction": 0.02, "mpi_ranks": 2}})


@pytest.mark.parametrize(
    "run, message",
    [
        ({"dt": 3.0e-5}, r"run.dt' \(3e-05\): run.startup_strain \(5\) is not a whole number of steps"),
        ({"dt": 2.0e-5, "table_strain": 0.0014}, r"run.table_strain' \(0.0014\) gives a stride of 70 steps"),
    ],
)
def test_rotations_start_on_the_output_grid(run, message):
    """LAMMPS writes a row or frame when the step is a multiple of the stride: a startup that
    does not end on every grid would start the rotations off it, so such a config is refused
    early, naming the key (startup 5 strain: 166666.7 steps at dt = 3e-5; a stride of 70 steps
    does not divide 250000)."""
    with pytest.raises(ConfigError, match=message):
        validate_config({**MINIMAL, "run": run})


def test_config_readme_names_every_key_and_shipped_file():
    """config/README.md lists every section and second-level key of the schema and every
    shipped study file, so the catalog's configuration page stays in step with the schema."""
    from pathlib import Path

    import yaml

    folder = Path(__file__).resolve().parents[2] / "config"
    readme = (folder / "README.md").read_text()
    schema = yaml.safe_load((folder / "schema.yaml").read_text())
    for section, spec in schema["properties"].items():
        assert f"`{section}`" in readme, section
        if section != "campaign":
            for key in spec.get("properties", {}):
                assert f"`{key}`" in readme, f"{section}.{key}"
    for path in folder.glob("*.yaml"):
        if path.name != "schema.yaml":
            assert f"`{path.name}`" in readme, path.name

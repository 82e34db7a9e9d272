"""Study configuration: schema validation with defaults, cross-key checks, run names.

The schema is ``config/schema.yaml`` (JSON schema with defaults and descriptions);
:func:`load_config` validates a YAML file against it (filling defaults) and then
checks what a schema cannot express. Errors name the offending key.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import yaml

from suspension_fabric.io.protocols import (
    PAPER_STARTUP,
    PaperRunNames,
    Protocol,
    ProtocolError,
    RunNode,
    paper_protocols,
    parse_protocols,
    run_tree,
)
from suspension_fabric.io.resources import SCHEMA_PATH
from suspension_fabric.models.fabric_models import ModelError, resolve_models
from suspension_fabric.models.stress_relations import RelationError, resolve_relations
from suspension_fabric.simulation.scales import (
    contact_period,
    contact_relaxation_time,
    max_dt_explicit,
    max_dt_implicit,
    output_stride,
)

__all__ = [
    "SCHEMA_PATH",
    "ConfigError",
    "validate_config",
    "load_config",
    "angle_label",
    "simulation_settings",
    "SIMULATION_RUN_KEYS",
    "study_protocols",
    "study_run_tree",
]

# velocity Verlet (run.integrator = explicit) must resolve the contact oscillation
MIN_STEPS_PER_CONTACT_PERIOD = 30


#: The ``run`` keys that change a simulation's outputs besides its strain (and all of
#: ``forces``); the others (thermo and restart intervals, failure bounds, MPI ranks) do not.
SIMULATION_RUN_KEYS = (
    "integrator",
    "contact_springs",
    "preconditioner",
    "solver_tol",
    "dt",
    "dump_strain",
    "table_strain",
)


def simulation_settings(config: dict) -> dict:
    """The settings of a validated config on which every startup and rotation result depends."""
    return {"forces": dict(config["forces"]), "run": {key: config["run"][key] for key in SIMULATION_RUN_KEYS}}


class ConfigError(ValueError):
    """The configuration is invalid; the message names the key."""


def study_protocols(config: dict) -> dict[str, Protocol]:
    """Every protocol of a validated study: the paper's family (startup, then run.rotation_strain at
    each of angles_deg; :func:`suspension_fabric.io.protocols.paper_protocols`) and the config's
    ``protocols``."""
    run = config["run"]
    protocols = paper_protocols(config["angles_deg"], run["startup_strain"], run["rotation_strain"])
    try:
        own = parse_protocols(config.get("protocols") or {})
    except ProtocolError as err:
        raise ConfigError(str(err)) from None
    clash = sorted(name for name in own if name == PAPER_STARTUP or name.startswith("rotation_theta"))
    if clash:
        raise ConfigError(
            f"config key 'protocols.{clash[0]}': the name belongs to the paper's family (startup, "
            "rotation_theta<angle>); choose another"
        )
    return {**protocols, **own}


def study_run_tree(config: dict) -> dict[str, RunNode]:
    """The runs of a validated study, parents first, keyed by run name (the paper's runs keep
    their names ``startup`` and ``rotation_theta<angle>``; :func:`suspension_fabric.io.protocols.run_tree`)."""
    run = config["run"]
    try:
        return run_tree(study_protocols(config).values(), PaperRunNames(run["startup_strain"], run["rotation_strain"]))
    except ProtocolError as err:
        raise ConfigError(f"config key 'protocols': {err}") from None


def _fill_and_validate(config: dict, schema: dict) -> None:
    import jsonschema

    validator_class = jsonschema.validators.validator_for(schema)

    def set_defaults(validator, properties, instance, schema_):
        if isinstance(instance, dict):
            for name, sub in properties.items():
                if "default" in sub and name not in instance:
                    instance[name] = (
                        sub["default"]
                        if not isinstance(sub["default"], (dict, list))
                        else type(sub["default"])(sub["default"])
                    )
        yield from validator_class.VALIDATORS["properties"](validator, properties, instance, schema_)

    filling = jsonschema.validators.extend(validator_class, {"properties": set_defaults})
    errors = sorted(filling(schema).iter_errors(config), key=lambda e: list(e.absolute_path))
    if errors:
        first = errors[0]
        key = ".".join(str(p) for p in first.absolute_path) or "<top level>"
        raise ConfigError(f"config key '{key}': {first.message}")


def _coerce_command_line_text(value, schema: dict):
    """Snakemake's ``--config key='{a: 1}'`` gives nested values as text: read them as YAML
    where the schema expects something other than text, so overrides validate like files."""
    types = schema.get("type", [])
    types = [types] if isinstance(types, str) else types
    if isinstance(value, str) and "string" not in types and "enum" not in schema:
        try:
            return yaml.safe_load(value)
        except yaml.YAMLError:
            return value
    if isinstance(value, dict):
        properties = schema.get("properties", {})
        others = schema.get("additionalProperties")
        others = others if isinstance(others, dict) else {}
        return {key: _coerce_command_line_text(item, properties.get(key, others)) for key, item in value.items()}
    if isinstance(value, list) and isinstance(schema.get("items"), dict):
        return [_coerce_command_line_text(item, schema["items"]) for item in value]
    return value


#: Larger numbers overflow the derived scales (a float holds up to ~1.8e308).
LARGEST_NUMBER = 1e300


def _check_numbers(value, path: str = "") -> None:
    """Every number of the config is finite and of a size floats can hold: NaN passes the
    schema's range checks (comparisons with NaN are false) and inf or 10**400 overflow the derived
    scales, so they are stopped here, naming the key."""
    if isinstance(value, dict):
        for key, item in value.items():
            _check_numbers(item, f"{path}.{key}" if path else str(key))
    elif isinstance(value, list):
        for index, item in enumerate(value):
            _check_numbers(item, f"{path}.{index}")
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        # an int is compared as such: float(10**400) itself overflows
        if not (
            abs(value) <= LARGEST_NUMBER
            if isinstance(value, int)
            else math.isfinite(value) and abs(value) <= LARGEST_NUMBER
        ):
            shown = str(value) if len(str(value)) <= 24 else f"{str(value)[:20]}... ({len(str(value))} digits)"
            raise ConfigError(
                f"config key '{path or '<top level>'}': {shown} is not a finite number below {LARGEST_NUMBER:g} in size"
            )


def validate_config(config: dict, schema_path: str | os.PathLike = SCHEMA_PATH) -> dict:
    """Validate ``config`` in place against the schema (filling defaults), then cross-check keys."""
    schema = yaml.safe_load(Path(schema_path).read_text())
    config.update(_coerce_command_line_text(dict(config), schema))
    _check_numbers(config)
    _fill_and_validate(config, schema)
    try:
        _cross_check(config)
    except (ArithmeticError, ValueError) as err:  # derived scales of extreme but valid numbers
        if isinstance(err, ConfigError):
            raise
        raise ConfigError(
            f"config key 'run.dt': the sizes, forces and time step give no usable time scales "
            f"({type(err).__name__}: {err})"
        ) from None
    return config


def _cross_check(config: dict) -> None:
    """The checks across keys that the schema cannot state."""
    run, analysis, particles = config["run"], config["analysis"], config["particles"]
    lo, hi = analysis["steady_window"]
    if not 0 <= lo < hi <= run["startup_strain"]:
        raise ConfigError(
            f"config key 'analysis.steady_window': need 0 <= min < max <= run.startup_strain "
            f"({run['startup_strain']}), got {analysis['steady_window']}"
        )
    for key in ("dump_strain", "thermo_strain", "table_strain"):
        if run[key] > min(run["startup_strain"], run["rotation_strain"]):
            raise ConfigError(f"config key 'run.{key}' ({run[key]}) exceeds the shortest run's strain")
        if run[key] < run["dt"]:
            raise ConfigError(f"config key 'run.{key}' ({run[key]}) is below one time step run.dt ({run['dt']})")
    if particles["d_large"] < particles["d_small"]:
        raise ConfigError("config key 'particles.d_large' must be >= particles.d_small")
    forces = config["forces"]
    relaxation = contact_relaxation_time(
        particles["d_large"], particles["d_large"], forces["eta_f"], forces["delta"], forces["kn"]
    )
    if relaxation > run["max_contact_relaxation_strain"]:
        raise ConfigError(
            f"config key 'forces.kn' ({forces['kn']:g}) is too soft for the stiff, rate-independent "
            f"limit: with forces.eta_f = {forces['eta_f']:g} and forces.delta = {forces['delta']:g} a "
            f"contact needs {relaxation:.3g} strain to unload, above "
            f"run.max_contact_relaxation_strain = {run['max_contact_relaxation_strain']:g} "
            f"(suspension_fabric.simulation.scales); raise kn to at least "
            f"{forces['kn'] * relaxation / run['max_contact_relaxation_strain']:.3g}"
        )
    _check_time_step(run, forces, particles["d_small"])
    _check_output_grid(run)
    if run["integrator"] == "explicit" and run["contact_springs"] == "implicit":
        raise ConfigError(
            "config key 'run.contact_springs' (implicit) needs run.integrator = implicit: the "
            "springs are solved with the implicit hydrodynamics"
        )
    if run["integrator"] == "implicit" and run["mpi_ranks"] > 1:
        raise ConfigError(
            f"config key 'run.mpi_ranks' ({run['mpi_ranks']}): the implicit integrator runs on one MPI "
            "rank; parallelism comes from running seeds and angles as separate jobs (use "
            "run.integrator = explicit for MPI runs)"
        )
    window = config["verdicts"]["window"]
    if window > run["rotation_strain"]:
        raise ConfigError(
            f"config key 'verdicts.window' ({window}) exceeds run.rotation_strain "
            f"({run['rotation_strain']}): the claims integrate over the strain after a rotation"
        )
    try:
        models = resolve_models(config["models"]["fabric"])
    except ModelError as error:
        raise ConfigError(f"config key 'models.fabric': {error}") from None
    compared = config["verdicts"]["models"]
    for role, key in compared.items():
        if key not in models:
            raise ConfigError(
                f"config key 'verdicts.models.{role}': {key!r} is not one of the models of models.fabric "
                f"({', '.join(models)})"
            )
    if compared["reference"] == compared["challenger"]:
        raise ConfigError("config key 'verdicts.models.challenger': the claims compare two different models")
    try:
        resolve_relations(config["models"]["stress"])
    except RelationError as error:
        raise ConfigError(f"config key 'models.stress': {error}") from None
    labels = [angle_label(a) for a in config["angles_deg"]]
    if len(set(labels)) != len(labels):
        raise ConfigError(f"config key 'angles_deg': angles collide after formatting: {labels}")
    _check_protocols(config)


def _check_protocols(config: dict) -> None:
    """Every segment of the config's protocols a whole number of output strides long, so that the
    next segment starts on the output grid (as :func:`_check_output_grid` for the paper's runs)."""
    run = config["run"]
    protocols = study_protocols(config)
    for name in config.get("protocols") or {}:
        for index, segment in enumerate(protocols[name].segments):
            key = f"protocols.{name}.{index}.strain"
            fault = _off_grid(segment.strain, run)
            if fault == ("dt", 1):
                raise ConfigError(
                    f"config key '{key}' ({segment.strain:g}) is not a whole number of steps of run.dt ({run['dt']:g})"
                )
            if fault is not None:
                grid, stride = fault
                raise ConfigError(
                    f"config key '{key}' ({segment.strain:g}) is not a whole number of run.{grid} "
                    f"strides ({stride} steps at dt = {run['dt']:g}): the next segment would start "
                    "off the output grid"
                )
    study_run_tree(config)


def _off_grid(strain: float, run: dict) -> tuple[str, int] | None:
    """Why a run of ``strain`` would not end on every output grid: ("dt", 1) for a strain that is
    not a whole number of steps, (grid key, stride) for one that is not a whole number of that
    grid's strides; None if it ends on all of them."""
    steps = strain / run["dt"]
    if abs(steps - round(steps)) > 1e-6 * steps:
        return ("dt", 1)
    for grid in ("dump_strain", "table_strain"):
        stride = output_stride(run[grid], run["dt"])
        if round(steps) % stride:
            return (grid, stride)
    return None


def _check_time_step(run: dict, forces: dict, d_small: float) -> None:
    """dt within the stability limit of the chosen integrator (suspension_fabric.simulation.scales)."""
    dt, integrator = run["dt"], run["integrator"]
    kt = forces["kt"] if forces["kt"] is not None else 2.0 / 7.0 * forces["kn"]
    if integrator == "implicit" and run["contact_springs"] == "implicit":
        tau = contact_relaxation_time(d_small, d_small, forces["eta_f"], forces["delta"], forces["kn"])
        limit = run["max_dt_per_relaxation"] * tau
        reason = (
            f"with the contact springs implicit the step must resolve the contact relaxation time "
            f"tau = {tau:.3g} (two small spheres at forces.kn = {forces['kn']:g}, "
            f"suspension_fabric.simulation.scales.contact_relaxation_time): dt <= run.max_dt_per_relaxation "
            f"({run['max_dt_per_relaxation']:g}) x tau"
        )
    elif integrator == "implicit":
        limit = max_dt_implicit(d_small, forces["eta_f"], forces["delta"], kt)
        reason = (
            f"the explicit tangential contact spring (kt = {kt:g}, damped by the shear "
            f"lubrication at the regularised gap) is stable only for dt < {limit:.3g} "
            "with run.integrator = implicit (suspension_fabric.simulation.scales.max_dt_implicit)"
        )
    else:
        limit = max_dt_explicit(d_small, forces["eta_f"], forces["delta"])
        period = contact_period(d_small, d_small, forces["kn"])
        if period / MIN_STEPS_PER_CONTACT_PERIOD < limit:
            limit = period / MIN_STEPS_PER_CONTACT_PERIOD
            reason = (
                f"velocity Verlet needs {MIN_STEPS_PER_CONTACT_PERIOD} steps per contact "
                f"period ({period:.3g} at forces.kn = {forces['kn']:g})"
            )
        else:
            reason = (
                f"run.integrator = explicit integrates the lubrication squeeze explicitly, "
                f"stable only for dt <= {limit:.3g} at forces.eta_f = {forces['eta_f']:g}, "
                f"forces.delta = {forces['delta']:g} (suspension_fabric.simulation.scales.max_dt_explicit)"
            )
    if dt > limit:
        raise ConfigError(f"config key 'run.dt' ({dt:g}) is too large: {reason}; use dt <= {limit:.3g}")


def _check_output_grid(run: dict) -> None:
    """The startup must end on a step of every output grid: LAMMPS writes a table row or a frame
    when the step is a multiple of the stride, so a rotation that starts between two grid
    steps would miss its first row (and the strain grid would be shifted)."""
    startup_steps = run["startup_strain"] / run["dt"]
    fault = _off_grid(run["startup_strain"], run)
    if fault == ("dt", 1):
        raise ConfigError(
            f"config key 'run.dt' ({run['dt']:g}): run.startup_strain "
            f"({run['startup_strain']:g}) is not a whole number of steps "
            f"({startup_steps:.6g}); choose dt that divides it"
        )
    if fault is not None:
        key, stride = fault
        raise ConfigError(
            f"config key 'run.{key}' ({run[key]:g}) gives a stride of {stride} steps at "
            f"dt = {run['dt']:g}, which does not divide the {round(startup_steps)} steps "
            f"of the startup; the rotations would start off the output grid"
        )


def load_config(path: str | os.PathLike) -> dict:
    """Read and validate a study YAML file; errors name the file and the key."""
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"config file not found: {path}")
    config = yaml.safe_load(path.read_text()) or {}
    try:
        return validate_config(config)
    except ConfigError as err:
        raise ConfigError(f"{path}: {err}") from None


def angle_label(theta_deg: float) -> str:
    """Text of an angle for file names: 45 -> '45', 22.5 -> '22.5', -30 -> 'm30'."""
    text = f"{float(theta_deg):g}"
    return text.replace("-", "m")

"""Study configuration: schema validation with defaults, cross-key checks, run names.

The schema is ``config/schema.yaml`` (JSON schema with defaults and descriptions);
[`load_config`][suspension_fabric.study.config.load_config] validates a YAML file against it (filling defaults) and then
checks what a schema cannot express. Errors name the offending key, and the file that set it.

Files are read strictly ([`read_config_file`][suspension_fabric.study.config.read_config_file]): a YAML syntax error
names the file, line and column, a key given twice in one mapping is refused (PyYAML, and so Snakemake, keeps the last
one without a word). The Snakefile reads its ``--configfile`` files and ``--config`` entries again this
way ([`read_config_sources`][suspension_fabric.study.config.read_config_sources]) before it validates the config
Snakemake parsed.
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
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
from suspension_fabric.io.schema import read_schema
from suspension_fabric.models.fabric_models import ModelError, resolve_models
from suspension_fabric.models.stress_relations import RelationError, resolve_relations
from suspension_fabric.simulation.engine_rule import ENGINE_KEYS, choose_engine
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
    "ConfigSources",
    "read_config_file",
    "read_config_sources",
    "validate_config",
    "check_complete_study",
    "check_comparison",
    "frames_between",
    "load_config",
    "load_layered_config",
    "angle_label",
    "simulation_settings",
    "SIMULATION_RUN_KEYS",
    "study_protocols",
    "study_run_tree",
    "shipped_paths",
]

# velocity Verlet (run.integrator = explicit) must resolve the contact oscillation
MIN_STEPS_PER_CONTACT_PERIOD = 30

#: LAMMPS runs at most this many steps in one ``run ... upto`` (a 32-bit count), i.e. per segment.
LAMMPS_MAX_STEPS = 2**31 - 1

#: The sheared box is narrowest with both tilts at half its length (fix deform flips them there):
#: width L / sqrt(1.25) across the two tilted faces.
SHEARED_WIDTH = 1.0 / math.sqrt(1.25)

#: Longest file or folder name (ext4 and most file systems).


#: The ``run`` keys that change a simulation's outputs besides its strain (and all of
#: ``forces``); the others (thermo and restart intervals, failure bounds, MPI ranks) do not.
SIMULATION_RUN_KEYS = (
    "integrator",
    "contact_springs",
    "contact_solve",
    "preconditioner",
    "solver_tol",
    "local_solve_fraction",
    "initial_guess",
    "dt",
    "dump_strain",
    "table_strain",
)


#: ``run`` keys added after simulations were made with the value given (the old velocities as
#: the solve's first iterate): at that value they stay out of a simulation's settings, so the
#: simulations finished before them do not rerun.
RUN_KEYS_ADDED_LATER = {"initial_guess": "previous"}


def simulation_settings(config: dict) -> dict:
    """The settings of a validated config on which every startup and rotation result depends."""
    run = {
        key: config["run"][key]
        for key in SIMULATION_RUN_KEYS
        if key not in RUN_KEYS_ADDED_LATER or config["run"][key] != RUN_KEYS_ADDED_LATER[key]
    }
    return {"forces": dict(config["forces"]), "run": run}


class ConfigError(ValueError):
    """The configuration is invalid; the message names the key."""


# ----------------------------------------------------------------------------- reading
class _YamlSyntaxError(ConfigError):
    """Text that is not YAML (a ``--config`` value may still be meant as text)."""


_MERGE_TAG = "tag:yaml.org,2002:merge"
_KEY_IN_MESSAGE = re.compile(r"config key '([^']+)'")


def _at(mark, one_line: bool) -> str:
    return f"column {mark.column + 1} of the value" if one_line else f"line {mark.line + 1}, column {mark.column + 1}"


def _refuse_repeated_keys(node, source: str, path: tuple, one_line: bool, visited: set) -> None:
    if id(node) in visited:  # an alias: checked where it was defined
        return
    visited.add(id(node))
    if isinstance(node, yaml.MappingNode):
        first = {}
        for key_node, value_node in node.value:
            scalar = isinstance(key_node, yaml.ScalarNode)
            name = key_node.value if scalar else "?"
            if scalar and key_node.tag != _MERGE_TAG:
                key = (key_node.tag, key_node.value)
                if key in first:
                    raise ConfigError(
                        f"{source}, {_at(key_node.start_mark, one_line)}: config key "
                        f"'{'.'.join((*path, name))}' is given twice (first at {_at(first[key], one_line)}); "
                        "YAML keeps only the last one, without a word: merge the two"
                    )
                first[key] = key_node.start_mark
            _refuse_repeated_keys(value_node, source, (*path, str(name)), one_line, visited)
    elif isinstance(node, yaml.SequenceNode):
        for index, item in enumerate(node.value):
            _refuse_repeated_keys(item, source, (*path, str(index)), one_line, visited)


def _strict_yaml(text: str, source: str, path: tuple = (), one_line: bool = False):
    """``text`` read as YAML (safe tags only); a syntax error or a key repeated in one mapping is a
    ConfigError naming ``source`` and the position."""
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        _refuse_repeated_keys(node, source, path, one_line, set())
        return loader.construct_document(node)
    except yaml.MarkedYAMLError as err:
        mark, opened = err.problem_mark or err.context_mark, err.context_mark
        what = err.problem or ""
        if err.context:
            what += f" ({err.context}{f' at {_at(opened, one_line)}' if opened else ''})"
        if mark is None:
            raise _YamlSyntaxError(f"{source}: not valid YAML: {what}") from None
        lines = text.splitlines()
        if mark.line >= len(lines) or not lines[mark.line].strip():  # at the end: show where it opened
            mark = opened or mark
        shown = lines[mark.line] if mark.line < len(lines) else ""
        raise _YamlSyntaxError(
            f"{source}, {_at(err.problem_mark or mark, one_line)}: not valid YAML: {what}\n"
            f"    {shown}\n    {' ' * mark.column}^"
        ) from None
    except yaml.YAMLError as err:  # e.g. a control character
        raise _YamlSyntaxError(f"{source}: not valid YAML ({err})") from None
    finally:
        loader.dispose()


def _shown(path: str | os.PathLike) -> str:
    """A path as the user would write it: relative to the working directory if inside it."""
    path = Path(path)
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except (ValueError, OSError):
        return str(path)


def _json_pairs(pairs):
    keys = [key for key, _ in pairs]
    repeated = sorted({key for key in keys if keys.count(key) > 1})
    if repeated:
        raise ConfigError(f"config key '{repeated[0]}' is given twice in one JSON object")
    return dict(pairs)


def read_config_file(path: str | os.PathLike) -> dict:
    """A config file's keys, read strictly: errors name the file, and the line and column of a YAML
    syntax error or of both places of a key given twice in one mapping. JSON that YAML cannot read
    (tabs) is read as JSON, as Snakemake does."""
    shown = _shown(path)
    if not Path(path).is_file():
        where = "" if Path(path).is_absolute() else f" (relative to the working directory {Path.cwd()})"
        raise ConfigError(f"config file not found: {shown}{where}")
    try:
        text = Path(path).read_text(encoding="utf-8")
    except UnicodeDecodeError as err:
        raise ConfigError(f"{shown}: not UTF-8 text ({err})") from None
    try:
        data = _strict_yaml(text, shown)
    except _YamlSyntaxError as syntax:
        try:
            data = json.loads(text, object_pairs_hook=_json_pairs)
        except ConfigError as err:
            raise ConfigError(f"{shown}: {err}") from None
        except ValueError:
            raise ConfigError(str(syntax)) from None
    if data is None:
        raise ConfigError(f"{shown}: holds no config keys (an empty file, or comments only)")
    if not isinstance(data, dict):
        raise ConfigError(
            f"{shown}: the top level must be a mapping of config keys (study: ..., seeds: [...]), "
            f"not a {type(data).__name__}"
        )
    return data


def _accepts_text(schema: dict) -> bool:
    types = schema.get("type", [])
    return not schema or "enum" in schema or "string" in ([types] if isinstance(types, str) else types)


def _leaves(value, path: tuple):
    if isinstance(value, dict) and value:
        for key, item in value.items():
            yield from _leaves(item, (*path, str(key)))
    else:
        yield path


def _merge(base: dict, override: dict) -> None:
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            _merge(base[key], value)
        else:
            base[key] = value


def _command_line_config(entries, schema: dict) -> dict:
    """The ``--config key=value`` entries read strictly (Snakemake reads a value it cannot parse
    as text, and keeps the last of a key given twice): a value that is not YAML where the schema
    wants no text, a key repeated inside a value or set by two entries is a ConfigError naming
    ``--config``."""
    merged, set_by = {}, {}
    for entry in entries:
        key, equals, text = str(entry).partition("=")
        if not equals:  # Snakemake refuses it before the Snakefile runs
            continue
        try:
            value = _strict_yaml(text, f"--config {key}", (key,), one_line=True)
        except _YamlSyntaxError as err:
            if not _accepts_text(schema.get("properties", {}).get(key, {})):
                raise ConfigError(str(err)) from None
            value = text
        for leaf in _leaves({key: value}, ()):
            for earlier, where in set_by.items():
                if leaf[: len(earlier)] == earlier or earlier[: len(leaf)] == leaf:
                    raise ConfigError(
                        f"--config: config key '{'.'.join(leaf)}' is given twice ({where!r} and {entry!r}); "
                        "Snakemake keeps the last one, without a word: give it once"
                    )
        set_by.update(dict.fromkeys(_leaves({key: value}, ()), entry))
        _merge(merged, {key: value})
    return merged


class ConfigSources(list):
    """Where a workflow's config came from: (label, keys) pairs in the order Snakemake merges them
    (a later one overrides), a file's label its path, the command line's ``--config``."""

    def where(self, key: str) -> str:
        """The label of the source that sets ``key`` (a dotted path), or the deepest part of it;
        all labels if none does (a default)."""
        best, depth = None, 0
        for label, data in self:
            found = 0
            for part in key.split("."):
                if isinstance(data, dict) and part in data:
                    data = data[part]
                elif isinstance(data, list) and part.isdigit() and int(part) < len(data):
                    data = data[int(part)]
                else:
                    break
                found += 1
            if found and found >= depth:
                best, depth = label, found
        return best or ", ".join(label for label, _ in self)

    def locate(self, error: ConfigError) -> ConfigError:
        """``error`` with the source of the first key it names put in front."""
        match = _KEY_IN_MESSAGE.search(str(error))
        where = self.where(match.group(1)) if match else ", ".join(label for label, _ in self)
        return ConfigError(f"{where}: {error}")


def read_config_sources(files, command_line=None, schema_path: str | os.PathLike = SCHEMA_PATH) -> ConfigSources:
    """The config ``files`` (in Snakemake's order) and ``--config`` entries (``key=value`` texts) of a
    workflow run, each read strictly ([`read_config_file`][suspension_fabric.study.config.read_config_file],
    `_command_line_config`)."""
    sources = ConfigSources((_shown(path), read_config_file(path)) for path in files)
    schema = read_schema(schema_path)
    overrides = _command_line_config(command_line or [], schema)
    if overrides:
        sources.append(("--config", overrides))
    return sources


def study_protocols(config: dict) -> dict[str, Protocol]:
    """Every protocol of a validated study: the paper's family (startup, then run.rotation_strain at
    each of angles_deg;
    [`suspension_fabric.io.protocols.paper_protocols`][suspension_fabric.io.protocols.paper_protocols]) and the config's
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
    their names ``startup`` and ``rotation_theta<angle>``;
    [`suspension_fabric.io.protocols.run_tree`][suspension_fabric.io.protocols.run_tree])."""
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
        # a pattern says nothing to a reader: add what the schema says the key is
        meant = first.schema.get("description", "").split(";")[0] if first.validator == "pattern" else ""
        raise ConfigError(f"config key '{key}': {first.message}" + (f" ({meant})" if meant else ""))


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


def validate_config(
    config: dict, schema_path: str | os.PathLike = SCHEMA_PATH, *, sources: ConfigSources | None = None
) -> dict:
    """Validate ``config`` in place against the schema (filling defaults), then cross-check keys;
    with ``sources`` ([`read_config_sources`][suspension_fabric.study.config.read_config_sources]) an error also names
    the file that set the key."""
    try:
        return _validate(config, schema_path)
    except ConfigError as err:
        if sources is None:
            raise
        raise sources.locate(err) from None


def _validate(config: dict, schema_path) -> dict:
    schema = read_schema(schema_path)
    config.update(_coerce_command_line_text(dict(config), schema))
    _check_numbers(config)
    engine_keys_given = [
        f"{section}.{key}"
        for section, key in ENGINE_KEYS
        if isinstance(config.get(section), dict) and key in config[section]
    ]
    _fill_and_validate(config, schema)
    if config["run"]["engine"] == "rule":
        _apply_engine_rule(config, engine_keys_given)
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


def _apply_engine_rule(config: dict, given: list[str]) -> None:
    """run.engine = rule: the engine's settings from the state point (simulation.engine_rule). A
    config validated before holds the rule's own values, which are accepted again."""
    phi, mu = config["particles"]["phi"], config["forces"]["mu"]
    try:
        finest_output = min(config["run"]["table_strain"], config["run"]["dump_strain"])
        choice = choose_engine(
            phi, mu, config["forces"]["eta_f"], finest_output, ranks=config["run"]["mpi_ranks"]
        ).as_record()
    except ValueError as err:
        raise ConfigError(
            f"config key 'run.engine' (rule) cannot choose the engine at particles.phi = {phi:g}, "
            f"forces.mu = {mu:g}: {err}; set run.engine: as_given with forces.kn and run.dt chosen by hand"
        ) from None
    differing = [name for name in given if config[name.split(".")[0]][name.split(".")[1]] != choice[name.split(".")[1]]]
    if differing:
        raise ConfigError(
            f"config key 'run.engine' (rule) chooses {', '.join(differing)} from the state point; give none of "
            "them, or set run.engine: as_given to set them yourself"
        )
    for section, key in ENGINE_KEYS:
        config[section][key] = choice[key]


#: The densest volume fraction the packing (pack.lmp: soft repulsion minimised at a fixed box) was
#: seen to reach without overlaps, for the paper's 1.4 bidisperse mix: 0.62 packed at N = 200, 0.63
#: left overlaps of 0.006-0.025 d at N = 200 and 1000 (simulation.lammps.pack, seed 1, 2026-12-07).
MAX_PACKED_PHI = 0.62


def _cross_check(config: dict) -> None:
    """The checks across keys that the schema cannot state."""
    run, analysis, particles = config["run"], config["analysis"], config["particles"]
    written = [seed for seed in config["seeds"] if not isinstance(seed, int) or isinstance(seed, bool)]
    if written:  # JSON Schema's integer admits 1.0, which would name a run folder seed1.0
        raise ConfigError(f"config key 'seeds': whole numbers without a decimal point expected, got {written}")
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
    if particles["phi"] > MAX_PACKED_PHI:
        raise ConfigError(
            f"config key 'particles.phi' ({particles['phi']}): above {MAX_PACKED_PHI}, the densest volume fraction "
            "the packing (pack.lmp) reaches without overlapping spheres; lower it"
        )
    if particles["d_large"] < particles["d_small"]:
        raise ConfigError("config key 'particles.d_large' must be >= particles.d_small")
    if particles["split"] == "volume" and particles["fraction_large"] >= 1:
        # pack.lmp turns a volume share into counts by dividing by 1 - fraction_large
        raise ConfigError(
            "config key 'particles.fraction_large' (1): with particles.split = volume the packing divides "
            "by 1 - fraction_large; for large spheres only use particles.split = number"
        )
    _check_box(particles, analysis["eps"])
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
    for key in ("startup_strain", "rotation_strain"):
        _check_steps(run[key], run, "run.dt", f"run.{key} ({run[key]:g})")
    _check_frames(config)
    if run["integrator"] == "explicit" and run["contact_springs"] == "implicit":
        raise ConfigError(
            "config key 'run.contact_springs' (implicit) needs run.integrator = implicit: the "
            "springs are solved with the implicit hydrodynamics"
        )
    if run["contact_solve"] == "newton" and run["contact_springs"] != "implicit":
        raise ConfigError(
            "config key 'run.contact_solve' (newton) needs run.contact_springs = implicit: it solves the "
            "contacts that fix hydro/implicit/sf owns"
        )
    if forces["critical_load_rate"] is not None and forces["critical_load_stress"] is not None:
        raise ConfigError(
            "config keys 'forces.critical_load_rate' and 'forces.critical_load_stress' exclude each other: "
            "a run imposes either its shear rate or its shear stress; drop one"
        )
    for key in ("critical_load_rate", "critical_load_stress"):
        if forces[key] is None:
            continue
        if forces["mu"] == 0:
            raise ConfigError(
                f"config key 'forces.{key}' needs forces.mu > 0: with mu = 0 every contact is "
                "frictionless whatever its load; drop the key or set mu"
            )
        if run["contact_springs"] != "implicit":
            raise ConfigError(
                f"config key 'forces.{key}' needs run.contact_springs = implicit (got "
                f"{run['contact_springs']}): only fix hydro/implicit/sf's own contacts have a critical load"
            )
    if run["local_solve_fraction"] > 0 and run["mpi_ranks"] > 1:
        raise ConfigError(
            f"config key 'run.local_solve_fraction' ({run['local_solve_fraction']:g}) needs run.mpi_ranks = 1: "
            "on several ranks each solves its patches without the couplings to the other ranks' atoms, "
            "and the global CG iterations grow instead of falling (BENCHMARKS.md, local solves); "
            "set run.local_solve_fraction = 0 to run on several ranks"
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
    _check_parameters_from(config["models"].get("parameters_from"), models)
    config["angles_deg"] = folded_angles(config["angles_deg"])
    labels = [angle_label(a) for a in config["angles_deg"]]
    if len(set(labels)) != len(labels):
        raise ConfigError(f"config key 'angles_deg': angles collide after formatting: {labels}")
    _check_protocols(config)


def frames_between(run: dict, strain: float, low: float, high: float, tolerance: float = 0.0) -> int:
    """How many fabric frames of a run of ``strain`` (one every run.dump_strain stride, from strain 0)
    lie in [low - tolerance, high + tolerance], their strains computed as the fabric tables do
    (step x dt, so a window's end on the grid may fall just outside it)."""
    dt = run["dt"]
    stride = output_stride(run["dump_strain"], dt)
    last = round(strain / dt) // stride
    low, high = low - tolerance, high + tolerance

    def at(k):
        return (k * stride) * dt

    first = max(0, math.floor(low / (stride * dt)) - 1)
    while first <= last and at(first) < low:
        first += 1
    end = min(last, math.ceil(high / (stride * dt)) + 1)
    while end >= 0 and at(end) > high:
        end -= 1
    return max(0, end - first + 1)


def _check_frames(config: dict) -> None:
    """The windows the analysis averages over hold frames: two per seed in the steady window
    (analysis.tables.steady_state), one after each rotation within verdicts.window (the claims and
    benchmarks average over the frames of (0, window])."""
    run, (low, high) = config["run"], config["analysis"]["steady_window"]
    frames = frames_between(run, run["startup_strain"], low, high)
    spacing = output_stride(run["dump_strain"], run["dt"]) * run["dt"]
    if frames < 2:
        raise ConfigError(
            f"config key 'analysis.steady_window' ([{low:g}, {high:g}]) holds {frames} fabric frame(s) of "
            f"the startup (one every {spacing:g} strain, run.dump_strain); the steady state averages "
            "at least 2 per seed: widen the window or lower run.dump_strain"
        )
    window = config["verdicts"]["window"]
    if spacing > window + 1e-9:
        raise ConfigError(
            f"config key 'verdicts.window' ({window:g}) holds no fabric frame after a rotation (the first "
            f"is at strain {spacing:g}, run.dump_strain); the claims and benchmarks average over the "
            "frames of (0, window]: widen it or lower run.dump_strain"
        )


def _check_steps(strain: float, run: dict, key: str, what: str) -> None:
    """A run of ``strain`` within the steps LAMMPS runs in one go."""
    steps = round(strain / run["dt"])
    if steps > LAMMPS_MAX_STEPS:
        raise ConfigError(
            f"config key '{key}': {what} takes {steps:.3g} steps of run.dt = {run['dt']:g}, more than "
            f"LAMMPS runs in one go ({LAMMPS_MAX_STEPS}, 'run N upto'); use a larger dt or a shorter run"
        )


def _box(particles: dict, n: int) -> tuple[float, float]:
    """The packing's box length for ``n`` particles (pack.lmp's counts, LAMMPS rounding halves up)
    and the largest diameter in it."""
    share = particles["fraction_large"]
    d_small, d_large = particles["d_small"], particles["d_large"]
    if particles["split"] == "volume":
        ratio = share * d_small**3 / ((1.0 - share) * d_large**3)
        share = ratio / (1.0 + ratio)
    n_large = math.floor(n * share + 0.5)
    volume = math.pi / 6.0 * ((n - n_large) * d_small**3 + n_large * d_large**3)
    return (volume / particles["phi"]) ** (1.0 / 3.0), d_large if n_large else d_small


def _check_box(particles: dict, eps: float) -> None:
    """The box wide enough for the fabric's near-contact search (analysis.fabric.near_contact_pairs):
    the largest near-contact distance d (1 + eps) below half the box's narrowest width, sheared."""
    length, diameter = _box(particles, particles["n"])
    half_width = 0.5 * SHEARED_WIDTH * length
    if diameter * (1.0 + eps) < half_width:
        return
    largest_eps = half_width / diameter - 1.0
    reason = (
        f"{particles['n']} particles at particles.phi = {particles['phi']:g} fill a box {length:.3g} wide, "
        f"{2 * half_width:.3g} across its narrowest faces when sheared (both tilts at half the box); the "
        f"fabric's near-contact search needs that above twice the largest near-contact distance "
        f"d (1 + analysis.eps) = {diameter * (1.0 + eps):.3g} (suspension_fabric.analysis.fabric.near_contact_pairs)"
    )
    if largest_eps > 0.01:  # the box would do for the paper's eps: eps is what is off
        raise ConfigError(f"config key 'analysis.eps' ({eps:g}): {reason}; use eps < {largest_eps:.3g}")
    n = max(particles["n"], math.ceil(particles["n"] * (diameter * (1.0 + eps) / half_width) ** 3))
    for _ in range(1000):  # the estimate is off by a few at most (rounded counts of each size)
        length, diameter = _box(particles, n)
        if diameter * (1.0 + eps) < 0.5 * SHEARED_WIDTH * length:
            break
        n += 1
    raise ConfigError(f"config key 'particles.n' ({particles['n']}): {reason}; use n >= {n}")


def _check_protocols(config: dict) -> None:
    """Every segment of the config's protocols a whole number of output strides long, so that the
    next segment starts on the output grid (as `_check_output_grid` for the paper's runs)."""
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
    low, high = config["analysis"]["steady_window"]
    for name in config.get("protocols") or {}:
        segments = protocols[name].segments
        for index, segment in enumerate(segments):
            _check_steps(segment.strain, run, f"protocols.{name}.{index}.strain", f"the segment ({segment.strain:g})")
            _check_turning(segment.turning_deg_per_strain, run, f"protocols.{name}.{index}.turning_deg_per_strain")
        # the protocol tables compare each later segment with the first's steady state
        # (analysis.protocol_tables.segment_states) and the benchmarks score the later ones only
        if len(segments) < 2:
            raise ConfigError(
                f"config key 'protocols.{name}': one segment; a protocol needs a first segment from rest "
                "into the steady state (analysis.steady_window) and at least one after it, which the "
                "protocol tables and benchmarks score"
            )
        if not frames_between(run, segments[0].strain, low, high, tolerance=1e-9):
            raise ConfigError(
                f"config key 'protocols.{name}.0.strain' ({segments[0].strain:g}): the first segment holds no "
                f"frame in analysis.steady_window ([{low:g}, {high:g}]), its steady state to which the "
                "protocol tables compare the later segments: make it reach the window"
            )


#: The most a rotary segment's flow direction may turn per time step and per fabric frame (degrees):
#: the box's tilt is updated once per step, and the fabric, read every run.dump_strain, must
#: follow the turning with at least 36 frames per turn.
MAX_TURN_PER_STEP_DEG = 0.1
MAX_TURN_PER_FRAME_DEG = 10.0


def _check_turning(rate: float, run: dict, key: str) -> None:
    """A rotary segment's turning resolved by the step and by the fabric frames, the limits stated."""
    for per, stride, limit in (
        ("time step (run.dt", run["dt"], MAX_TURN_PER_STEP_DEG),
        ("fabric frame (run.dump_strain", run["dump_strain"], MAX_TURN_PER_FRAME_DEG),
    ):
        if abs(rate) * stride > limit:
            raise ConfigError(
                f"config key '{key}' ({rate:g}): the flow turns {abs(rate) * stride:.3g} degrees per {per} = "
                f"{stride:g}), more than the {limit:g} that resolve it; turn slower or make the stride smaller"
            )


def _check_parameters_from(path, models: dict) -> None:
    """models.parameters_from: a parameters table that records what its fits saw and fits every model."""
    if path is None:
        return
    import pandas as pd

    from suspension_fabric.io.fit_provenance import check_provenance

    where = f"config key 'models.parameters_from' ({path})"
    if not Path(path).is_file():
        raise ConfigError(f"{where}: file not found (relative paths are from the working directory {Path.cwd()})")
    try:
        table = pd.read_csv(path)
        check_provenance(table, where)
    except (ValueError, pd.errors.ParserError) as error:
        raise ConfigError(str(error) if str(error).startswith(where) else f"{where}: {error}") from None
    missing = sorted(set(models) - set(table["model"]) if "model" in table.columns else set(models))
    if missing:
        raise ConfigError(f"{where}: no fits of the models {missing} of models.fabric")


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
    """Read (strictly, [`read_config_file`][suspension_fabric.study.config.read_config_file]) and validate a study YAML
    file; errors name the file and the key."""
    config = read_config_file(path)
    return validate_config(config, sources=ConfigSources([(_shown(path), config)]))


def load_layered_config(paths) -> dict:
    """Read and validate study YAML files layered in order, as the workflow reads
    ``--configfile A.yaml B.yaml`` (later files' keys replace earlier ones, nested sections merged);
    errors name the file and the key."""
    sources = read_config_sources(paths)
    config = {}
    for _, data in sources:
        _merge(config, yaml.safe_load(yaml.safe_dump(data)))  # a copy: the sources stay as read
    return validate_config(config, sources=sources)


def shipped_paths(config: dict, checkout: str | os.PathLike) -> dict:
    """Make absolute, in ``config`` (a study or campaign, changed in place and returned; a key of
    the wrong type is left to the validation), every relative path that names nothing in the
    working directory but something in ``checkout``: for this workflow imported as another one's
    module, whose working directory is the importer's, so that a study naming the checkout's
    datasets or model files (``data/...``) finds them. The paths: ``dataset``, the folders of
    ``verdicts.comparisons``, the files of ``models.fabric`` and ``models.stress`` (``path.json``,
    ``path.py:NAME``), ``campaign.datasets`` and the campaign's overrides of them. A path found in
    the working directory stays as it is."""
    checkout = Path(checkout)

    def shipped(path):
        if not isinstance(path, str) or not path or os.path.isabs(path) or os.path.exists(path):
            return path
        return str(checkout / path) if (checkout / path).exists() else path

    def model(spec):
        if not isinstance(spec, str):
            return spec
        location, colon, name = spec.rpartition(":")
        if colon and location.endswith(".py"):
            return f"{shipped(location)}:{name}"
        return shipped(spec) if spec.endswith(".json") else spec

    def study(section):
        if not isinstance(section, dict):
            return
        if "dataset" in section:
            section["dataset"] = shipped(section["dataset"])
        verdicts = section.get("verdicts")
        if isinstance(verdicts, dict) and isinstance(verdicts.get("comparisons"), dict):
            verdicts["comparisons"] = {label: shipped(folder) for label, folder in verdicts["comparisons"].items()}
        models = section.get("models")
        for kind in ("fabric", "stress"):
            if isinstance(models, dict) and isinstance(models.get(kind), list):
                models[kind] = [model(spec) for spec in models[kind]]

    study(config)
    campaign = config.get("campaign")
    if isinstance(campaign, dict):
        if "datasets" in campaign:
            campaign["datasets"] = shipped(campaign["datasets"])
        if isinstance(campaign.get("overrides"), dict):
            for override in campaign["overrides"].values():
                study(override)
    return config


def check_complete_study(config: dict, sources: ConfigSources | None = None) -> None:
    """What the full set of a validated study's outputs (the workflow's default target) needs
    beyond a valid config; a study short of it still runs single targets (e.g. one seed's startup).
    Errors name the key (and with ``sources`` the file that set it)."""
    study, message = config["study"], None
    if len(config["seeds"]) < 2:
        message = (
            f"config key 'seeds' ({config['seeds']}) of study {study}: its full set of outputs needs at "
            "least 2 seeds: the model benchmarks weight their fits by the seeds' standard errors and give "
            "intervals over seeds (suspension_fabric.evaluation.model_benchmark, stress_benchmark); one "
            f"seed still runs single targets, e.g. results/{study}/seed{config['seeds'][0]}/startup/fabric.csv"
        )
    elif len(config["angles_deg"]) < 2:
        message = (
            f"config key 'angles_deg' ({config['angles_deg']}) of study {study}: its full set of outputs "
            "needs at least 2 angles: the benchmarks' held-out evaluation predicts each fold of angles "
            "(models.held_out_folds, capped at the number of angles) from a fit on the others"
        )
    elif all(theta in (0, 180) for theta in config["angles_deg"]):
        message = (
            f"config key 'angles_deg' ({config['angles_deg']}) of study {study}: its full set of outputs "
            "needs an angle strictly between 0 and 180 degrees (either sign): the claims decide on the "
            "rotations that turn the vorticity, as <nn>'_23 is zero by symmetry at 0 and 180 "
            "(suspension_fabric.evaluation.claims)"
        )
    if message is not None:
        error = ConfigError(message)
        raise (error if sources is None else sources.locate(error)) from None


def check_comparison(config: dict, label: str, compared: dict, *, taken=(), stress: bool = True) -> None:
    """A dataset the validated study ``config`` is compared with (verdicts.comparisons: ``label`` ->
    a dataset folder, ``compared`` its config): its label must be none of ``taken`` (the study's own
    and its verdict choices, the other columns of the tables it joins), its rotations must reach
    verdicts.window (rule verdicts) and, with ``stress`` (rule compare_datasets, which averages it
    over the study's steady window), its startups must hold 2 frames in analysis.steady_window."""
    where = f"config key 'verdicts.comparisons': {label!r}"
    if label in taken:
        raise ConfigError(
            f"{where} is also the name of {'the study' if label == config['study'] else 'a verdict choice'} "
            f"in the tables the comparisons join (taken: {', '.join(map(repr, taken))}): choose another label"
        )
    run, window = compared["run"], config["verdicts"]["window"]
    if run["rotation_strain"] < window - 1e-9:
        raise ConfigError(
            f"{where} runs {run['rotation_strain']:g} strain after each rotation, less than "
            f"verdicts.window ({window:g}) over which its claims are decided"
        )
    low, high = config["analysis"]["steady_window"]
    if stress and frames_between(run, run["startup_strain"], low, high) < 2:
        raise ConfigError(
            f"{where}: its startups (to strain {run['startup_strain']:g}, a frame every "
            f"{run['dump_strain']:g}) hold fewer than 2 frames in this study's analysis.steady_window "
            f"([{low:g}, {high:g}]), over which rule compare_datasets averages both"
        )


def folded_angles(angles_deg) -> list:
    """The rotations of ``angles_deg`` once each, in their order: -180 degrees turns the flow as 180 does,
    so it is read as 180 and a repeat is dropped (a rotation simulated once)."""
    folded = []
    for theta in angles_deg:
        theta = 180 if theta == -180 else theta
        if theta not in folded:
            folded.append(theta)
    return folded


def angle_label(theta_deg: float) -> str:
    """Text of an angle for file names: 45 -> '45', 22.5 -> '22.5', -30 -> 'm30'."""
    text = f"{float(theta_deg):g}"
    return text.replace("-", "m")


if __name__ == "__main__":  # the command moved to study.validate, which also validates a campaign's points
    print("python -m suspension_fabric.study.validate CONFIG.yaml [MORE.yaml...] validates a study", file=sys.stderr)
    sys.exit(2)

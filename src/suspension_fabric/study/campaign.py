"""A campaign: one study per state point (volume fraction phi, friction mu), run by the same rules.

A config with a ``campaign`` section is a grid of studies: every key outside ``campaign`` is the
base study; each point of the grid ``campaign.phi`` x ``campaign.mu`` (x ``campaign.critical_load_rate``
or ``campaign.critical_load_stress`` if given: a flow curve per (phi, mu) under critical-load friction,
at imposed rates or stresses) is the base with ``particles.phi`` and ``forces.mu`` (and the flow curve's
``forces`` key) set, plus that point's
``campaign.overrides`` (nested study
keys, e.g. a longer startup near jamming). A point's outputs go to ``results/<study>/<point>``
(``point_name``: ``phi0.45_mu0.5``); the map over the points goes to ``results/<study>``.
``campaign.points`` runs a subset (``--config campaign='{points: [phi0.45_mu0.5]}'``);
``campaign.not_run`` names points left out, with the reason the map table gives for each;
``campaign.datasets`` takes every point's tables from ``<datasets>/<point>`` (a reference
dataset each, [`suspension_fabric.study.dataset`][suspension_fabric.study.dataset]) instead of simulating.
"""

from __future__ import annotations

import copy
from itertools import product

from suspension_fabric.simulation.engine_rule import ENGINE_KEYS

from .config import ConfigError, ConfigSources, validate_config

__all__ = [
    "point_name",
    "campaign_points",
    "study_configs",
    "is_flow_curve_campaign",
    "flow_curve_axis",
    "FLOW_CURVE_AXES",
]

#: Keys a point's overrides may not set: the campaign sets them for the point (its results folder,
#: its phi and mu, which its name states), so an override would be dropped or belie the name.
FIXED_BY_THE_CAMPAIGN = ("study", "campaign", "particles.phi", "forces.mu")


#: The flow-curve axes of a campaign: the config key (campaign and forces) -> the point name's tag
FLOW_CURVE_AXES = {"critical_load_rate": "rate", "critical_load_stress": "stress"}


def point_name(phi: float, mu: float, critical_load_rate: float | None = None, *, critical_load_stress=None) -> str:
    """Folder name of a state point: (0.45, 0.5) -> 'phi0.45_mu0.5', (0.4, 0) -> 'phi0.40_mu0',
    (0.54, 1, 0.03) -> 'phi0.54_mu1_rate0.03', (0.56, 1, critical_load_stress=0.1) -> 'phi0.56_mu1_stress0.1'."""
    name = f"phi{phi:.2f}_mu{mu:g}"
    for value, tag in zip((critical_load_rate, critical_load_stress), FLOW_CURVE_AXES.values()):
        if value is not None:
            name += f"_{tag}{value:g}"
    return name


def flow_curve_axis(config: dict) -> str | None:
    """The campaign's flow-curve axis (a key of FLOW_CURVE_AXES), None for a (phi, mu) grid; both
    axes at once are refused naming the keys."""
    campaign = config["campaign"] or {}
    given = [key for key in FLOW_CURVE_AXES if campaign.get(key)]
    if len(given) > 1:
        raise ConfigError(
            "config keys 'campaign.critical_load_rate' and 'campaign.critical_load_stress' exclude each other: "
            "a flow curve imposes either the rate or the stress at its points; make two campaigns"
        )
    return given[0] if given else None


def is_flow_curve_campaign(config: dict) -> bool:
    """Whether a validated config is a campaign of flow curves (``campaign.critical_load_rate``):
    its default target is each point's steady state, not the rotation study, so the full study's
    needs (two angles, an oblique one) do not apply to its points."""
    return flow_curve_axis(config) is not None


def _merged(base: dict, override: dict) -> dict:
    """``base`` with ``override`` merged in key by key (nested dicts merged, other values replaced)."""
    merged = copy.deepcopy(base)
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(merged.get(key), dict):
            merged[key] = _merged(merged[key], value)
        else:
            merged[key] = copy.deepcopy(value)
    return merged


def campaign_points(config: dict) -> dict[str, dict]:
    """The validated study config of every selected point of a validated campaign config, by
    point name, in grid order (phi, then mu). Errors name the point and the key."""
    campaign = config["campaign"]
    base = {key: value for key, value in config.items() if key != "campaign"}
    if base.get("run", {}).get("engine") == "rule":
        # the rule chose the base's engine for the base's own state point: each point chooses its own
        base = copy.deepcopy(base)
        for section, key in ENGINE_KEYS:
            base[section].pop(key, None)
    axis = flow_curve_axis(config)
    values = campaign[axis] if axis else [None]
    window = campaign.get("shape_window")
    if window is not None:
        inside = [value for value in (values if axis else []) if window[0] <= value <= window[1]]
        if len(inside) < 3:
            raise ConfigError(
                f"config key 'campaign.shape_window' ({window}): the shape of a flow curve needs 3 or more of "
                f"its imposed values (campaign.critical_load_rate or critical_load_stress) inside [low, high], "
                f"got {inside}"
            )

    def named(phi, mu, value):
        return point_name(phi, mu, **({axis: value} if axis else {}))

    grid = {named(*point): point for point in product(campaign["phi"], campaign["mu"], values)}
    if len(grid) != len(campaign["phi"]) * len(campaign["mu"]) * len(values):
        raise ConfigError(f"config key 'campaign': state points collide after naming: {sorted(grid)}")
    for key in ("points", "overrides", "not_run"):
        unknown = [name for name in campaign[key] if name not in grid]
        if unknown:
            raise ConfigError(
                f"config key 'campaign.{key}': {unknown[0]!r} is not a point of the grid "
                f"campaign.phi x campaign.mu (points: {', '.join(grid)})"
            )
    fixed = FIXED_BY_THE_CAMPAIGN + (("dataset",) if campaign["datasets"] else ())
    fixed += (f"forces.{axis}",) if axis else ()
    for name, override in campaign["overrides"].items():
        for key in fixed:
            section, _, inner = key.partition(".")
            if section in override and (
                not inner or isinstance(override[section], dict) and inner in override[section]
            ):
                raise ConfigError(
                    f"config key 'campaign.overrides.{name}.{key}': the campaign sets {key} of each point "
                    f"(from campaign.phi, campaign.mu, campaign.{axis or 'phi'}, campaign.datasets and its "
                    f"name {name}); an override "
                    "would be dropped or belie the point's name"
                )
    selected = [name for name in (campaign["points"] or grid) if name not in campaign["not_run"]]
    if not selected:
        raise ConfigError("config key 'campaign.points': no point left to run (all are in campaign.not_run)")
    points = {}
    for name in (name for name in grid if name in selected):
        phi, mu, value = grid[name]
        forces = {"mu": mu} if axis is None else {"mu": mu, axis: value}
        point = _merged(base, {"study": name, "particles": {"phi": phi}, "forces": forces})
        point = _merged(point, campaign["overrides"].get(name, {}))
        if campaign["datasets"]:
            point["dataset"] = f"{campaign['datasets']}/{name}"
        try:
            points[name] = validate_config(point)
        except ConfigError as err:
            raise ConfigError(
                f"campaign point {name} (config key 'campaign.overrides.{name}' or the base study): {err}"
            ) from None
        points[name]["study"] = f"{config['study']}/{name}"  # its results folder: results/<campaign>/<point>
    return points


def study_configs(config: dict, sources: ConfigSources | None = None) -> dict[str, dict]:
    """Every study a validated config describes, by study name (its results folder under
    ``results/``): the config itself, or each point of its campaign. With ``sources``
    ([`suspension_fabric.study.config.read_config_sources`][suspension_fabric.study.config.read_config_sources]) errors
    name the file too."""
    if config.get("campaign") is None:
        return {config["study"]: config}
    try:
        points = campaign_points(config)
    except ConfigError as err:
        if sources is None:
            raise
        raise sources.locate(err) from None
    return {point["study"]: point for point in points.values()}

"""The engine's rule for its stiffness, step and solve (suspension_fabric.simulation.engine_rule).

Checked: the pressure law through two points, Pi = A (phi_J - phi)^-2, recovers A and phi_J exactly;
the map's estimate is the measurement at a measured point and log-linear between points; the factor
is the smallest that meets kn / (eta_f Pi) >= 3e4; the step falls as 1 / factor (x10 with the Newton
solve from factor 25); the committed map's points get the stiffness their datasets were checked
with, except where the rule is cheaper; the first strain's pressure refuses a soft kn; the config's
run.engine: rule fills the keys and refuses them when given.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from suspension_fabric.io.schema import schema_default
from suspension_fabric.simulation import engine_rule
from suspension_fabric.simulation.engine_rule import (
    FIRST_STRAIN_MARGIN,
    STIFF_RATIO,
    PressureLaw,
    check_first_strain,
    choose_engine,
    fit_pressure_law,
    stiffness_factor,
)
from suspension_fabric.study.config import ConfigError, validate_config

KN0 = schema_default("forces", "kn")
DT0 = schema_default("run", "dt")
ETA0 = schema_default("forces", "eta_f")


def exact_law(amplitude, phi_j, phis, mu):
    return [(phi, mu, amplitude / (phi_j - phi) ** 2) for phi in phis]


def test_the_law_through_the_two_densest_points_recovers_its_parameters():
    points = exact_law(0.3, 0.58, [0.40, 0.50, 0.55], 0.5) + exact_law(0.1, 0.63, [0.45, 0.53], 0.0)
    law = fit_pressure_law(points)
    assert law.mu == (0.0, 0.5)
    assert law.phi_j == pytest.approx((0.63, 0.58), rel=1e-12)
    assert law.amplitude == pytest.approx((0.1, 0.3), rel=1e-10)


def test_the_estimate_is_the_measurement_at_a_point_and_log_linear_between():
    points = [(0.50, 0.0, 10.0), (0.55, 0.0, 40.0), (0.50, 1.0, 80.0), (0.55, 1.0, 1000.0)]
    law = fit_pressure_law(points)
    assert law.pressure(0.50, 0.0) == pytest.approx(10.0)
    assert law.pressure(0.525, 0.0) == pytest.approx(20.0)  # sqrt(10 * 40)
    assert law.pressure(0.50, 0.5) == pytest.approx(math.sqrt(10.0 * 80.0))
    # beyond the densest point: the law through the two densest, anchored there
    phi_j = law.phi_j[1]
    assert law.pressure(0.555, 1.0) == pytest.approx(1000.0 * ((phi_j - 0.55) / (phi_j - 0.555)) ** 2)
    # mu outside the map: the nearest mu's
    assert law.pressure(0.50, 2.0) == pytest.approx(80.0)
    with pytest.raises(ValueError, match="phi_J"):
        law.pressure(phi_j - 0.005, 1.0)


def test_the_factor_is_the_smallest_that_meets_the_requirement():
    assert stiffness_factor(0.2) == 1.0
    assert stiffness_factor(1.0) == 1.0
    assert stiffness_factor(1.01) == 2.0
    assert stiffness_factor(24.9) == 25.0
    assert stiffness_factor(63.0) == 62.5 * 2.5
    with pytest.raises(ValueError):
        stiffness_factor(float("nan"))


@pytest.mark.parametrize("pressure", [5.0, 40.0, 120.0, 400.0, 3000.0])
def test_the_choice_keeps_the_stiff_ratio_and_scales_the_step(pressure):
    law = PressureLaw((0.5,), (1.0,), (0.6,), ((0.5, 0.5, pressure), (0.45, 0.5, pressure / 2)))
    choice = choose_engine(0.5, 0.5, ETA0, law=law)
    assert choice.kn / (ETA0 * pressure) >= STIFF_RATIO
    # the next factor down would not do
    smaller = [f for f in engine_rule.STIFFNESS_FACTORS if f < choice.stiffness_factor]
    if smaller:
        assert KN0 * smaller[-1] / (ETA0 * pressure) < STIFF_RATIO
    newton = choice.stiffness_factor >= engine_rule.NEWTON_FROM_FACTOR
    assert choice.contact_solve == ("newton" if newton else "lagged")
    gain = engine_rule.NEWTON_STEP_GAIN if newton else 1.0
    assert choice.dt == pytest.approx(gain * DT0 / choice.stiffness_factor, rel=1e-11)


def test_kn_scales_with_the_fluid_viscosity_and_the_step_does_not():
    law = PressureLaw((0.5,), (1.0,), (0.6,), ((0.5, 0.5, 40.0), (0.45, 0.5, 20.0)))
    base, tenfold = choose_engine(0.5, 0.5, ETA0, law=law), choose_engine(0.5, 0.5, 10 * ETA0, law=law)
    assert tenfold.kn == pytest.approx(10 * base.kn)
    assert tenfold.dt == base.dt


def test_the_step_is_shortened_onto_the_output_grid():
    law = PressureLaw((0.5,), (1.0,), (0.6,), ((0.5, 0.5, 1000.0), (0.45, 0.5, 500.0)))
    free = choose_engine(0.5, 0.5, ETA0, law=law)
    on_grid = choose_engine(0.5, 0.5, ETA0, output_strain=0.001, law=law)
    steps = 0.001 / on_grid.dt
    assert abs(steps - round(steps)) < 1e-6
    assert on_grid.dt <= free.dt < 0.001 / (round(steps) - 1)


def test_the_map_was_made_by_the_rule():
    """At every point of the committed map (config/engine_pressure_law.json, from data/campaign) the
    rule's choice is the engine the point's dataset records: config/campaign.yaml (run.engine: rule)
    describes every dataset of data/campaign."""
    import json

    law = PressureLaw.read()
    repo = engine_rule.LAW_FILE.parents[1]
    assert len(law.points) == 15
    for phi, mu, _ in law.points:
        from suspension_fabric.study.campaign import point_name

        record = json.loads((repo / "data/campaign" / point_name(phi, mu) / "dataset.json").read_text())
        choice = choose_engine(phi, mu, ETA0, output_strain=0.02, law=law).as_record()
        for section, key in engine_rule.ENGINE_KEYS:
            # a record older than a key holds the key's default
            recorded = record["config"][section].get(key, schema_default(section, key))
            assert recorded == choice[key], (point_name(phi, mu), key)


def test_a_soft_kn_is_refused_by_the_first_strain_pressure():
    strain = np.linspace(0.0, 2.0, 201)
    pressure = np.where(strain < 0.5, 1.0, 100.0)
    limit = STIFF_RATIO / FIRST_STRAIN_MARGIN * ETA0 * 100.0
    assert check_first_strain(strain, pressure, 1.01 * limit, ETA0) == pytest.approx(100.0)
    with pytest.raises(ValueError, match=r"forces.kn.*Raise forces.kn to at least"):
        check_first_strain(strain, pressure, 0.99 * limit, ETA0)
    # a run shorter than its first strain's window: nothing to check
    assert math.isnan(check_first_strain(strain[:40], pressure[:40], 1.0, ETA0))


def rule_config(**particles):
    return {
        "study": "rule",
        "seeds": [1],
        "angles_deg": [0, 90],
        "particles": {"n": 500, **particles},
        "forces": {"mu": 1.0},
        "run": {"engine": "rule", "table_strain": 0.02},
    }


def test_run_engine_rule_fills_the_engine_keys_and_accepts_its_own_values():
    config = validate_config(rule_config(phi=0.55))
    choice = choose_engine(0.55, 1.0, ETA0, 0.02)
    assert config["forces"]["kn"] == choice.kn
    assert config["run"]["dt"] == choice.dt
    assert config["run"]["contact_solve"] == "newton"
    assert validate_config(copy.deepcopy(config)) == config


@pytest.mark.fault("refused")
def test_run_engine_rule_refuses_engine_keys_it_would_set_otherwise():
    config = rule_config(phi=0.50)
    config["forces"]["kn"] = 1.0e9
    with pytest.raises(ConfigError, match=r"'run.engine' \(rule\) chooses forces.kn"):
        validate_config(config)


@pytest.mark.fault("refused")
def test_run_engine_rule_refuses_a_point_at_the_laws_divergence():
    with pytest.raises(ConfigError, match=r"'run.engine'.*particles.phi = 0.57.*as_given"):
        validate_config(rule_config(phi=0.57))


def test_no_committed_startup_comes_near_the_first_strain_limit_as_the_docs_say():
    """Every startup in data/ passes check_first_strain with its own kn, and the lowest ratio
    kn / (eta_f Pi) over their first strains is the one docs/physics.md quotes."""
    import json
    import re

    import pandas as pd

    repo = engine_rule.LAW_FILE.parents[1]
    ratios = []
    for table in sorted((repo / "data").glob("**/startup/stress.csv")):
        variables = json.loads((table.parent / "run.json").read_text())["variables"]
        frame = pd.read_csv(table, usecols=["strain", "Pi"])
        kn, eta_f = float(variables["kn"]), float(variables["eta_f"])
        pressure = check_first_strain(frame["strain"], frame["Pi"], kn, eta_f, str(table))
        if not math.isnan(pressure):
            ratios.append(kn / (eta_f * pressure))
    assert len(ratios) > 100
    mantissa, exponent = f"{min(ratios):.1e}".split("e")
    quoted = re.search(
        r"lowest first-strain\s+ratio over every dataset in `data/` is \$([0-9.]+)\\times10\^(\d+)\$",
        (repo / "docs/physics.md").read_text(),
    )
    assert quoted is not None
    assert (quoted.group(1), int(quoted.group(2))) == (mantissa, int(exponent))


def test_the_docs_quote_the_rules_own_ratios():
    """docs/physics.md states the stiff ratio and the first strain's limit the module defines."""
    page = (engine_rule.LAW_FILE.parents[1] / "docs/physics.md").read_text()

    def latex(value: float) -> str:
        mantissa, exponent = f"{value:.1e}".split("e")
        return f"{mantissa}\\times10^{int(exponent)}"

    assert f"k_n/(\\eta_f \\Pi) \\ge {latex(STIFF_RATIO)}" in page
    assert f"k_n/(\\eta_f\\Pi) = {latex(STIFF_RATIO / FIRST_STRAIN_MARGIN)}" in page


def test_the_first_strains_pressure_against_the_steady_one_is_as_the_docs_say():
    """The margin FIRST_STRAIN_MARGIN covers the first strain's pressure, which docs/physics.md puts at
    0.5-1.3 times the steady one (strain 2-5) over the seeds of the map's points (data/campaign)."""
    import pandas as pd

    repo = engine_rule.LAW_FILE.parents[1]
    ratios = []
    for table in sorted((repo / "data/campaign").glob("*/seed*/startup/stress.csv")):
        frame = pd.read_csv(table, usecols=["strain", "Pi"])
        first = frame[(frame["strain"] > 0.5) & (frame["strain"] <= 1.0)]["Pi"].mean()
        steady = frame[(frame["strain"] > 2.0) & (frame["strain"] <= 5.0)]["Pi"].mean()
        ratios.append(first / steady)
    assert len(ratios) == 60
    quoted = f"{min(ratios):.1f}-{max(ratios):.1f} times the steady one"
    assert quoted in " ".join((repo / "docs/physics.md").read_text().split())
    assert max(ratios) < FIRST_STRAIN_MARGIN

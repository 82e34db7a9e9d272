"""The engine's own choice of contact stiffness, time step and contact solve at a state point.

With ``run.engine: rule`` a study gives no engine settings; they follow from (phi, mu) by one rule:

1. **Stiffness.** The contacts are taken as stiff while kn / (eta_f Pi) >= ``STIFF_RATIO`` (Pi the
   particle pressure in units of eta_f gammadot): the ratio of the map's densest point, (0.55, 1),
   which a check against twice its stiffness did not reject, while (0.45, 1) at 3.1e4 left the
   fabric's recovery after a reversal behind that of twice the stiffness (docs/physics.md, "How the
   engine chooses its settings", for how far this evidence goes). Pi is estimated by
   ``PressureLaw`` and kn is the default's, scaled with eta_f, times the smallest factor of
   ``STIFFNESS_FACTORS`` that meets the ratio: the factors the map's points were made with.
2. **Step and solve.** The contact relaxation time falls as 1 / kn, so the step does: the lagged
   contact solve at the default's 0.024 of it (dt = default dt / factor); from
   ``NEWTON_FROM_FACTOR`` on, where the lagged step gets short, the Newton solve at ten times that
   step (0.24 of the relaxation time), with the first iterate extrapolated, local solves and
   solver_tol 3e-4, the settings validated at the map's densest points.
3. **The pressure measured.** Each run from a packing has the pressure of its first strain (mean
   over strain 0.5-1) checked against ``STIFF_RATIO / FIRST_STRAIN_MARGIN`` when its stress table
   is made, which is refused, naming the kn needed, if the kn is too soft (``check_first_strain``):
   the estimate is checked by the run it sets up. The margin covers the first strain's pressure, 0.5-1.3 times the
   steady one at the map's points.

The pressure estimate (``PressureLaw``) is the map's: Pi measured at its points (the seeds' mean
over the steady window of the startups, ``python -m suspension_fabric.simulation.engine_rule fit
data/campaign``, written to ``LAW_FILE``), interpolated linearly in ln Pi over phi and mu; beyond the
map's volume fractions the form Pi = A (phi_J - phi)^-2 through the two densest measurements at each
friction coefficient carries the nearest measurement on; outside the map's mu the nearest mu's.
phi_J is the local divergence of that form, not a jamming analysis.
"""

from __future__ import annotations

import argparse
import functools
import glob
import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from suspension_fabric.io.resources import ENGINE_PRESSURE_LAW_PATH
from suspension_fabric.io.schema import schema_default

__all__ = [
    "STIFF_RATIO",
    "FIRST_STRAIN_MARGIN",
    "FIRST_STRAIN_WINDOW",
    "STIFFNESS_FACTORS",
    "NEWTON_FROM_FACTOR",
    "NEWTON_STEP_GAIN",
    "ENGINE_KEYS",
    "LAW_FILE",
    "PressureLaw",
    "EngineChoice",
    "stiffness_factor",
    "choose_engine",
    "stiffness_shortfall",
    "check_first_strain",
    "check_run_stiffness",
    "fit_pressure_law",
]

STIFF_RATIO = 3.6e4
FIRST_STRAIN_MARGIN = 1.5
#: strain window of the first strain whose mean pressure a run from a packing checks
FIRST_STRAIN_WINDOW = (0.5, 1.0)
STIFFNESS_FACTORS = (1.0, 2.0, 4.0, 10.0, 25.0, 62.5)
#: beyond the last factor each further one is this many times the one before
FACTOR_STEP_BEYOND = 2.5
NEWTON_FROM_FACTOR = 25.0
NEWTON_STEP_GAIN = 10.0
#: the Newton solve's settings at the map's densest points (docs/physics.md)
NEWTON_SETTINGS = {
    "contact_solve": "newton",
    "max_dt_per_relaxation": 0.25,
    "initial_guess": "quadratic",
    "local_solve_fraction": 0.02,
    "solver_tol": 3.0e-4,
}
#: the config keys the rule sets (section, key); a study with run.engine = rule gives none of them
ENGINE_KEYS = (
    ("forces", "kn"),
    ("run", "dt"),
    *(("run", key) for key in NEWTON_SETTINGS),
)
LAW_FILE = ENGINE_PRESSURE_LAW_PATH
#: a state point must lie this far below the law's phi_J: closer, the prediction diverges
MIN_DISTANCE_TO_PHI_J = 0.01


@dataclass(frozen=True)
class PressureLaw:
    """The particle pressure Pi measured at the ``points`` (phi, mu, Pi) of a grid over (phi, mu), and
    the law Pi = A (phi_J - phi)^-2 fitted at each of its friction coefficients (``mu``, ascending;
    ``amplitude``, ``phi_j``), which carries the measurements beyond the grid's volume fractions."""

    mu: tuple[float, ...]
    amplitude: tuple[float, ...]
    phi_j: tuple[float, ...]
    points: tuple[tuple[float, float, float], ...] = ()
    source: str = ""

    @classmethod
    def read(cls, path: str | Path = LAW_FILE) -> PressureLaw:
        """The law in ``path``, read once per process (every config validation asks for it)."""
        return _read_law(str(Path(path).resolve()))

    @classmethod
    def _parse(cls, path: str | Path) -> PressureLaw:
        try:
            record = json.loads(Path(path).read_text())
            points = tuple((p["phi"], p["mu"], p["Pi"]) for p in record["points"])
            return cls(
                tuple(record["mu"]), tuple(record["amplitude"]), tuple(record["phi_j"]), points, record["source"]
            )
        except (OSError, ValueError, KeyError, TypeError) as err:
            raise ValueError(
                f"the engine rule's pressure law {path} cannot be read ({err!r}); make it with "
                "`python -m suspension_fabric.simulation.engine_rule fit data/campaign`"
            ) from None

    def record(self) -> dict:
        return {
            "mu": list(self.mu),
            "amplitude": list(self.amplitude),
            "phi_j": list(self.phi_j),
            "points": [dict(zip(("phi", "mu", "Pi"), point)) for point in self.points],
            "source": self.source,
        }

    def _log_pressure_at(self, index: int, phi: float) -> float:
        """ln Pi at the fitted friction coefficient ``mu[index]``: the measurements interpolated
        linearly in phi inside their range, the law anchored at the nearest measurement outside it
        (the law alone where there are none)."""
        mu, phi_j = self.mu[index], self.phi_j[index]
        if phi > phi_j - MIN_DISTANCE_TO_PHI_J:
            raise ValueError(
                f"phi = {phi:g} is within {MIN_DISTANCE_TO_PHI_J:g} of the pressure law's phi_J = {phi_j:.4f} "
                f"at mu = {mu:g}, where the pressure diverges"
            )
        measured = sorted((p_phi, p_pi) for p_phi, p_mu, p_pi in self.points if p_mu == mu)
        if not measured:
            return math.log(self.amplitude[index]) - 2.0 * math.log(phi_j - phi)
        phis = np.array([m[0] for m in measured])
        logs = np.log([m[1] for m in measured])
        if phis[0] <= phi <= phis[-1]:
            return float(np.interp(phi, phis, logs))
        anchor = 0 if phi < phis[0] else -1
        return float(logs[anchor] + 2.0 * math.log((phi_j - phis[anchor]) / (phi_j - phi)))

    def pressure(self, phi: float, mu: float) -> float:
        """Pi at (phi, mu): linear in mu between the fitted friction coefficients, the end ones' outside."""
        mu = min(max(mu, self.mu[0]), self.mu[-1])
        upper = int(np.searchsorted(self.mu, mu))
        if upper == 0 or self.mu[upper] == mu:
            return math.exp(self._log_pressure_at(upper, phi))
        lower = upper - 1
        weight = (mu - self.mu[lower]) / (self.mu[upper] - self.mu[lower])
        log_pressure = (1 - weight) * self._log_pressure_at(lower, phi) + weight * self._log_pressure_at(upper, phi)
        return math.exp(log_pressure)


@functools.cache
def _read_law(path: str) -> PressureLaw:
    return PressureLaw._parse(path)


@dataclass(frozen=True)
class EngineChoice:
    """The rule's settings for a state point and why."""

    kn: float
    dt: float
    contact_solve: str
    max_dt_per_relaxation: float
    initial_guess: str
    local_solve_fraction: float
    solver_tol: float
    stiffness_factor: float
    predicted_pressure: float

    def as_record(self) -> dict:
        return asdict(self)


def stiffness_factor(required: float) -> float:
    """The smallest factor of STIFFNESS_FACTORS (continued by FACTOR_STEP_BEYOND) >= ``required``."""
    if not math.isfinite(required):
        raise ValueError(f"no stiffness factor meets {required}")
    for factor in STIFFNESS_FACTORS:
        if factor >= required:
            return factor
    factor = STIFFNESS_FACTORS[-1]
    while factor < required:
        factor *= FACTOR_STEP_BEYOND
    return factor


def _significant(value: float) -> float:
    return float(f"{value:.12g}")


def choose_engine(
    phi: float,
    mu: float,
    eta_f: float,
    output_strain: float | None = None,
    law: PressureLaw | None = None,
    ranks: int = 1,
) -> EngineChoice:
    """The rule (module doc) at (phi, mu) and fluid viscosity ``eta_f``; with ``output_strain`` (the
    finest output stride) the step is shortened to the longest that puts it on whole steps. On
    several ``ranks`` no local solves (they slow a solve split over ranks)."""
    law = PressureLaw.read() if law is None else law
    pressure = law.pressure(phi, mu)
    base_kn = schema_default("forces", "kn") * eta_f / schema_default("forces", "eta_f")
    factor = stiffness_factor(STIFF_RATIO * eta_f * pressure / base_kn)
    lagged_dt = schema_default("run", "dt") / factor
    if factor >= NEWTON_FROM_FACTOR:
        settings = dict(NEWTON_SETTINGS)
        dt = NEWTON_STEP_GAIN * lagged_dt
    else:
        settings = {key: schema_default("run", key) for key in NEWTON_SETTINGS}
        dt = lagged_dt
    if ranks > 1:
        settings["local_solve_fraction"] = 0.0
    if output_strain is not None:
        dt = output_strain / math.ceil(output_strain / dt * (1.0 - 1e-12))
    return EngineChoice(
        kn=_significant(base_kn * factor),
        dt=_significant(dt),
        stiffness_factor=factor,
        predicted_pressure=pressure,
        **settings,
    )


def stiffness_shortfall(kn: float, eta_f: float, first_strain_pressure: float) -> float | None:
    """The kn a run needs if the pressure of its first strain shows ``kn`` too soft, else None."""
    needed = STIFF_RATIO / FIRST_STRAIN_MARGIN * eta_f * first_strain_pressure
    return needed if kn < needed else None


def check_first_strain(strain, pressure, kn: float, eta_f: float, where: str = "the run") -> float:
    """The mean pressure over FIRST_STRAIN_WINDOW of a run from a packing (``strain``, ``pressure``:
    its stress table's columns, Pi in units of eta_f gammadot); a ValueError naming forces.kn and
    the kn needed if it shows ``kn`` too soft (``stiffness_shortfall``)."""
    strain, pressure = np.asarray(strain, dtype=float), np.asarray(pressure, dtype=float)
    inside = (strain > FIRST_STRAIN_WINDOW[0]) & (strain <= FIRST_STRAIN_WINDOW[1])
    if not inside.any():
        return float("nan")  # a startup shorter than its first strain: nothing to check
    mean = float(pressure[inside].mean())
    needed = stiffness_shortfall(kn, eta_f, mean)
    if needed is not None:
        raise ValueError(
            f"{where}: the particle pressure of the first strain, Pi = {mean:.4g} (mean over strain "
            f"{FIRST_STRAIN_WINDOW[0]:g}-{FIRST_STRAIN_WINDOW[1]:g}), puts config key 'forces.kn' = {kn:.4g} below the "
            f"stiff limit: kn / (eta_f Pi) = {kn / (eta_f * mean):.3g} < {STIFF_RATIO / FIRST_STRAIN_MARGIN:.3g}. "
            f"Raise forces.kn to at least {needed:.3g} (with run.dt scaled as 1 / kn), or set run.engine: rule "
            '(docs/physics.md, "How the engine chooses its settings")'
        )
    return mean


def check_run_stiffness(strain, pressure, marker: str | Path) -> float:
    """``check_first_strain`` for the run whose completion marker is ``marker`` if it started from a
    packing (its recorded kn and eta_f), else nothing to check (nan)."""
    record = json.loads(Path(marker).read_text())
    if record.get("flow_segment", {}).get("index", 0) != 0:
        return float("nan")
    variables = record["variables"]
    return check_first_strain(strain, pressure, float(variables["kn"]), float(variables["eta_f"]), str(marker))


def fit_pressure_law(points: list[tuple[float, float, float]], source: str = "") -> PressureLaw:
    """The law Pi = A (phi_J - phi)^-2 through the two densest of ``points`` (phi, mu, Pi) at each
    friction coefficient: the local divergence that carries the map beyond its densest point."""
    by_mu: dict[float, list[tuple[float, float]]] = {}
    for phi, mu, pressure in points:
        by_mu.setdefault(float(mu), []).append((float(phi), float(pressure)))
    mus, amplitudes, phi_js = [], [], []
    for mu in sorted(by_mu):
        measured = sorted(by_mu[mu])
        if len({phi for phi, _ in measured}) != len(measured) or len(measured) < 2:
            raise ValueError(f"mu = {mu:g}: the pressure law needs two or more distinct volume fractions, one Pi each")
        (phi_1, pressure_1), (phi_2, pressure_2) = measured[-2:]
        ratio = math.sqrt(pressure_2 / pressure_1)
        if not ratio > 1.0:
            raise ValueError(f"mu = {mu:g}: Pi does not rise from phi = {phi_1:g} to {phi_2:g}")
        phi_j = (ratio * phi_2 - phi_1) / (ratio - 1.0)
        mus.append(mu)
        amplitudes.append(pressure_2 * (phi_j - phi_2) ** 2)
        phi_js.append(phi_j)
    return PressureLaw(tuple(mus), tuple(amplitudes), tuple(phi_js), tuple(map(tuple, points)), source)


def steady_pressures(datasets: str | Path, window: tuple[float, float]) -> list[tuple[float, float, float]]:
    """(phi, mu, Pi) per point of a campaign's datasets (``<datasets>/<point>/seed*/startup/stress.csv``
    and the point's dataset.json): the seeds' mean of the mean Pi over the strain ``window``."""
    import pandas as pd

    points = []
    for record_file in sorted(Path(datasets).glob("*/dataset.json")):
        study = json.loads(record_file.read_text())["config"]
        if study["forces"].get("critical_load_rate") or study["forces"].get("critical_load_stress"):
            continue
        means = []
        for table in sorted(glob.glob(str(record_file.parent / "seed*" / "startup" / "stress.csv"))):
            frame = pd.read_csv(table, usecols=["strain", "Pi"])
            inside = frame[(frame["strain"] > window[0]) & (frame["strain"] <= window[1])]
            means.append(inside["Pi"].mean())
        if means:
            points.append((study["particles"]["phi"], study["forces"]["mu"], float(np.mean(means))))
    return points


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m suspension_fabric.simulation.engine_rule")
    sub = parser.add_subparsers(dest="command", required=True)
    fit = sub.add_parser("fit", help="fit the pressure law to a campaign's datasets and write it")
    fit.add_argument("datasets", help="a campaign's datasets folder, e.g. data/campaign")
    fit.add_argument("--window", nargs=2, type=float, default=(2.0, 5.0), help="steady strain window of the startups")
    fit.add_argument("--to", default=str(LAW_FILE))
    show = sub.add_parser("choose", help="print the rule's choice at a state point")
    show.add_argument("phi", type=float)
    show.add_argument("mu", type=float)
    show.add_argument("--eta-f", type=float, default=schema_default("forces", "eta_f"))
    args = parser.parse_args(argv)
    if args.command == "fit":
        points = steady_pressures(args.datasets, tuple(args.window))
        source = (
            f"{args.datasets}, mean Pi over startup strain {args.window[0]:g}-{args.window[1]:g}, {len(points)} points"
        )
        law = fit_pressure_law(points, source)
        target = Path(args.to)
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(json.dumps(law.record(), indent=1) + "\n")
        print(f"{target}: {source}")
        for mu, amplitude, phi_j in zip(law.mu, law.amplitude, law.phi_j):
            print(f"  mu = {mu:g}: A = {amplitude:.4g}, phi_J = {phi_j:.4f}")
    else:
        print(json.dumps(choose_engine(args.phi, args.mu, args.eta_f).as_record(), indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

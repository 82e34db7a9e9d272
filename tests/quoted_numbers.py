"""Every result number the docs quote in their prose, tied to the table it comes from.

The tables and per-angle lists of results are fragments the workflow writes (``docs/generated/``,
compared with the rebuild's own in tests/workflow/test_reference.py); what is left typed in the
prose is registered here. A :class:`Quote` is a passage of a page with each quoted number in
braces, and a function giving those numbers from the tables, in the same order:

- the passage, braces removed, must be in the page (line breaks and runs of spaces count as one
  space), so a quote that drifts from its text fails (``passage_problems``, a fast test:
  tests/docs/test_quoted_numbers.py);
- each braced number must be the table's value rounded to the decimals it is printed with (a
  leading "+" printed as a sign), so a table that changes fails (``value_problems``): the quotes
  of a rebuilt study inside its rebuild test, those of the committed datasets in the fast test.

Printed numbers are compared to one unit in their last digit (``printed_agrees``,
``fragment_problems``): a number is printed only to digits its computation reproduces across
floating-point configurations (another processor's BLAS kernels), and two such computations, equal
to well within that unit, can still round to neighbouring digits at a rounding boundary. A number
printed with a digit its computation does not reproduce fails the second-configuration rebuilds
(``second_float_config``), which is what these tests are for.

``study`` names the results a quote reads: "reference" (config/reference.yaml), "default_reference"
(config/default_reference.yaml) or None for the committed datasets alone (``data/``).
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import json
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import t_interval

REPO = Path(__file__).resolve().parents[1]
# (not a LaTeX sub- or superscript: the 12 of $\langle nn\rangle_{12}$ is not a quoted number)
_BRACED = re.compile(r"(?<![_^])\{([-+]?\d+(?:\.\d+)?)\}")


class Results:
    """A study's results folder (``results/<study>``): its tables, read once each."""

    def __init__(self, folder: Path):
        self.folder = Path(folder)
        self._tables: dict[str, pd.DataFrame] = {}
        self.computed: dict = {}  # what the quotes compute from the tables, once

    def table(self, name: str) -> pd.DataFrame:
        if name not in self._tables:
            self._tables[name] = pd.read_csv(self.folder / "tables" / name)
        return self._tables[name]

    def fits(self) -> dict:
        return json.loads((self.folder / "fits.json").read_text())

    def row(self, name: str, **where) -> pd.Series:
        """The one row of table ``name`` whose columns equal ``where`` (numbers to 1e-9)."""
        table = self.table(name)
        keep = np.ones(len(table), dtype=bool)
        for column, value in where.items():
            if isinstance(value, (int, float)):
                keep &= np.isclose(table[column].to_numpy(dtype=float), value, rtol=0, atol=1e-9)
            else:
                keep &= (table[column] == value).to_numpy()
        rows = table[keep]
        if len(rows) != 1:
            raise LookupError(f"{name}: {len(rows)} rows with {where}")
        return rows.iloc[0]


@dataclass(frozen=True)
class Quote:
    page: str
    passage: str
    values: Callable[..., list[float]]
    study: str | None = "reference"


@dataclass(frozen=True)
class GeneratedTable:
    """A table of a page that a script prints from committed data: its head line, and the rows the
    script prints now (tests/docs/test_benchmarks_numbers.py compares each row of the page with them)."""

    page: str
    head: str
    rows: Callable[[], list[str]]


GENERATED_TABLES: list[GeneratedTable] = []


def passage_text(quote: Quote) -> str:
    return _BRACED.sub(r"\1", quote.passage)


def _flat(text: str) -> str:
    return re.sub(r"\s+", " ", text).strip()


def passage_problems(quotes: list[Quote]) -> list[str]:
    """Each quote whose passage is no longer in its page, or that braces no number."""
    problems = []
    for quote in quotes:
        if not _BRACED.search(quote.passage):
            problems.append(f"{quote.page}: no braced number in {quote.passage!r}")
        if _flat(passage_text(quote)) not in _flat((REPO / quote.page).read_text()):
            problems.append(f"{quote.page}: not found: {passage_text(quote)!r}")
    return problems


def last_digit_unit(text: str) -> float:
    """One unit in the last printed digit of ``text``: '1.038' -> 0.001, '66' -> 1."""
    return 10.0 ** -(len(text.split(".")[1]) if "." in text else 0)


def printed_agrees(value: float, text: str) -> bool:
    """``value`` printed as ``text`` within one unit of its last digit (the module docstring)."""
    return printed(value, text) == text or abs(value - float(text)) <= last_digit_unit(text) * (1 + 1e-9)


_NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def fragment_problems(made: str, committed: str) -> list[str]:
    """Where a generated fragment differs from the committed one: any text outside numbers, a
    number printed with other digits, or one more than a unit of its last digit away."""
    made_numbers, committed_numbers = _NUMBER.findall(made), _NUMBER.findall(committed)
    if _NUMBER.sub("#", made) != _NUMBER.sub("#", committed) or len(made_numbers) != len(committed_numbers):
        return ["the text outside the numbers differs"]
    problems = []
    for mine, theirs in zip(made_numbers, committed_numbers):
        if mine == theirs:
            continue
        same_digits = last_digit_unit(mine) == last_digit_unit(theirs) and ("e" in mine.lower()) == (
            "e" in theirs.lower()
        )
        if not same_digits or "e" in mine.lower() or not printed_agrees(float(mine), theirs):
            problems.append(f"{theirs} (committed) is {mine} (made)")
    return problems


def printed(value: float, like: str) -> str:
    """``value`` printed as ``like`` is: its decimals, its "+" if it has one."""
    decimals = len(like.split(".")[1]) if "." in like else 0
    text = f"{value:{'+' if like.startswith('+') else ''}.{decimals}f}"
    return text.replace("-", "") if float(text) == 0.0 else text  # no "-0.00"


def value_problems(quotes: list[Quote], results: dict[str, Results]) -> list[str]:
    """Each quoted number that is not its table's value at the printed precision."""
    problems = []
    for quote in quotes:
        typed = _BRACED.findall(quote.passage)
        values = quote.values(results[quote.study]) if quote.study else quote.values()
        if len(values) != len(typed):
            problems.append(f"{quote.page}: {len(typed)} numbers, {len(values)} values: {quote.passage!r}")
            continue
        for text, value in zip(typed, values):
            if not printed_agrees(float(value), text):
                problems.append(f"{quote.page}: {text} is {float(value)!r} in the tables: {passage_text(quote)!r}")
    return problems


# -- the committed datasets ----------------------------------------------------------------------


@cache
def dataset_fits(folder: str) -> dict:
    from suspension_fabric.study.dataset import read_dataset

    return read_dataset(REPO / folder)["fits"]


@cache
def loaded(folder: str):
    from suspension_fabric.study.dataset import load

    return load(REPO / folder)


def megabytes(folder: str) -> float:
    return sum(p.stat().st_size for p in (REPO / folder).rglob("*") if p.is_file()) / 1e6


def core_hours(folder: str) -> float:
    """What a dataset's runs cost: the LAMMPS wall times their run records hold (one core each)."""
    import json

    from suspension_fabric.study.dataset import read_dataset

    keys = [key for key in read_dataset(REPO / folder)["files"] if key.endswith("/run.json")]
    return sum(json.loads((REPO / folder / key).read_text())["wall_time_s"] for key in keys) / 3600


def steady_stress(folder: str, quantity: str, column: str = "mean") -> float:
    table = loaded(folder).steady_stress
    return float(table.loc[table["quantity"] == quantity, column].iloc[0])


# -- helpers on a study's tables -----------------------------------------------------------------


def interval(row: pd.Series, prefix: str = "") -> list[float]:
    """[mean, low, high] of a row (``prefix``: "difference" for its difference columns)."""
    if prefix:
        return [row[prefix], row[f"{prefix}_low"], row[f"{prefix}_high"]]
    return [row["mean"], row["low"], row["high"]]


def choice(r: Results, name: str, claim: str) -> pd.Series:
    return r.row("verdict_choices.csv", choice=name, claim=claim)


def per_angle(r: Results, claim: str, theta: float) -> pd.Series:
    return r.row("claims_per_angle.csv", claim=claim, theta=theta)


def compared(r: Results, label_start: str, quantity: str, theta: float | None = None) -> pd.Series:
    table = r.table("dataset_comparison.csv")
    named = table["dataset"] == label_start  # the study itself by its name, a dataset by its label's start
    rows = table[
        (named if named.any() else table["dataset"].str.startswith(label_start)) & (table["quantity"] == quantity)
    ]
    rows = rows[rows["theta"].isna()] if theta is None else rows[np.isclose(rows["theta"], theta)]
    if len(rows) != 1:
        raise LookupError(f"dataset_comparison.csv: {len(rows)} rows for {label_start}, {quantity}, {theta}")
    return rows.iloc[0]


def welch(first: pd.Series, second: pd.Series, level: float = 0.95) -> list[float]:
    """second - first with Welch's interval from the two rows' standard errors and seeds."""
    from scipy import stats

    se2 = first["se"] ** 2 + second["se"] ** 2
    dof = se2**2 / (first["se"] ** 4 / (first["n_seeds"] - 1) + second["se"] ** 4 / (second["n_seeds"] - 1))
    half = stats.t.ppf(0.5 + level / 2, dof) * np.sqrt(se2)
    difference = second["mean"] - first["mean"]
    return [difference, difference - half, difference + half]


def steady(r: Results, quantity: str, column: str = "mean", table: str = "stress_steady_state.csv") -> float:
    return float(r.row(table, quantity=quantity)[column])


def peaks(r: Results, window: float = 2.0) -> pd.DataFrame:
    from suspension_fabric.reporting.rotation_fragments import peak_ratios

    return peak_ratios(
        r.table("predictions.csv"), r.table("rotation_aggregate.csv"), r.fits()["targets"]["n12"]["mean"], window
    )


def deficit_d12(r: Results, model: str | None, theta: float, window: float = 2.0) -> float:
    """D12 = integral over (0, window] of 1 - <nn>'_12/<nn>_12^ss: the simulation's seed mean
    (model None) or a model's prediction from its steady fit."""
    ss = r.fits()["targets"]["n12"]["mean"]
    if model is None:
        rows = r.table("rotation_aggregate.csv")
        rows = rows[np.isclose(rows["theta"], theta) & (rows["strain"] <= window + 1e-9)].sort_values("strain")
        values = rows["n12_mean"]
    else:
        rows = r.table("predictions.csv")
        rows = rows[
            (rows["model"] == model)
            & (rows["protocol"] == "rotation")
            & np.isclose(rows["theta"], theta)
            & (rows["strain"] <= window + 1e-9)
        ].sort_values("strain")
        values = rows["n12"]
    return float(np.trapezoid(1.0 - values.to_numpy() / ss, rows["strain"].to_numpy()))


def relation_curve(r: Results, source: str, theta: float) -> pd.DataFrame:
    """The G-W stress relation's eta_r / eta_r^ss after a rotation on one fabric source
    (stress_predictions.csv), over the strain."""
    rows = r.table("stress_predictions.csv")
    rows = rows[(rows["source"] == source) & (rows["protocol"] == "rotation") & np.isclose(rows["theta"], theta)]
    rows = rows.sort_values("strain")
    return pd.DataFrame({"strain": rows["strain"], "ratio": rows["eta_r"] / steady(r, "eta_r")})


def simulated_rotation(r: Results, column: str, theta: float, strain: float = 0.0) -> float:
    """A simulated stress column of stress_rotation_aggregate.csv at a strain after a rotation, in
    units of eta_r^ss."""
    return float(r.row("stress_rotation_aggregate.csv", theta=theta, strain=strain)[column]) / steady(r, "eta_r")


def predicted_rotation(r: Results, column: str, theta: float, source: str = "simulation", strain: float = 0.0) -> float:
    row = r.row("stress_predictions.csv", source=source, protocol="rotation", theta=theta, strain=strain)
    return float(row[column]) / steady(r, "eta_r")


def rms(r: Results, source: str, quantity: str, thetas) -> list[float]:
    table = r.table("stress_model_errors.csv")
    rows = table[(table["protocol"] == "rotation") & (table["source"] == source) & (table["quantity"] == quantity)]
    return [float(rows.loc[np.isclose(rows["theta"], t), "rms_error"].iloc[0]) for t in thetas]


def relation_minima(r: Results, relation: str, thetas, smoothing: float = 0.1) -> list[tuple[float, float]]:
    """(minimum, strain) of a stress relation's seed-mean eta_r / eta_r^ss after each rotation,
    on every seed's own simulated fabric with the relation's fit of stress_relation_parameters.csv,
    smoothed as the simulation's viscosity transients are (stress_model.viscosity_transients)."""
    from suspension_fabric.evaluation import stress_benchmark
    from suspension_fabric.evaluation.stress_model import moving_average
    from suspension_fabric.models.stress_relations import resolve_relations

    if "stress curves" not in r.computed:
        tables = r.folder / "tables"
        r.computed["stress curves"] = stress_benchmark.read_stress_curves(
            *(tables / f"{name}_runs.csv" for name in ("startup", "rotation", "stress_startup", "stress_rotation")),
            2.0,
            (2.0, 5.0),
        )
    curves = r.computed["stress curves"]
    fitted = r.table("stress_relation_parameters.csv")
    fitted = fitted[(fitted["relation"] == relation) & ~fitted["parameter"].isin(["a_H", "a_C"])]
    predicted = stress_benchmark.relation_predictions(
        resolve_relations([relation])[relation], dict(zip(fitted["parameter"], fitted["value"])), curves
    )
    found = []
    for theta in thetas:
        ratio = predicted["eta_r rotation"][:, list(curves.thetas).index(theta)].mean(axis=0) / curves.eta_ss
        smoothed = moving_average(curves.rotation_strains, ratio, smoothing)
        found.append((float(smoothed.min()), float(curves.rotation_strains[np.argmin(smoothed)])))
    return found


def lowest(frame: pd.DataFrame) -> tuple[float, float]:
    """(smallest ratio, its strain) of a curve."""
    at = frame["ratio"].idxmin()
    return float(frame.loc[at, "ratio"]), float(frame.loc[at, "strain"])


# -- the quotes ----------------------------------------------------------------------------------

RESULTS = "docs/results.md"

QUOTES: list[Quote] = [
    # The paper at scale
    Quote(
        RESULTS,
        "every file's SHA-256 and the fits ({43.5} MB with the fourth moment below;",
        lambda: [megabytes("data/reference")],
        None,
    ),
    Quote(
        RESULTS,
        'reference.steady_fabric.set_index("quantity").loc["n12", "mean"]  # {-0.1054}',
        lambda: [dataset_fits("data/reference")["targets"]["n12"]["mean"]],
        None,
    ),
    Quote(
        RESULTS,
        "any plotted cell (angle, strain frame) is {0.026} of $\\left\\lvert \\langle nn\\rangle^{\\mathrm{ss}}_{12}"
        "\\right\\rvert$ for $\\langle nn\\rangle'_{12}$ and {0.029} for $\\langle nn\\rangle'_{23}$",
        lambda r: list(_cells(r).values()),
    ),
    # In words, for a referee
    Quote(
        RESULTS,
        "*simulated* strain-5 fabric the claim is refuted ($T = {-0.050}$ [{-0.089}, {-0.011}])",
        lambda r: interval(choice(r, "state: simulated", "C1")),
    ),
    Quote(
        RESULTS,
        "**C2, G-W underestimates the effect on $\\langle nn\\rangle_{23}$ at large angles: confirmed, narrowly** "
        "({0.038} [{0.015}, {0.060}] against an effect size of 1.25)",
        lambda r: interval(choice(r, "primary", "C2")),
    ),
    Quote(
        RESULTS,
        "$\\langle nn\\rangle'_{23}$ transient is too large there: $E_{23}$ {0.62} against the simulation's {0.43} at "
        "90) and confirmed at 135-165 ({0.50} against {0.79} at 135)",
        lambda r: [
            per_angle(r, "C2", 90)["reference"],
            per_angle(r, "C2", 90)["sim"],
            per_angle(r, "C2", 135)["reference"],
            per_angle(r, "C2", 135)["sim"],
        ],
    ),
    Quote(
        RESULTS,
        "it is larger, because it overshoots: $\\langle nn\\rangle'_{12}$ by {49}% of steady at 90 degrees",
        lambda r: [100 * per_angle(r, "C5", 90)["challenger"]],
    ),
    Quote(
        RESULTS,
        "per angle it is refuted at {90}-{120} degrees (G-W's",
        lambda r: _angles_with(r, "C2", "refuted", 90, 165),
    ),
    Quote(
        RESULTS,
        "and confirmed at {135}-{165} (0.50 against 0.79 at 135)",
        lambda r: _angles_with(r, "C2", "confirmed", 90, 165),
    ),
    Quote(
        RESULTS,
        "$\\langle nn\\rangle'_{23}$ transient ($E_{23}$ {1.04}-{1.30} at 105-150 degrees against the simulation's "
        "{0.54}-{0.83}).",
        lambda r: [
            min(per_angle(r, "C2", t)["challenger"] for t in (105, 120, 135, 150)),
            max(per_angle(r, "C2", t)["challenger"] for t in (105, 120, 135, 150)),
            min(per_angle(r, "C2", t)["sim"] for t in (105, 120, 135, 150)),
            max(per_angle(r, "C2", t)["sim"] for t in (105, 120, 135, 150)),
        ],
    ),
    Quote(
        RESULTS,
        "kinetic (velocity fluctuations, {0.0001} on $\\sigma_{12}$ at reference v2's steady state)",
        lambda r: [steady(r, "kinetic_12")],
    ),
    Quote(
        RESULTS,
        "**C5, the modified model overshoots $\\langle nn\\rangle_{12}$ near 90 degrees: confirmed** ({0.41} above the "
        "5% threshold)",
        lambda r: [choice(r, "primary", "C5")["mean"]],
    ),
    Quote(
        RESULTS,
        "**C6, ... and the simulations do not: confirmed** ({0.127} [{0.100}, {0.154}]:",
        lambda r: interval(choice(r, "primary", "C6")),
    ),
    # System size
    Quote(
        RESULTS,
        "The viscosity dip after a rotation at N = 1000 (v2): $V = {0.073}$ [{0.024}, {0.122}] at 90 degrees and "
        "{0.198} [{0.159}, {0.237}] at 120; the seed-mean curve's minimum is {0.863} [{0.838}, {0.881}] of steady "
        "at 90",
        lambda r: [
            *interval(compared(r, "reference", "viscosity_deficit", 90)),
            *interval(compared(r, "reference", "viscosity_deficit", 120)),
            *(
                r.row("stress_viscosity_transients.csv", theta=90)[c]
                for c in ("minimum", "minimum_low", "minimum_high")
            ),
        ],
    ),
    Quote(
        RESULTS,
        "its deficit exceeds v2's by {0.080} [{0.003}, {0.156}] at 90 degrees and {0.096} [{0.031}, {0.160}] "
        "at 120, and its $N_2$ is lower by {0.57} [{0.23}, {0.90}]",
        lambda r: [
            *interval(compared(r, "N = 500,", "viscosity_deficit", 90), "difference"),
            *interval(compared(r, "N = 500,", "viscosity_deficit", 120), "difference"),
            -compared(r, "N = 500,", "N2")["difference"],
            -compared(r, "N = 500,", "N2")["difference_high"],
            -compared(r, "N = 500,", "N2")["difference_low"],
        ],
    ),
    Quote(
        RESULTS,
        "to 165, and 180, with the fourth moment, {34} MB)",
        lambda: [megabytes("data/reference_n2000")],
        None,
    ),
    Quote(
        RESULTS,
        "$\\langle nn\\rangle_{12}$ {-0.1052} [{-0.1061}, {-0.1044}], $Z$ {3.503}, $\\eta_r$ {15.46} "
        "[{15.31}, {15.61}], $N_2$ {-5.57}; differences to v2 within ±{0.006} in the fabric, ±{0.41} in $\\eta_r$) "
        "and in the viscosity deficit at every angle (90 degrees: {0.042} [{0.013}, {0.071}], difference {-0.031} "
        "[{-0.086}, {0.025}])",
        lambda r: [
            *interval(compared(r, "N = 2000", "n12")),
            compared(r, "N = 2000", "Z")["mean"],
            *interval(compared(r, "N = 2000", "eta_r")),
            compared(r, "N = 2000", "N2")["mean"],
            max(
                max(abs(compared(r, "N = 2000", q)[c]) for c in ("difference_low", "difference_high"))
                for q in ("n11", "n22", "n33", "n12")
            ),
            max(abs(compared(r, "N = 2000", "eta_r")[c]) for c in ("difference_low", "difference_high")),
            *interval(compared(r, "N = 2000", "viscosity_deficit", 90)),
            *interval(compared(r, "N = 2000", "viscosity_deficit", 90), "difference"),
        ],
    ),
    Quote(
        RESULTS,
        "Its fits: G-W $\\beta$ {10.96} ± {0.04}, modified $\\beta$ {9.34}, $A$ {45.3}.",
        lambda: [
            dataset_fits("data/reference_n2000")["models"]["gw"]["parameters"]["beta"],
            dataset_fits("data/reference_n2000")["models"]["gw"]["errors"]["beta"],
            dataset_fits("data/reference_n2000")["models"]["modified"]["parameters"]["beta"],
            dataset_fits("data/reference_n2000")["models"]["modified"]["parameters"]["A"],
        ],
        None,
    ),
    Quote(
        RESULTS,
        "C2 included: {0.034} [{0.017}, {0.051}] over 90-165 degrees with 16 seeds, against v2's {0.038} "
        "[{0.015}, {0.060}] (difference {-0.004} [{-0.031}, {0.024}], Welch",
        lambda r: [
            *interval(choice(r, "N = 2000 (data/reference_n2000)", "C2")),
            *interval(choice(r, "primary", "C2")),
            *welch(choice(r, "primary", "C2"), choice(r, "N = 2000 (data/reference_n2000)", "C2")),
        ],
    ),
    Quote(
        RESULTS,
        "(v2 per angle: {-0.355} at 90, +{0.164} at 135)",
        lambda r: [per_angle(r, "C2", 90)["mean"], per_angle(r, "C2", 135)["mean"]],
    ),
    # the fabric-model leaderboard
    Quote(
        RESULTS,
        "at 90 degrees its peak of $\\langle nn\\rangle'_{12}/\\langle nn\\rangle^{\\mathrm{ss}}_{12}$ is {1.092}, the "
        "simulation's {1.095}, the modified model's {1.486})",
        lambda r: [peaks(r).loc[90.0, c] for c in ("separate_rates", "simulation", "modified")],
    ),
    Quote(
        RESULTS,
        "(integrated deficit {0.56} at 90 degrees against the simulation's {0.11})",
        lambda r: [deficit_d12(r, "separate_rates", 90), deficit_d12(r, None, 90)],
    ),
    # the stress-relation leaderboard
    Quote(
        RESULTS,
        "cuts the error of the viscosity after a rotation on held-out angles by {60}% and removes G-W's bias "
        "({+0.048} to {+0.002}): as the coordination drops after a reversal ({3.5} to {2.8})",
        lambda r: [
            100 * (1 - _stress(r, "gw_jamming")["held_out_mse"] / _stress(r, "gw")["held_out_mse"]),
            _stress(r, "gw")["bias"],
            _stress(r, "gw_jamming")["bias"],
            steady(r, "Z", table="steady_state.csv"),
            _lowest_z(r, 180),
        ],
    ),
    Quote(
        RESULTS,
        "its viscosity minimum comes at strain {0.24}-{0.32} after the rotation (simulated: {0.14}-{0.30}) instead "
        "of at the rotation, and is deeper ({0.51} at reversal against G-W's {0.61}; simulated {0.38})",
        lambda r: [
            min(s for _, s in relation_minima(r, "gw_jamming", (90, 135, 180))),
            max(s for _, s in relation_minima(r, "gw_jamming", (90, 135, 180))),
            r.row("stress_viscosity_transients.csv", theta=90)["strain_at_min"],
            r.row("stress_viscosity_transients.csv", theta=180)["strain_at_min"],
            relation_minima(r, "gw_jamming", (180,))[0][0],
            relation_minima(r, "gw", (180,))[0][0],
            r.row("stress_viscosity_transients.csv", theta=180)["minimum"],
        ],
    ),
    # the paper-scale stress
    Quote(
        RESULTS,
        "the steady state is $\\eta_r = {15.53} \\pm {0.14}$ (contact {10.50} ± {0.14}, lubrication {2.906} ± "
        "{0.004}), $N_1 = {-1.22} \\pm {0.11}$, $N_2 = {-5.56} \\pm {0.10}$, $\\Pi = {12.24} \\pm {0.18}$; the "
        "relation fitted on the simulated fabric ($a_H = {25.44} \\pm {0.07}$, $a_C = {131.8} \\pm {1.1}$) predicts "
        "$N_1 = +{1.57}$, $N_2 = {-10.8}$, $\\Pi = {15.8}$",
        lambda r: [
            *(
                steady(r, q, c)
                for q in ("eta_r", "contact_12", "lubrication_12", "N1", "N2", "Pi")
                for c in ("mean", "sem_between_seeds")
            ),
            *(r.row("stress_relation_fits.csv", source="simulation")[c] for c in ("a_H", "a_H_err", "a_C", "a_C_err")),
            *(r.row("stress_relation_fits.csv", source="simulation")[f"{q}_predicted"] for q in ("N1", "N2", "Pi")),
        ],
    ),
    Quote(
        RESULTS,
        "The deficit excludes 0 from {75} degrees on.",
        lambda r: [_decided_from(r.table("stress_viscosity_transients.csv"))],
    ),
    Quote(
        RESULTS,
        "(0.86 at 90, 0.81 at 105, 0.61 at 180 degrees); on the G-W fabric it reaches {0.74}, {0.65} and {0.37} there",
        lambda r: [lowest(relation_curve(r, "gw", t))[0] for t in (90, 105, 180)],
    ),
    Quote(
        RESULTS,
        "at the rotation itself or just after it ({0.86} at 90, {0.81} at 105, {0.61} at 180 degrees)",
        lambda r: [lowest(relation_curve(r, "simulation", t))[0] for t in (90, 105, 180)],
    ),
    Quote(
        RESULTS,
        "The N = 500 study's dip is deeper at 90 and 120 degrees by {0.080} [{0.003}, {0.156}] and {0.096} "
        "[{0.031}, {0.160}] (Welch intervals",
        lambda r: [
            *interval(compared(r, "N = 500,", "viscosity_deficit", 90), "difference"),
            *interval(compared(r, "N = 500,", "viscosity_deficit", 120), "difference"),
        ],
    ),
    # the N = 500 study (config/default_reference.yaml)
    Quote(
        RESULTS,
        "| {15.63} +- {0.27} | {10.63} +- {0.27} | {2.88} +- {0.02} | {-0.74} +- {0.27} | {-6.13} +- {0.22} | "
        "{12.24} +- {0.35} |",
        lambda r: [
            steady(r, q, c)
            for q in ("eta_r", "contact_12", "lubrication_12", "N1", "N2", "Pi")
            for c in ("mean", "sem")
        ],
        "default_reference",
    ),
    Quote(
        RESULTS,
        "Contacts carry {68}% of $\\eta_r$ ({79}% of the particle part) and all of the pressure. Fitted coefficients: "
        "simulated fabric $a_H = {25.2} \\pm {0.2}$, $a_C = {134} \\pm {3}$; G-W fabric {56.7}, {224}; modified fabric "
        "{26.6}, {140}.",
        lambda r: [
            100 * steady(r, "contact_12") / steady(r, "eta_r"),
            100 * steady(r, "contact_12") / (steady(r, "eta_r") - steady(r, "solvent_12") - steady(r, "einstein_12")),
            *(r.row("stress_relation_fits.csv", source="simulation")[c] for c in ("a_H", "a_H_err", "a_C", "a_C_err")),
            *(r.row("stress_relation_fits.csv", source=s)[c] for s in ("gw", "modified") for c in ("a_H", "a_C")),
        ],
        "default_reference",
    ),
    Quote(
        RESULTS,
        "it predicts $N_1 = +{1.5}$ (simulated {-0.74}), $N_2 = {-11.0}$ ({-6.1}) and $\\Pi = {16.0}$ ({12.2}): $N_2$ "
        "and $\\Pi$ too large by {79}% and {31}%, $N_1$ of the wrong sign. On the model fabrics $N_2$ is {-12.9} (G-W) "
        "and {-7.9} (modified).",
        lambda r: [
            *(
                r.row("stress_relation_fits.csv", source="simulation")[f"{q}_{c}"]
                for q in ("N1", "N2", "Pi")
                for c in ("predicted", "simulated")
            ),
            *(
                100 * (_fit(r, "simulation")[f"{q}_predicted"] / _fit(r, "simulation")[f"{q}_simulated"] - 1)
                for q in ("N2", "Pi")
            ),
            _fit(r, "gw")["N2_predicted"],
            _fit(r, "modified")["N2_predicted"],
        ],
        "default_reference",
    ),
    Quote(
        RESULTS,
        "At the rotation $\\eta_r$ is predicted within {0.04} at every angle ({0.85} against {0.86} at 90 degrees, "
        "{0.59} against {0.58} at reversal), but the contact part is too high ({0.51} against {0.25} at 90 degrees, "
        "{0.27} against {0.00} at reversal) and the lubrication jump ({0.18} to {0.48} at 90 degrees) is missing",
        lambda r: [
            max(
                abs(predicted_rotation(r, "eta_r", t) - simulated_rotation(r, "eta_r_mean", t))
                for t in (0, 30, 60, 90, 120, 150, 180)
            ),
            predicted_rotation(r, "eta_r", 90),
            simulated_rotation(r, "eta_r_mean", 90),
            predicted_rotation(r, "eta_r", 180),
            simulated_rotation(r, "eta_r_mean", 180),
            predicted_rotation(r, "contact_12", 90),
            simulated_rotation(r, "contact_12_mean", 90),
            predicted_rotation(r, "contact_12", 180),
            simulated_rotation(r, "contact_12_mean", 180),
            steady(r, "lubrication_12") / steady(r, "eta_r"),
            simulated_rotation(r, "lubrication_12_mean", 90),
        ],
        "default_reference",
    ),
    Quote(
        RESULTS,
        "The simulation dips to {0.77} (90 degrees) and {0.37} (reversal) of steady at strain {0.18}-{0.30}; the "
        "relation on the simulated fabric is lowest at the rotation or just after it ({0.85} and {0.58}) and then "
        "rises",
        lambda r: [
            r.row("stress_viscosity_transients.csv", theta=90)["minimum"],
            r.row("stress_viscosity_transients.csv", theta=180)["minimum"],
            r.row("stress_viscosity_transients.csv", theta=90)["strain_at_min"],
            r.row("stress_viscosity_transients.csv", theta=180)["strain_at_min"],
            lowest(relation_curve(r, "simulation", 90))[0],
            lowest(relation_curve(r, "simulation", 180))[0],
        ],
        "default_reference",
    ),
    Quote(
        RESULTS,
        "rms error of $\\eta_r$: {0.06} for $\\theta \\le 60$ degrees, {0.09}-{0.20} beyond.",
        lambda r: [
            max(rms(r, "simulation", "eta_r", (0, 30, 60))),
            min(rms(r, "simulation", "eta_r", (90, 120, 150, 180))),
            max(rms(r, "simulation", "eta_r", (90, 120, 150, 180))),
        ],
        "default_reference",
    ),
    Quote(
        RESULTS,
        "Its minima ({0.74}, {0.57}, {0.42}, {0.37} at 90, 120, 150, 180 degrees) match the simulated ones ({0.77}, "
        "{0.60}, {0.44}, {0.37}) but occur at the rotation, not 0.2-0.3 strain later; rms error of $\\eta_r$ "
        "{0.04}-{0.09} at 0-150 degrees",
        lambda r: [
            *(lowest(relation_curve(r, "gw", t))[0] for t in (90, 120, 150, 180)),
            *(r.row("stress_viscosity_transients.csv", theta=t)["minimum"] for t in (90, 120, 150, 180)),
            min(rms(r, "gw", "eta_r", (0, 30, 60, 90, 120, 150))),
            max(rms(r, "gw", "eta_r", (0, 30, 60, 90, 120, 150))),
        ],
        "default_reference",
    ),
    Quote(
        RESULTS,
        "all along at 60-90 degrees (rms up to {0.26}), the worst for $\\eta_r$ from 60 degrees on",
        lambda r: [max(rms(r, "modified", "eta_r", (0, 30, 60, 90, 120, 150, 180)))],
        "default_reference",
    ),
    Quote(
        RESULTS,
        "The relation gives +{0.04} to +{0.15} at 30-150 degrees from its contact term; the simulation's is within "
        "±{0.08} and negative at 30-60 degrees, where the lubrication part ({-0.11} and {-0.15} at the rotation) "
        "outweighs the contact part (+{0.05} and +{0.11}); the relation's hydrodynamic term gives almost none (at "
        "most {0.01}).",
        lambda r: [
            min(predicted_rotation(r, "total_23", t) for t in (30, 60, 90, 120, 150)),
            max(predicted_rotation(r, "total_23", t) for t in (30, 60, 90, 120, 150)),
            max(abs(simulated_rotation(r, "total_23_mean", t)) for t in (0, 30, 60, 90, 120, 150, 180)),
            simulated_rotation(r, "lubrication_23_mean", 30),
            simulated_rotation(r, "lubrication_23_mean", 60),
            simulated_rotation(r, "contact_23_mean", 30),
            simulated_rotation(r, "contact_23_mean", 60),
            max(abs(predicted_rotation(r, "lubrication_23", t)) for t in (0, 30, 60, 90, 120, 150, 180)),
        ],
        "default_reference",
    ),
]

FABRIC_MODELS = "docs/fabric_models.md"

QUOTES += [
    Quote(
        FABRIC_MODELS,
        "(it needs $b_c \\approx {-4.6}$), hence the choice of $\\langle nn\\rangle_{33}$ "
        "($\\langle nn\\rangle_{22}$ and $\\langle nn\\rangle_{33}$ differ by {0.5}% there)",
        lambda: [_separate_rates_fitted_to_22()["beta_c"], _n22_over_n33_percent()],
        None,
    ),
    Quote(
        FABRIC_MODELS,
        "(its peak is within {0.03} of the simulation's from 45 to 105 degrees, where the modified model overshoots "
        "by {23}-{42}% of $\\langle nn\\rangle^{\\mathrm{ss}}_{12}$)",
        lambda r: [
            max(abs(peaks(r).loc[t, "separate_rates"] - peaks(r).loc[t, "simulation"]) for t in (45, 60, 75, 90, 105)),
            min(100 * (peaks(r).loc[t, "modified"] - peaks(r).loc[t, "simulation"]) for t in (45, 60, 75, 90, 105)),
            max(100 * (peaks(r).loc[t, "modified"] - peaks(r).loc[t, "simulation"]) for t in (45, 60, 75, 90, 105)),
        ],
    ),
    Quote(
        FABRIC_MODELS,
        "(better by {0.004} [{0.001}, {0.007}]). The separate-rates model recovers slowly after the rotation (its "
        "breaking rate $\\beta_e = {4.6}$ is less than half G-W's $\\beta = {11.0}$)",
        lambda r: [
            -_board(r, "modified", "global", "n23")["held_out_difference_vs_gw"],
            -_board(r, "modified", "global", "n23")["held_out_difference_high_vs_gw"],
            -_board(r, "modified", "global", "n23")["held_out_difference_low_vs_gw"],
            r.row("model_parameters.csv", model="separate_rates", mode="steady", parameter="beta_e")["value"],
            r.row("model_parameters.csv", model="gw", mode="steady", parameter="beta")["value"],
        ],
    ),
    Quote(
        FABRIC_MODELS,
        "is {0.56} at 90 degrees and {0.96} at 135 against the simulation's {0.11} and {0.35} (G-W {0.37} and {0.71}).",
        lambda r: [
            deficit_d12(r, "separate_rates", 90),
            deficit_d12(r, "separate_rates", 135),
            deficit_d12(r, None, 90),
            deficit_d12(r, None, 135),
            deficit_d12(r, "gw", 90),
            deficit_d12(r, "gw", 135),
        ],
    ),
    Quote(
        FABRIC_MODELS,
        "and $\\beta = {50}$ ruins $\\langle nn\\rangle'_{12}$.",
        lambda r: [r.row("model_parameters.csv", model="gw", mode="global", parameter="beta")["value"]],
    ),
    Quote(
        FABRIC_MODELS,
        "which the simulation completes (every component within 10% of steady) by strain {0.96}, these three models "
        "by strain {3.1} to {5.0}",
        lambda r: [
            _settled_startup(r, None),
            min(_settled_startup(r, m) for m in ("gw", "modified", "separate_rates")),
            max(_settled_startup(r, m) for m in ("gw", "modified", "separate_rates")),
        ],
    ),
    Quote(
        FABRIC_MODELS,
        "after a reversal Z drops from {3.5} to {2.8} while the simulated contact stress",
        lambda r: [steady(r, "Z", table="steady_state.csv"), _lowest_z(r, 180)],
    ),
    Quote(
        FABRIC_MODELS,
        "viscosity minimum after a rotation by 90, 135 and 180 degrees is {0.86}, {0.56} and {0.38} of steady at "
        "strain {0.14}, {0.20} and {0.30} in the simulation; G-W on the simulated fabric gives {0.87}, {0.71} and "
        "{0.61} at strain {0} to {0.06}, gw_jamming {0.81}, {0.62} and {0.51} at strain {0.24} to {0.32}.",
        lambda r: [
            *(r.row("stress_viscosity_transients.csv", theta=t)["minimum"] for t in (90, 135, 180)),
            *(r.row("stress_viscosity_transients.csv", theta=t)["strain_at_min"] for t in (90, 135, 180)),
            *(m for m, _ in relation_minima(r, "gw", (90, 135, 180))),
            min(s for _, s in relation_minima(r, "gw", (90, 135, 180))),
            max(s for _, s in relation_minima(r, "gw", (90, 135, 180))),
            *(m for m, _ in relation_minima(r, "gw_jamming", (90, 135, 180))),
            min(s for _, s in relation_minima(r, "gw_jamming", (90, 135, 180))),
            max(s for _, s in relation_minima(r, "gw_jamming", (90, 135, 180))),
        ],
    ),
]

GW_STRESS = "docs/gw_stress_relation.md"

QUOTES += [
    Quote(
        GW_STRESS,
        "negligible at St = 1/223: (total - contact - lubrication)_xz = {0.000} $\\eta_f\\dot\\gamma$ in the "
        "steady state",
        lambda: [steady_stress("data/default", "kinetic_12")],
        None,
    ),
    Quote(
        GW_STRESS,
        "In the steady state that pressure is almost nil ({0.025} of $\\Pi = {12.24}$ in the reference data: "
        "approaching and separating pairs cancel), early in startup it dominates ({2.9} of $\\Pi = {3.8}$ at strain "
        "0.2-0.3 in the reference data",
        lambda r: [
            _lubrication_pressure(r.table("stress_steady_state.csv").set_index("quantity")["mean"]),
            steady(r, "Pi"),
            *_early_pressures(r, 0.2, 0.3),
        ],
    ),
    Quote(
        GW_STRESS,
        "(X11, X22, X33, X12) = ({0.547}, {0.599}, {0.591}, {-0.103}) (`data/default`'s fits), H12 = {0.114} and "
        "C12 = {0.079} by the closure.",
        lambda: [
            *(dataset_fits("data/default")["targets"][c]["mean"] for c in ("n11", "n22", "n33", "n12")),
            *_closure_h12_c12(dataset_fits("data/default")["targets"]),
        ],
        None,
    ),
    Quote(
        GW_STRESS,
        "the G-W steady fabric has Tr = {0.76}, the modified model's n33 = {1.01}, the simulation's Tr = {1.74}",
        lambda: [
            sum(dataset_fits("data/default")["models"]["gw"]["steady_state"][c] for c in ("n11", "n22", "n33")),
            dataset_fits("data/default")["models"]["modified"]["steady_state"]["n33"],
            sum(dataset_fits("data/default")["targets"][c]["mean"] for c in ("n11", "n22", "n33")),
        ],
        None,
    ),
    Quote(
        GW_STRESS,
        "(iii) the G-W steady fabric (beta = {10.75}), (iv) the modified model's (beta = {9.25}, A = {44.8}).",
        lambda: [
            dataset_fits("data/default")["models"]["gw"]["parameters"]["beta"],
            dataset_fits("data/default")["models"]["modified"]["parameters"]["beta"],
            dataset_fits("data/default")["models"]["modified"]["parameters"]["A"],
        ],
        None,
    ),
]


def scaling_table(name: str) -> pd.DataFrame:
    """A table of benchmarks/mpi_scaling.py (benchmarks/data/mpi_scaling/<name>)."""
    return pd.read_csv(REPO / "benchmarks/data/mpi_scaling" / name)


def scaling_median(name: str, column: str, **where) -> float:
    """Median of ``column`` over the rows of the table whose columns equal ``where``; the column
    "cost" is the loop time per atom per step."""
    table = scaling_table(name)
    for key, value in where.items():
        table = table[table[key] == value if isinstance(value, str) else np.isclose(table[key], value)]
    values = table["loop_s"] / (table["steps"] * table["n"]) if column == "cost" else table[column]
    return float(values.median())


def mpi_speedup(n: int, table: str = "measure.csv") -> float:
    """Median over the alternating pairs of benchmarks/mpi_scaling.py measure: 1-rank loop time
    over 2-rank loop time."""
    return mpi_speedups(table, n)[-1]


OTHER_PAGES = [
    Quote(
        "docs/workflow.md",
        "fabric and per-frame stress tables, {1.8} MB)",
        lambda: [megabytes("data/default")],
        None,
    ),
    Quote(
        "docs/workflow.md",
        "N = 16000: {1.53}x faster on 2 ranks than on 1 at the same `run.solver_tol`",
        lambda: [mpi_speedup(16000)],
        None,
    ),
]
QUOTES += OTHER_PAGES

# -- docs/physics.md's summary of the MPI research (benchmarks/data/mpi_scaling) -----------------


def preconditioner_pairs() -> list[float]:
    """benchmarks/solver_prototype/rank_ordered_dilu_pair.sh: per pair, the 2-rank loop time with block
    Jacobi across the ranks over that with the dilu order across them; then their median."""
    table = scaling_table("n16000/rank_ordered_dilu_pair.csv")
    times = table.pivot(index="pair", columns="preconditioner", values="loop_s")
    ratios = list(times["block_jacobi"] / times["rank_ordered_dilu"])
    return ratios + [float(np.median(ratios))]


def contention_figures(table: str = "contention.csv", repeats: bool = False) -> list[float]:
    """benchmarks/mpi_scaling.py contention: the slowdown of two 1-rank runs at once over one alone (%),
    its median, least and largest over the repeats, and the 2-rank speed-up that median allows; with
    repeats, each repeat's slowdown first."""
    table = scaling_table(f"n16000/{table}")
    slowdowns = 100.0 * ((table["first_s"] + table["second_s"]) / 2 / table["alone_s"] - 1.0)
    median = float(slowdowns.median())
    figures = [median, float(slowdowns.min()), float(slowdowns.max()), 2.0 / (1.0 + median / 100.0)]
    return (list(slowdowns) if repeats else []) + figures


def mpi_speedups(table: str, n: int = 16000) -> list[float]:
    """benchmarks/mpi_scaling.py measure: 1-rank over 2-rank loop time per alternating pair, then their median."""
    rows = scaling_table(f"n{n}/{table}")
    ratios = list(rows[rows["ranks"] == 1]["loop_s"].to_numpy() / rows[rows["ranks"] == 2]["loop_s"].to_numpy())
    return ratios + [float(np.median(ratios))]


PHYSICS = "docs/physics.md"
MPI_RESEARCH_QUOTES = [
    Quote(
        PHYSICS,
        "at N = 16000, {10.85} CG iterations per step on 2 ranks against {15.40} with block Jacobi across the ranks "
        "(one rank: {9.90} in `measure`'s longer window).",
        lambda: [
            scaling_median("n16000/rank_ordered_dilu_pair.csv", "iterations", preconditioner="rank_ordered_dilu"),
            scaling_median("n16000/rank_ordered_dilu_pair.csv", "iterations", preconditioner="block_jacobi"),
            scaling_median("n16000/measure.csv", "iterations", ranks=1),
        ],
        None,
    ),
    Quote(
        PHYSICS,
        "It gave no faster steps (median loop-time ratio {0.96} over six pairs)",
        lambda: preconditioner_pairs()[-1:],
        None,
    ),
    Quote(
        PHYSICS,
        "two at once take {2.2}% longer (median; {-4.4}% to {+8.2}%, as much as the machine's own drift between "
        "runs). That bounds the 2-rank speed-up at about {1.96}x. So the {1.53}x is not the shared memory's",
        lambda: contention_figures() + [mpi_speedup(16000)],
        None,
    ),
    Quote(
        PHYSICS,
        "the local solves make the solve slower, not faster: {37.85} global CG iterations per step against {15.35} "
        "without them",
        lambda: [
            scaling_median("n16000/measure_local0.02.csv", "iterations", ranks=2),
            scaling_median("n16000/measure.csv", "iterations", ranks=2),
        ],
        None,
    ),
]
QUOTES += MPI_RESEARCH_QUOTES


# -- BENCHMARKS.md's record of the test suite's CPU (benchmarks/suite_cpu.py) ---------------------


@cache
def benchmark_script(name: str):
    """A script of benchmarks/ as a module (it may import its sibling scripts)."""
    folder = str(REPO / "benchmarks")
    spec = importlib.util.spec_from_file_location(name, REPO / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, folder)
    try:
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(folder)
    return module


def suite_cpu_figures(commit: str) -> list[float]:
    """benchmarks/suite_cpu.py's record of a commit: the processes and their CPU; those outside any
    test, their CPU, the CPU and count of the Snakemake job steps among them; the reference
    rebuild's and the map rebuild's CPU."""
    suite_cpu = benchmark_script("suite_cpu")
    table = suite_cpu.read_record(REPO / "benchmarks/data/suite_cpu" / f"{commit}.tsv")
    outside = suite_cpu.outside_summary(table)

    def test_cpu(name: str) -> float:
        return float(table.loc[table["test"].str.endswith(name), "cpu_s"].sum())

    return [
        len(table),
        float(table["cpu_s"].sum()),
        outside["processes"],
        outside["cpu_s"],
        outside["job_steps_cpu_s"],
        outside["job_steps"],
        test_cpu("test_the_reference_study_rebuilds_the_fits_without_simulating"),
        test_cpu("test_the_map_rebuilds_from_the_committed_datasets_as_the_docs_show_it"),
    ]


QUOTES.append(
    Quote(
        "BENCHMARKS.md",
        "{644} Python processes spent {1110} s of CPU; the largest items were the study on SLURM ({79} s outside "
        "any test) and the reference and map rebuilds ({172} s and {136} s).",
        lambda: [figure for k, figure in enumerate(suite_cpu_figures("4e6495e")) if k in (0, 1, 3, 6, 7)],
        None,
    )
)


# -- BENCHMARKS.md's reading of the N-scaling and local-solve tables -----------------------------

SIZES = "local_solves_n500_n4000_n16000.csv"
LARGEST = "local_solves_n500_n32000.csv"
BENCHMARK_QUOTES = [
    Quote(
        "BENCHMARKS.md",
        "Its cost per atom per step on one rank is about {3.1} times N = 500's, and its global CG iterations "
        "({12.10} per step) continue the growth with N of the table above ({4.20}, {7.65}, {9.90} at N = 500, 4000, "
        "16000): {1.1} more per doubling of N from 4000 to 16000, {2.2} from 16000 to 32000. Local solves take "
        "{40}% of the iterations there ({12.10} to {7.20}) and {10}% of the time.",
        lambda: [
            scaling_median(LARGEST, "cost", n=32000, local_solve_fraction=0)
            / scaling_median(LARGEST, "cost", n=500, local_solve_fraction=0),
            scaling_median(LARGEST, "iterations", n=32000, local_solve_fraction=0),
            *(scaling_median(SIZES, "iterations", n=n, local_solve_fraction=0) for n in (500, 4000, 16000)),
            (
                scaling_median(SIZES, "iterations", n=16000, local_solve_fraction=0)
                - scaling_median(SIZES, "iterations", n=4000, local_solve_fraction=0)
            )
            / 2,
            scaling_median(LARGEST, "iterations", n=32000, local_solve_fraction=0)
            - scaling_median(SIZES, "iterations", n=16000, local_solve_fraction=0),
            100
            * (
                1
                - scaling_median(LARGEST, "iterations", n=32000, local_solve_fraction=0.02)
                / scaling_median(LARGEST, "iterations", n=32000, local_solve_fraction=0)
            ),
            scaling_median(LARGEST, "iterations", n=32000, local_solve_fraction=0),
            scaling_median(LARGEST, "iterations", n=32000, local_solve_fraction=0.02),
            100
            * (
                1
                - scaling_median(LARGEST, "cost", n=32000, local_solve_fraction=0.02)
                / scaling_median(LARGEST, "cost", n=32000, local_solve_fraction=0)
            ),
        ],
        None,
    ),
]
QUOTES += BENCHMARK_QUOTES


@cache
def scheduler_overhead() -> pd.DataFrame:
    """benchmarks/data/scheduler_overhead.csv (commit 8c75e99: benchmarks/scheduler_overhead.py --save)."""
    return pd.read_csv(REPO / "benchmarks/data/scheduler_overhead.csv")


def cpu_range(column: str, setting: str | None = None) -> list[float]:
    """The smallest and largest CPU seconds in a column, over one setting's rounds or every row."""
    table = scheduler_overhead()
    values = table[column] if setting is None else table.loc[table["setting"] == setting, column]
    return [values.min(), values.max()]


QUOTES.append(
    Quote(
        "BENCHMARKS.md",
        "the profiles' greedy scheduler cut Snakemake's own CPU on the map's rebuild from {52}-{59} s to {17}-{19} s",
        lambda: [*cpu_range("main", "defaults (ilp, 100/1s)"), *cpu_range("main", "greedy")],
        None,
    )
)


# -- the steady pressure of (0.55, 1)'s first dataset (its startups' stress tables, benchmarks/data) ---

VALIDATION = REPO / "benchmarks/data/engine_validation"
#: the steady window of the engine validation (commit 85ba66c: benchmarks/engine_validation.py)
STEADY_STRAINS = (2.0, 5.0)
DENSE_FRICTIONAL_LONG = [
    VALIDATION / "engine_newton_dt8e-6_phi0.55_mu1",
    VALIDATION / "engine_newton_dt8e-6_phi0.55_mu1_seeds5-8",
]


@cache
def _seed_steady_means(folders: tuple[Path, ...], column: str) -> np.ndarray:
    means = []
    for folder in folders:
        for startup in sorted(Path(folder).glob("seed*/startup")):
            table = pd.read_csv(startup / "stress.csv")
            steady = (table["strain"] >= STEADY_STRAINS[0]) & (table["strain"] <= STEADY_STRAINS[1])
            means.append(table[column][steady].mean())
    return np.array(means)


def steady_means(folders, column: str = "eta_r") -> np.ndarray:
    """Each seed's mean of a stress column over the steady window of its startup, over the seed folders
    of every folder given."""
    return _seed_steady_means(tuple(folders), column)


# -- the map (docs/map.md): each campaign point's committed dataset ------------------------------

MAP = "docs/map.md"
MAP_POINTS = [(phi, mu) for mu in ("0", "0.5", "1") for phi in ("0.40", "0.45", "0.50", "0.53", "0.55")]
MAP_FOLDERS = [f"data/campaign/phi{phi}_mu{mu}" for phi, mu in MAP_POINTS]


def corner_forces() -> dict:
    """The forces config/campaign.yaml gives (0.55, 1)."""
    from suspension_fabric.study.campaign import campaign_points
    from suspension_fabric.study.config import load_config

    return campaign_points(load_config(REPO / "config" / "campaign.yaml"))["phi0.55_mu1"]["forces"]


def pilot_pressure(point: str) -> float:
    """The pilot's Pi at a campaign point (benchmarks/data/campaign_pilot.csv)."""
    pilot = pd.read_csv(REPO / "benchmarks" / "data" / "campaign_pilot.csv").set_index("point")
    return float(pilot.loc[point, "Pi"])


@cache
def map_point(phi: str, mu: str) -> dict[str, float]:
    """A campaign point's steady state, fits and steady-state check from its dataset
    (data/campaign/phi<phi>_mu<mu>), as the map's row (evaluation.state_map.point_row) has them."""
    from suspension_fabric.evaluation.state_map import steady_state_drift

    folder = f"data/campaign/phi{phi}_mu{mu}"
    data, fits = loaded(folder), dataset_fits(folder)
    fabric = data.steady_fabric.set_index("quantity")["mean"]
    stress = data.steady_stress.set_index("quantity")["mean"]
    gw, modified = fits["models"]["gw"]["parameters"], fits["models"]["modified"]["parameters"]
    window = data.config["analysis"]["steady_window"]
    drifts = [
        steady_state_drift(data.fabric_startup, "n12", window, fabric["n12"]),
        steady_state_drift(data.stress_startup, "eta_r", window, stress["eta_r"]),
    ]
    verdicts = [d["verdict"] for d in drifts]
    return {
        "eta_r": stress["eta_r"],
        "Pi": stress["Pi"],
        "Z": fabric["Z"],
        "n12": fabric["n12"],
        "gw_beta": gw["beta"],
        "beta": modified["beta"],
        "A": modified["A"],
        "A_over_beta": modified["A"] / modified["beta"],
        "largest_drift": max(abs(d["mean"]) for d in drifts),
        "eta_r_drift": drifts[1],
        "steady": "steady"
        if verdicts == ["steady", "steady"]
        else "drifting"
        if "drifting" in verdicts
        else "not resolved",
    }


def _bgp(phi: float) -> tuple[float, float]:
    from suspension_fabric.evaluation.state_map import bgp_viscosities

    eta, pressure = bgp_viscosities([phi])
    return float(eta[0]), float(pressure[0])


def _over_bgp_percent(phi: str) -> float:
    return 100 * (map_point(phi, "0.5")["eta_r"] / _bgp(float(phi))[0] - 1)


QUOTES += [
    Quote(
        MAP,
        "G-W beta stays within {9.6}-{11.0} over the whole map (a little larger with friction), the modified beta "
        "within {8.7}-{9.3}, while A grows linearly with phi ({39} at 0.40 to {52} at 0.55), so A/beta goes from "
        "{4.3} to {6.0}",
        lambda: [
            min(map_point(*p)["gw_beta"] for p in MAP_POINTS),
            max(map_point(*p)["gw_beta"] for p in MAP_POINTS),
            min(map_point(*p)["beta"] for p in MAP_POINTS),
            max(map_point(*p)["beta"] for p in MAP_POINTS),
            map_point("0.40", "0")["A"],
            map_point("0.55", "0")["A"],
            min(map_point(*p)["A_over_beta"] for p in MAP_POINTS),
            max(map_point(*p)["A_over_beta"] for p in MAP_POINTS),
        ],
        None,
    ),
    Quote(
        MAP,
        "law of Boyer, Guazzelli and Pouliquen (2011) in Pi ({4.7}, {11.9}, {40.7} against {4.7}, {11.1}, {34.6} at "
        "phi = 0.40, 0.45, 0.50) and lie {12}-{13}% above it in eta_r; closer to jamming, at phi = 0.53 and "
        "0.55, they lie above it in both, and further above as phi grows (eta_r {81.5} and {164} against {68.9} "
        "and {145}, Pi {120} and {285} against {93} and {247})",
        lambda: [
            *(map_point(phi, "0.5")["Pi"] for phi in ("0.40", "0.45", "0.50")),
            *(_bgp(phi)[1] for phi in (0.40, 0.45, 0.50)),
            min(_over_bgp_percent(phi) for phi in ("0.40", "0.45", "0.50")),
            max(_over_bgp_percent(phi) for phi in ("0.40", "0.45", "0.50")),
            *(map_point(phi, "0.5")["eta_r"] for phi in ("0.53", "0.55")),
            *(_bgp(phi)[0] for phi in (0.53, 0.55)),
            *(map_point(phi, "0.5")["Pi"] for phi in ("0.53", "0.55")),
            *(_bgp(phi)[1] for phi in (0.53, 0.55)),
        ],
        None,
    ),
    Quote(
        MAP,
        "frictionless suspensions are far less viscous (eta_r {12.6} against {36} at phi = 0.50, mu = 0.5)",
        lambda: [map_point("0.50", "0")["eta_r"], map_point("0.50", "0.5")["eta_r"]],
        None,
    ),
    Quote(
        MAP,
        "within +-{10}% in the mean at every point but (0.55, 1), where eta_r's second half lies {14}% below its "
        "first in the mean, 95% t-interval over the seeds {-33}% to {+6}%); with 4 seeds the intervals "
        'resolve it as steady (inside +-10%) at {3} points and leave {12} "not resolved"',
        lambda: [
            10 * np.ceil(10 * max(map_point(*p)["largest_drift"] for p in MAP_POINTS if p != ("0.55", "1"))),
            -100 * map_point("0.55", "1")["eta_r_drift"]["mean"],
            100 * map_point("0.55", "1")["eta_r_drift"]["low"],
            100 * map_point("0.55", "1")["eta_r_drift"]["high"],
            sum(map_point(*p)["steady"] == "steady" for p in MAP_POINTS),
            sum(map_point(*p)["steady"] == "not resolved" for p in MAP_POINTS),
        ],
        None,
    ),
]


def _lubrication_pressure(values) -> float:
    """The particle pressure of the lubrication part, -Tr/3, from its diagonal components."""
    return -(values["lubrication_11"] + values["lubrication_22"] + values["lubrication_33"]) / 3.0


def _early_pressures(r: Results, low: float, high: float) -> list[float]:
    """The lubrication pressure and Pi of the seed-mean startup, averaged over the strains [low, high]."""
    rows = r.table("stress_startup_aggregate.csv")
    rows = rows[(rows["strain"] >= low - 1e-9) & (rows["strain"] <= high + 1e-9)]
    means = {c.removesuffix("_mean"): rows[c].mean() for c in rows.columns if c.endswith("_mean")}
    return [_lubrication_pressure(means), means["Pi"]]


def _closure_h12_c12(targets: dict) -> list[float]:
    """H12 = (<nnnn>:E^)_12 and C12 = (<nnnn>:E^_c)_12 of simple shear, <nnnn> the paper's closure
    of the steady fabric (gillissen_wilson.contract_closure, split_strain_rate)."""
    from suspension_fabric.analysis.frames import vec_to_sym
    from suspension_fabric.models import gillissen_wilson

    fabric = vec_to_sym(np.array([targets[c]["mean"] for c in ("n11", "n22", "n33", "n12", "n13", "n23")]))
    grad = np.zeros((3, 3))
    grad[0, 1] = 1.0  # simple shear e1 e2
    _, e_hat, _, e_comp, _ = gillissen_wilson.split_strain_rate(grad)
    return [
        float(gillissen_wilson.contract_closure(e_hat, fabric)[0, 1]),
        float(gillissen_wilson.contract_closure(e_comp, fabric)[0, 1]),
    ]


def _board(r: Results, model: str, mode: str, component: str) -> pd.Series:
    return r.row("leaderboard.csv", model=model, mode=mode, component=component)


def _separate_rates_fitted_to_22() -> dict[str, float]:
    """The separate-rates model's steady fit to <nn>_11, <nn>_22, <nn>_12 of the reference dataset
    instead of <nn>_33 (as models.fabric_models fits it to <nn>_33): its one stable root."""
    from suspension_fabric.models import gillissen_wilson

    targets, phi = dataset_fits("data/reference")["targets"], dataset_fits("data/reference")["phi"]
    wanted = np.array([targets[c]["mean"] for c in ("n11", "n12", "n22")]) / phi

    def rates(beta_e):
        parts = np.stack(gillissen_wilson.shear_steady_parts(np.asarray(beta_e, dtype=float)), axis=-1)
        coefficients = np.linalg.solve(parts[[0, 3], :], wanted[:2])
        return coefficients, parts[1, :] @ coefficients - wanted[2]

    def miss(beta_e):
        return np.array([rates(b)[1] for b in np.atleast_1d(beta_e)]).reshape(np.shape(beta_e))

    (root,) = [
        b for b in gillissen_wilson.roots_on_grid(miss, gillissen_wilson.RATE_GRID) if gillissen_wilson.is_stable(b)
    ]
    (beta_c, a), _ = rates(root)
    return {"beta_e": float(root), "beta_c": float(beta_c), "A": float(a)}


def _n22_over_n33_percent() -> float:
    targets = dataset_fits("data/reference")["targets"]
    return 100 * (targets["n22"]["mean"] / targets["n33"]["mean"] - 1)


def _cells(r: Results) -> dict[str, float]:
    from suspension_fabric.reporting.figures import polar_cell_errors

    return polar_cell_errors(r.table("rotation_aggregate.csv"), r.fits()["targets"]["n12"]["mean"])


def _stress(r: Results, relation: str) -> pd.Series:
    return r.row("stress_leaderboard.csv", relation=relation, quantity="eta_r rotation")


def _fit(r: Results, source: str) -> pd.Series:
    return r.row("stress_relation_fits.csv", source=source)


def _lowest_z(r: Results, theta: float) -> float:
    rows = r.table("rotation_aggregate.csv")
    return float(rows.loc[np.isclose(rows["theta"], theta), "Z_mean"].min())


def _decided_from(transients: pd.DataFrame) -> float:
    """The smallest angle from which every integrated deficit's interval lies above 0."""
    ordered = transients.sort_values("theta")
    above = ordered["deficit_low"].to_numpy() > 0
    first = len(above) - int(np.argmin(above[::-1])) if not above.all() else 0
    return float(ordered["theta"].iloc[first])


def _angles_with(r: Results, claim: str, verdict: str, low: float, high: float) -> list[float]:
    """The first and last angle in [low, high] at which a claim's per-angle verdict is ``verdict``."""
    rows = r.table("claims_per_angle.csv")
    rows = rows[(rows["claim"] == claim) & rows["theta"].between(low, high) & (rows["verdict"] == verdict)]
    return [float(rows["theta"].min()), float(rows["theta"].max())]


def _settled_startup(r: Results, model: str | None) -> float:
    """The strain from which every steady fabric component of the startup stays within 10% of its
    steady value: the simulation's seed mean (model None) or a model's prediction (its own steady
    state)."""
    from suspension_fabric.analysis.tables import TOLERANCE, settle_strain

    fits = r.fits()
    if model is None:
        rows = r.table("startup_aggregate.csv").sort_values("strain")
        curves = {c: rows[f"{c}_mean"] / fits["targets"][c]["mean"] for c in ("n11", "n22", "n33", "n12")}
    else:
        rows = r.table("predictions.csv")
        rows = rows[(rows["model"] == model) & (rows["protocol"] == "startup")].sort_values("strain")
        own = fits["models"][model]["steady_state"]
        curves = {c: rows[c] / own[c] for c in ("n11", "n22", "n33", "n12")}
    strain = rows["strain"].to_numpy()
    return max(settle_strain(strain, curve.to_numpy() - 1.0, TOLERANCE)[0] for curve in curves.values())


# -- the models' right-hand sides on 6-vectors (commit f89f0d6: benchmarks/model_vector_forms.py) -----


@cache
def vector_forms(name: str = "model_vector_forms.csv") -> pd.DataFrame:
    """benchmarks/data/model_vector_forms*.csv (benchmarks/model_vector_forms.py)."""
    return pd.read_csv(REPO / "benchmarks/data" / name)


def curves_ratio(model: str) -> float:
    return vector_forms().set_index("model").loc[model, "curves_ratio"]


QUOTES += [
    Quote(
        "docs/fabric_models.md",
        "make an evaluation of the model's curves {2.8} and {3.5} times cheaper",
        lambda: [curves_ratio("gw_hybrid"), curves_ratio("sparse")],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "took {89.5} s of CPU with the tensor right-hand sides and {42.0} s with the vector forms",
        lambda: list(vector_forms("model_vector_forms_leaderboard.csv")["leaderboard_cpu_s"]),
        None,
    ),
]


@cache
def figure_pdf_cost() -> pd.DataFrame:
    """benchmarks/data/figure_pdf_cost.csv (commit 94e3e9f: benchmarks/figure_pdf_cost.py --save)."""
    return pd.read_csv(REPO / "benchmarks/data/figure_pdf_cost.csv").set_index(["figure", "maps"])


QUOTES.append(
    Quote(
        "BENCHMARKS.md",
        "figures' cells are rasterized at 200 dpi, Fig. 2 in {7.7} s and {0.49} MB instead of {33.5} s and {8.67} MB "
        "as vector paths",
        lambda: [
            figure_pdf_cost().loc[("fig2_rotation", "rasterized"), "cpu_s"],
            figure_pdf_cost().loc[("fig2_rotation", "rasterized"), "pdf_mb"],
            figure_pdf_cost().loc[("fig2_rotation", "vector cells"), "cpu_s"],
            figure_pdf_cost().loc[("fig2_rotation", "vector cells"), "pdf_mb"],
        ],
        None,
    )
)


# -- BENCHMARKS.md's reading of what solver_tol means on several ranks (benchmarks/mpi_accuracy.py) -----


def accuracy_ratios(n: int) -> dict:
    """benchmarks/mpi_accuracy.py's error ratios of every (ranks, preconditioner, tol) at N = n."""
    accuracy = benchmark_script("mpi_accuracy")
    return accuracy.error_ratios(accuracy.read_table(REPO / "benchmarks/data/mpi_scaling" / f"n{n}" / "accuracy.csv"))


def accuracy_ratio(n: int, ranks: int, preconditioner: str, tol: float, key: str) -> list[float]:
    """One setting's geometric-mean error ratio over the default engine's, then its 95% interval."""
    return list(accuracy_ratios(n)[(ranks, preconditioner, tol)][key])


def matched_tol(n: int, ranks: int, preconditioner: str) -> float:
    return benchmark_script("mpi_accuracy").matched_tolerances(accuracy_ratios(n))[(ranks, preconditioner)]


def accuracy_iterations(n: int, ranks: int, preconditioner: str, tol: float) -> float:
    """Mean CG iterations per step of one setting (accuracy_iterations.csv)."""
    return scaling_median(
        f"n{n}/accuracy_iterations.csv", "iterations", ranks=ranks, preconditioner=preconditioner, tol=tol
    )


MPI_ACCURACY_QUOTES = [
    Quote(
        "BENCHMARKS.md",
        "On 2 ranks at the default tol, dilu left {1.56} times the 1-rank velocity error in rms (95% interval "
        "{1.23}-{1.97}) and {1.87} times the largest. Block Jacobi left {1.81} and {1.50} times, on any rank count.",
        lambda: [
            *accuracy_ratio(16000, 2, "dilu", 1e-3, "rms"),
            accuracy_ratio(16000, 2, "dilu", 1e-3, "largest")[0],
            accuracy_ratio(16000, 2, "jacobi", 1e-3, "rms")[0],
            accuracy_ratio(16000, 2, "jacobi", 1e-3, "largest")[0],
        ],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "is {5}e-4 for both preconditioners on 2 ranks. There dilu takes {18.30} CG iterations per step instead of "
        "{15.25}, and block Jacobi {28.25} instead of {24.25}, against {10.40} for the default engine on 1 rank.",
        lambda: [
            1e4 * matched_tol(16000, 2, "dilu"),
            accuracy_iterations(16000, 2, "dilu", matched_tol(16000, 2, "dilu")),
            accuracy_iterations(16000, 2, "dilu", 1e-3),
            accuracy_iterations(16000, 2, "jacobi", matched_tol(16000, 2, "jacobi")),
            accuracy_iterations(16000, 2, "jacobi", 1e-3),
            accuracy_iterations(16000, 1, "dilu", 1e-3),
        ],
        None,
    ),
]
QUOTES += MPI_ACCURACY_QUOTES


def timing_loops(label: str, ranks: int, preconditioner: str) -> pd.Series:
    """benchmarks/mpi_accuracy.py timing: one setting's loop time per round."""
    table = scaling_table(f"n16000/accuracy_timing_{label}.csv")
    chosen = (table["ranks"] == ranks) & (table["preconditioner"] == preconditioner)
    return table[chosen].set_index("repeat")["loop_s"]


def jacobi_wins(labels: tuple[str, ...]) -> list[int]:
    """Over the given timing commands: the rounds block Jacobi was the faster on 2 ranks, and all rounds."""
    ratios = [r for label in labels for r in timing_ratios(label)]
    return [sum(r < 1 for r in ratios), len(ratios)]


def timing_ratios(label: str) -> list[float]:
    """benchmarks/mpi_accuracy.py timing: block Jacobi's 2-rank loop time over dilu's, per round."""
    return list(timing_loops(label, 2, "jacobi") / timing_loops(label, 2, "dilu"))


def timing_speedups(label: str) -> list[float]:
    """benchmarks/mpi_accuracy.py timing: per round, the 1-rank default's loop time over each 2-rank
    preconditioner's (block Jacobi's rounds, then dilu's), then jacobi's 2-rank loop time over dilu's, median."""
    one = timing_loops(label, 1, "dilu")
    by_name = {name: timing_loops(label, 2, name) for name in ("jacobi", "dilu")}
    speedups = [list(one / by_name[name]) for name in ("jacobi", "dilu")]
    return speedups[0] + speedups[1] + [float((by_name["jacobi"] / by_name["dilu"]).median())]


MPI_ACCURACY_QUOTES += [
    Quote(
        "docs/workflow.md",
        "at N = 16000 on 2 ranks tol 1e-3 left {1.56} times the 1-rank velocity error (rms).",
        lambda: [accuracy_ratio(16000, 2, "dilu", 1e-3, "rms")[0]],
        None,
    ),
]
QUOTES += MPI_ACCURACY_QUOTES[3:]


# -- BENCHMARKS.md's calm-phase timing with block Jacobi on 1 rank too, and the model at equal accuracy -------
CALM_TIMINGS = ("20261206f", "20261206g")


def calm_loops(ranks: int, preconditioner: str) -> list[float]:
    """Over both calm timing commands: one setting's loop times."""
    return [loop for label in CALM_TIMINGS for loop in timing_loops(label, ranks, preconditioner)]


def calm_rounds(numerator: tuple[int, str], denominator: tuple[int, str]) -> pd.Series:
    """Over both calm timing commands, per round: one setting's loop time over another's."""
    return pd.concat([timing_loops(label, *numerator) / timing_loops(label, *denominator) for label in CALM_TIMINGS])


def equal_accuracy_model() -> dict:
    """benchmarks/mpi_accuracy.py model --n 16000 --labels 20261206f 20261206g (run from the repository)."""
    with contextlib.chdir(REPO):
        return benchmark_script("mpi_accuracy").equal_accuracy_model(16000, list(CALM_TIMINGS))


def modelled(ranks: int, preconditioner: str, key: str) -> float:
    row = next(
        r for r in equal_accuracy_model()["rows"] if r["ranks"] == ranks and r["preconditioner"] == preconditioner
    )
    return row[key]


CALM_TIMING_QUOTES: list[Quote] = []


ALL_TIMINGS = ("20261206", "20261206e", *CALM_TIMINGS)


def geometric_mean_interval(ratios: pd.Series) -> list[float]:
    """The geometric mean of per-round ratios, the number of rounds, and the 95% t-interval over the rounds."""
    from scipy import stats

    logs = np.log(ratios.to_numpy())
    half = stats.t.ppf(0.975, logs.size - 1) * logs.std(ddof=1) / np.sqrt(logs.size)
    mean = logs.mean()
    return [float(np.exp(mean)), logs.size, float(np.exp(mean - half)), float(np.exp(mean + half))]


def calm_reading() -> list[float]:
    """The reading of the calm timing commands, in the order BENCHMARKS.md quotes it."""
    jacobi = calm_rounds((1, "dilu"), (2, "jacobi"))
    dilu = calm_rounds((1, "dilu"), (2, "dilu"))
    alone = calm_rounds((1, "jacobi"), (1, "dilu"))
    split = calm_rounds((1, "jacobi"), (2, "jacobi"))
    return [
        jacobi.min(),
        jacobi.max(),
        jacobi.size,
        jacobi.median(),
        dilu.min(),
        dilu.max(),
        dilu.median(),
        jacobi_wins(CALM_TIMINGS)[0],
        *jacobi_wins(ALL_TIMINGS),
        alone.median(),
        alone.iloc[0],
        alone.iloc[1:].min(),
        alone.iloc[1:].max(),
        split.min(),
        split.max(),
        split.median(),
        *geometric_mean_interval(split),
        jacobi.median(),
        100 * (alone.median() - 1),
        split.median(),
    ]


CALM_TIMING_QUOTES.append(
    Quote(
        "BENCHMARKS.md",
        "At the 1-rank default's accuracy, block Jacobi on 2 ranks ran {1.39}-{1.55} times as fast (median of the "
        "{6} rounds {1.46}) and dilu {1.20}-{1.36} times ({1.23}). Block Jacobi was the faster on 2 ranks in all {6} "
        "rounds, so in {11} rounds of {12} over the four `timing` commands. On 1 rank it took {1.16} times the "
        "default's time (median; {1.41} in the first round, {1.14}-{1.18} in the other five), and its 2-rank run was "
        "{1.64}-{2.17} times as fast as its 1-rank run (median {1.68}; geometric mean {1.76}, 95% t-interval over the "
        "{6} rounds {1.57}-{1.97}): the distributed solve itself, at the same iterations on 1 and 2 ranks, is about "
        "at the target's efficiency.",
        lambda: calm_reading()[:-3],
        None,
    )
)
QUOTES += CALM_TIMING_QUOTES


def command_medians() -> list[float]:
    """Per timing command and 2-rank preconditioner, the median speed-up over the 1-rank default."""
    return [
        float(np.median(speedups[i : i + 3]))
        for label in ALL_TIMINGS
        for speedups in [timing_speedups(label)]
        for i in (0, 3)
    ]


def same_tol_efficiency(ranks: int) -> float:
    """benchmarks/mpi_scaling.py model --n 16000 (every rank count at the default tol): the efficiency on `ranks`."""
    with contextlib.chdir(REPO):
        rows = benchmark_script("mpi_scaling").same_tol_model(16000)["rows"]
    return next(row["efficiency"] for row in rows if row["ranks"] == ranks)


def model_gap() -> list[float]:
    """The measured 2-rank steps of the calm timing rounds (ms) less the model's, least and largest, then the
    least and largest measured step."""
    steps = {name: [1000 * loop / 1000 for loop in calm_loops(2, name)] for name in ("jacobi", "dilu")}
    gaps = [step - 1000 * modelled(2, name, "step") for name, found in steps.items() for step in found]
    measured = [step for found in steps.values() for step in found]
    return [min(gaps), max(gaps), min(measured), max(measured)]


EQUAL_ACCURACY_MODEL_QUOTES = [
    Quote(
        "docs/workflow.md",
        "on 2 ranks was faster than dilu at the same accuracy in {11} rounds of {12}",
        lambda: jacobi_wins(ALL_TIMINGS),
        None,
    ),
    Quote(
        "docs/workflow.md",
        "At equal accuracy 2 ranks ran {1.1} to {1.5} times as fast as 1, by the host's phase; block Jacobi at "
        "5.0e-4 ran {1.46} times as fast in the calmest phase measured, and a model of 8-64 ranks keeps {0.54} of "
        "the ideal speed-up on 64 ranks with it, against {0.37} with dilu",
        lambda: [
            min(command_medians()),
            max(command_medians()),
            calm_rounds((1, "dilu"), (2, "jacobi")).median(),
            modelled(64, "jacobi", "efficiency"),
            modelled(64, "dilu", "efficiency"),
        ],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "At 2 ranks the model is optimistic: {1.58}x for block Jacobi against the {1.46}x measured, {1.41}x for "
        "dilu against {1.23}x. What it leaves out of the measured 2-rank steps ({1.1} to {4.4} ms of {25.4} to "
        "{31.8})",
        lambda: [
            *equal_accuracy_model()["check"]["jacobi"],
            *equal_accuracy_model()["check"]["dilu"],
            *model_gap(),
        ],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "at equal accuracy block Jacobi keeps {0.74} of the ideal speed-up on 8 ranks and {0.54} on 64, dilu {0.57} "
        "and {0.37}. dilu's matched iterations grow by {2.67} per doubling of the ranks ({18.30} on 2 ranks, "
        "{23.65} on 8), and from {32} ranks on they exceed block Jacobi's, which do not grow at all. The model at "
        "the default tol (`mpi_scaling.py model --n 16000`) gave dilu {0.43} on 64 ranks",
        lambda: [
            modelled(8, "jacobi", "efficiency"),
            modelled(64, "jacobi", "efficiency"),
            modelled(8, "dilu", "efficiency"),
            modelled(64, "dilu", "efficiency"),
            equal_accuracy_model()["growth"]["dilu"],
            accuracy_iterations(16000, 2, "dilu", 5e-4),
            accuracy_iterations(16000, 8, "dilu", 5e-4),
            min(
                r["ranks"]
                for r in equal_accuracy_model()["rows"]
                if r["preconditioner"] == "dilu" and r["iterations"] > modelled(r["ranks"], "jacobi", "iterations")
            ),
            same_tol_efficiency(64),
        ],
        None,
    ),
]
QUOTES += EQUAL_ACCURACY_MODEL_QUOTES


MPI_SUMMARY_QUOTES = [
    Quote(
        "BENCHMARKS.md",
        "| the default engine (dilu) at the same solver_tol, calm host | {1.53} | | at the 1-rank default's accuracy: "
        "block Jacobi at 5e-4, calm host (median of {6} rounds) | {1.46} | | at the 1-rank default's accuracy: dilu "
        "at 5e-4, calm host (median of {6} rounds) | {1.23} | | block Jacobi against itself on 1 rank, the same "
        "solve (median of {6} rounds) | {1.68} |",
        lambda: [
            mpi_speedup(16000),
            calm_rounds((1, "dilu"), (2, "jacobi")).size,
            calm_rounds((1, "dilu"), (2, "jacobi")).median(),
            calm_rounds((1, "dilu"), (2, "dilu")).size,
            calm_rounds((1, "dilu"), (2, "dilu")).median(),
            calm_rounds((1, "jacobi"), (2, "jacobi")).size,
            calm_rounds((1, "jacobi"), (2, "jacobi")).median(),
        ],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "{1.68} times as fast on 2 ranks as on 1 (median of the rounds; geometric mean {1.76}, 95% t-interval over "
        "the rounds {1.57}-{1.97}). What keeps 2 ranks "
        "below 1.7x at equal accuracy is the preconditioner: dilu, the faster on one rank, loses its couplings "
        "across the rank boundary and needs a tighter tol there, and block Jacobi is {16}% slower than dilu on one "
        "rank. Modelled at equal accuracy, block Jacobi keeps {0.54} of the ideal speed-up on 64 ranks and dilu "
        "{0.37}",
        lambda: [
            calm_rounds((1, "jacobi"), (2, "jacobi")).median(),
            *(lambda g: [g[0], g[2], g[3]])(geometric_mean_interval(calm_rounds((1, "jacobi"), (2, "jacobi")))),
            100 * (calm_rounds((1, "jacobi"), (1, "dilu")).median() - 1),
            modelled(64, "jacobi", "efficiency"),
            modelled(64, "dilu", "efficiency"),
        ],
        None,
    ),
]
QUOTES += MPI_SUMMARY_QUOTES


# -- BENCHMARKS.md's generated tables: printed again by their scripts from the committed data --------------


def printed_rows(print_table: Callable[[], None]) -> list[str]:
    """The table rows (lines starting with "|") that a script's function prints, run from the repository."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.chdir(REPO):
        print_table()
    return [line for line in out.getvalue().splitlines() if line.startswith("|")]


GENERATED_TABLES += [
    GeneratedTable(  # mpi_accuracy.py model --n 16000 --labels 20261206f 20261206g
        "BENCHMARKS.md",
        "| ranks P | grid |",
        lambda: printed_rows(lambda: benchmark_script("mpi_accuracy").model(16000, list(CALM_TIMINGS))),
    ),
    GeneratedTable(  # mpi_scaling.py sizes --n 500 4000 16000 (benchmarks/data/mpi_scaling/n*/split.csv)
        "BENCHMARKS.md",
        "| N | ms per step | CG iterations |",
        lambda: printed_rows(lambda: benchmark_script("mpi_scaling").sizes([500, 4000, 16000])),
    ),
    GeneratedTable(  # dataset_cost.py on the reference datasets' run records
        "BENCHMARKS.md",
        "| dataset ",
        lambda: printed_rows(
            lambda: benchmark_script("dataset_cost").main(
                ["data/reference", "data/reference_v1", "data/reference_n2000"]
            )
        ),
    ),
]


# -- BENCHMARKS.md's MPI measurement at N = 16000 (benchmarks/data/mpi_scaling/n16000/measure.csv) ------------


def measure_figures() -> list[float]:
    """The 1-rank and the 2-rank runs of mpi_scaling.py measure: least and largest loop time, CG iterations."""
    table = scaling_table("n16000/measure.csv")
    figures = []
    for ranks in (1, 2):
        rows = table[table["ranks"] == ranks]
        figures += [rows["loop_s"].min(), rows["loop_s"].max(), rows["iterations"].median()]
    return figures


QUOTES += [
    Quote(
        "BENCHMARKS.md",
        "each (1 rank: {42.5}-{42.9} s, {9.90} CG iterations per step; 2 ranks: {27.6}-{28.9} s, {15.35}):",
        measure_figures,
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "Output: speed-up of 2 ranks over 1 (loop time), per pair: {1.55}, {1.48}, {1.53}; median {1.53} "
        "(target >= 1.7)",
        lambda: mpi_speedups("measure.csv"),
        None,
    ),
]


# -- BENCHMARKS.md's campaign costs (benchmarks/dataset_cost.py data/campaign: the points' run records) ---------


@cache
def campaign_costs() -> pd.DataFrame:
    """dataset_cost.py's row of each campaign point, with the point's contact solve."""
    from suspension_fabric.study.dataset import read_dataset

    cost = benchmark_script("dataset_cost")
    rows = []
    for folder in MAP_FOLDERS:
        run = read_dataset(REPO / folder)["config"]["run"]
        rows.append({**cost.dataset_cost(REPO / folder), "solve": run.get("contact_solve", "lagged")})
    table = pd.DataFrame(rows)
    table["point"] = table["dataset"].map(lambda d: Path(d).name)
    return table.set_index("point")


def lagged_costs() -> list[float]:
    """The least and the largest core-hours of the points on the lagged solve (NaN if not the points the
    page names), then their sum."""
    hours = campaign_costs().loc[lambda t: t["solve"] == "lagged", "core_hours"]
    least = hours.min() if hours.idxmin() == "phi0.40_mu0" else np.nan
    largest = hours.max() if hours.idxmax() == "phi0.53_mu0.5" else np.nan
    return [least, largest, hours.sum()]


QUOTES += [
    Quote(
        "BENCHMARKS.md",
        "cost {0.076} (phi0.40_mu0) to {0.945} core-hours (phi0.53_mu0.5), {3.49} together",
        lagged_costs,
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "| phi0.53_mu1 | 3.125e9 | 4e-5 | {0.674} | {0.0808} | | phi0.55_mu0.5 | 3.125e9 | 4e-5 | {0.529} | {0.0635} | "
        "| phi0.55_mu1 | 7.8125e9 | 1.6e-5 | {1.37} | {0.165} | | all fifteen | | | {6.06} | |",
        lambda: [
            *(
                campaign_costs().loc[point, column]
                for point in ("phi0.53_mu1", "phi0.55_mu0.5", "phi0.55_mu1")
                for column in ("core_hours", "core_s_per_particle_strain")
            ),
            campaign_costs()["core_hours"].sum(),
        ],
        None,
    ),
]


# -- BENCHMARKS.md's random kills (benchmarks/chaos.py: benchmarks/data/chaos_rounds.csv) --------------------


def chaos_kills() -> list[int]:
    """The kills that landed, then those of Snakemake, of a LAMMPS run and of an analysis job."""
    rounds = pd.read_csv(REPO / "benchmarks/data/chaos_rounds.csv")
    landed = rounds[rounds["victim"] != "nothing"]
    return [len(landed), *(int((landed["kind"] == kind).sum()) for kind in ("workflow", "lammps", "analysis"))]


QUOTES.append(
    Quote(
        "BENCHMARKS.md",
        "made once, then again while {20} SIGKILLs landed at random (Snakemake {10}, a LAMMPS run {2}, an analysis "
        "job {8}; schedule in",
        chaos_kills,
        None,
    )
)


# -- BENCHMARKS.md's table of the models' right-hand sides (benchmarks/data/model_vector_forms.csv) ----------

VECTOR_FORM_COLUMNS = ["call_tensor_us", "call_vector_us", "call_ratio", "curves_tensor_s", "curves_vector_s"]
VECTOR_FORM_COLUMNS += ["curves_ratio", "max_difference"]


def vector_form_row(model: str, exponent: int) -> list[float]:
    """A model's row of the table, its largest difference in units of 10^-exponent (as the page prints it)."""
    row = vector_forms().set_index("model").loc[model, VECTOR_FORM_COLUMNS].astype(float)
    return [*row.iloc[:-1], 10.0**exponent * row.iloc[-1]]


QUOTES.append(
    Quote(
        "BENCHMARKS.md",
        "| gw_hybrid | {111.3} | {31.4} | {3.54} | {0.163} | {0.058} | {2.8} | {7.2}e-09 | "
        "| sparse | {57.8} | {8.4} | {6.86} | {0.091} | {0.026} | {3.5} | {1.4}e-14 |",
        lambda: vector_form_row("gw_hybrid", 9) + vector_form_row("sparse", 14),
        None,
    )
)


# -- BENCHMARKS.md's engine validations (commit 85ba66c: benchmarks/engine_validation.py) -------------------
# The runs compared with a committed dataset are in git history only: benchmarks/data/engine_validation/
# seed_means.csv keeps what the comparison reads of them (write_seed_means), and the committed datasets
# are read the same way here.

VALIDATION_FABRIC = ("n11", "n22", "n33", "n12", "n13", "n23", "Z")
VALIDATION_STRESS = ("eta_r", "contact_12", "lubrication_12", "N1", "N2", "Pi")
VALIDATION_ANGLES = (0, 45, 90, 135, 180)
#: after each rotation: (table, column) in each strain bin (engine_ladder.BINS; the last one closed at its end)
VALIDATION_TRANSIENTS = (("fabric", "n12"), ("fabric", "n23"), ("stress", "total_12"), ("stress", "total_23"))
VALIDATION_BINS = ((0.0, 0.05), (0.05, 0.1), (0.1, 0.2), (0.2, 0.3), (0.3, 0.5), (0.5, 1.0), (1.0, 2.0))
#: the strains [low, high) after the reversal over which the page reads <nn>'_12's recovery
REVERSAL_WINDOW = (0.2, 0.5)
SEED_MEANS = REPO / "benchmarks/data/engine_validation/seed_means.csv"
#: the seed folders in git history that seed_means.csv keeps: (its name there, commit, folder)
HISTORY_RUNS = [
    (
        "newton_paper",
        "85ba66cd05eefedc91b9e4868d634795f95bde49",
        "benchmarks/data/engine_validation/engine_newton_paper",
    ),
    (
        "newton_paper",
        "85ba66cd05eefedc91b9e4868d634795f95bde49",
        "benchmarks/data/engine_validation/engine_newton_paper_seeds5-8",
    ),
    # the map's first datasets of the points the engine's rule made again (the commit before b71fca33)
    ("first_phi0.53_mu0", "f3502a093a156c0b78fb52797f861b7551ad0bfc", "data/campaign/phi0.53_mu0"),
    ("first_phi0.55_mu0.5", "f3502a093a156c0b78fb52797f861b7551ad0bfc", "data/campaign/phi0.55_mu0.5"),
]


def _window_mean(strain: np.ndarray, values: np.ndarray, low: float, high: float, closed: bool) -> float:
    return float(values[(strain >= low) & ((strain < high) | (closed & (strain <= high)))].mean())


def seed_means(folder: Path) -> pd.DataFrame:
    """Per seed of a folder of seed folders, what engine_validation.py compares: each steady quantity's
    mean over the startup's strain 2-5 (window "2-5"), each transient's mean in each strain bin after
    each rotation, <nn>'_12 over REVERSAL_WINDOW after the reversal, and each run's wall time."""
    rows = []
    for seed_folder in sorted(folder.glob("seed*")):
        seed = int(seed_folder.name.removeprefix("seed"))

        def add(run: str, quantity: str, window: str, value: float, seed=seed) -> None:
            rows.append({"seed": seed, "run": run, "quantity": quantity, "window": window, "value": value})

        for kind, columns in (("fabric", VALIDATION_FABRIC), ("stress", VALIDATION_STRESS)):
            table = pd.read_csv(seed_folder / "startup" / f"{kind}.csv", usecols=["strain", *columns])
            for column in columns:
                value = _window_mean(table["strain"].to_numpy(), table[column].to_numpy(float), *STEADY_STRAINS, True)
                add("startup", column, "2-5", value)
        for angle in VALIDATION_ANGLES:
            run = f"rotation_theta{angle}"
            for kind, column in VALIDATION_TRANSIENTS:
                table = pd.read_csv(seed_folder / run / f"{kind}.csv", usecols=["strain", column])
                strain, values = table["strain"].to_numpy(), table[column].to_numpy(float)
                for k, (low, high) in enumerate(VALIDATION_BINS):
                    add(run, column, f"{low:g}-{high:g}", _window_mean(strain, values, low, high, k == 6))
                if angle == 180 and column == "n12":
                    add(
                        run,
                        column,
                        "{:g}-{:g}".format(*REVERSAL_WINDOW),
                        _window_mean(strain, values, *REVERSAL_WINDOW, False),
                    )
        for record in sorted(seed_folder.glob("*/run.json")):
            add(record.parent.name, "wall_time_s", "run", json.loads(record.read_text())["wall_time_s"])
    return pd.DataFrame(rows)


def write_seed_means() -> None:
    """Writes SEED_MEANS from the seed folders of HISTORY_RUNS, read out of git history (run once; kept)."""
    import subprocess
    import tempfile

    tables = []
    with tempfile.TemporaryDirectory() as scratch:
        for name, commit, folder in HISTORY_RUNS:
            archive = subprocess.run(["git", "archive", commit, folder], cwd=REPO, check=True, capture_output=True)
            subprocess.run(["tar", "-x", "-C", scratch], input=archive.stdout, check=True)
            tables.append(seed_means(Path(scratch) / folder).assign(source=name))
    table = pd.concat(tables, ignore_index=True)
    table[["source", *table.columns[:-1]]].to_csv(SEED_MEANS, index=False, float_format="%.10g")


@cache
def validation_means(source: str) -> pd.DataFrame:
    """seed_means of a committed folder of seed folders (a path), or of runs SEED_MEANS keeps (their name)."""
    if (REPO / source).is_dir():
        return seed_means(REPO / source)
    table = pd.read_csv(SEED_MEANS)
    return table[table["source"] == source].drop(columns="source")


@cache
def _seed_series(source: str) -> dict[tuple[str, str, str], pd.Series]:
    return {
        key: rows.set_index("seed")["value"].sort_index()
        for key, rows in validation_means(source).groupby(["run", "quantity", "window"])
    }


def seed_values(source: str, run: str, quantity: str, window: str) -> pd.Series:
    """Per seed (the index), one quantity's mean in one window of one run."""
    return _seed_series(source)[(run, quantity, window)]


def steady_values(source: str, quantity: str) -> pd.Series:
    return seed_values(source, "startup", quantity, "{:g}-{:g}".format(*STEADY_STRAINS))


def welch_row(study: str, dataset: str, quantity: str) -> list[float]:
    """engine_validation.py's steady row: each side's mean, standard error and seeds, the difference,
    it in percent of the dataset's mean, z and Welch's p."""
    from scipy import stats

    x, y = steady_values(study, quantity).to_numpy(), steady_values(dataset, quantity).to_numpy()
    sems = [v.std(ddof=1) / np.sqrt(len(v)) for v in (x, y)]
    difference = x.mean() - y.mean()
    z = difference / np.hypot(*sems)
    p = stats.ttest_ind(x, y, equal_var=False).pvalue
    return [x.mean(), sems[0], len(x), y.mean(), sems[1], len(y), difference, 100 * difference / abs(y.mean()), z, p]


def bin_zs(study: str, dataset: str) -> np.ndarray:
    """z of each strain bin after each rotation (Welch's, over the seeds of each side)."""
    zs = []
    for angle in VALIDATION_ANGLES:
        for _, column in VALIDATION_TRANSIENTS:
            for low, high in VALIDATION_BINS:
                x, y = (seed_values(s, f"rotation_theta{angle}", column, f"{low:g}-{high:g}") for s in (study, dataset))
                zs.append(
                    (x.mean() - y.mean()) / np.hypot(x.std(ddof=1) / np.sqrt(len(x)), y.std(ddof=1) / np.sqrt(len(y)))
                )
    return np.array(zs)


def paired_interval(study: str, dataset: str, run: str, quantity: str, window: str, level: float = 0.95):
    """Over the seeds both sides ran: the mean of the per-seed differences and its t-interval."""
    from scipy import stats

    x, y = seed_values(study, run, quantity, window), seed_values(dataset, run, quantity, window)
    d = (x - y).dropna().to_numpy()
    half = stats.t.ppf(0.5 + level / 2, len(d) - 1) * d.std(ddof=1) / np.sqrt(len(d))
    return [d.mean(), d.mean() - half, d.mean() + half]


def welch_null(seeds_a: int, seeds_b: int, count: int, draws: int = 20000, level: float = 0.95) -> list[float]:
    """engine_validation.py's Monte Carlo of Welch's z of ``count`` normal quantities (fixed seed): how many
    exceed 2 on average, and the |z| that the largest exceeds in 1 - level of the draws."""
    rng = np.random.default_rng(0)
    a = rng.normal(size=(draws, seeds_a, count))
    b = rng.normal(size=(draws, seeds_b, count))
    z = np.abs(a.mean(axis=1) - b.mean(axis=1)) / np.sqrt(
        a.var(axis=1, ddof=1) / seeds_a + b.var(axis=1, ddof=1) / seeds_b
    )
    return [float((z > 2.0).sum(axis=1).mean()), float(np.quantile(z.max(axis=1), level))]


def sidak_bound(count: int, level: float = 0.95) -> float:
    """|z| that the largest of ``count`` independent standard normals exceeds with 1 - level."""
    from scipy import stats

    return float(stats.norm.ppf(1.0 - (1.0 - level ** (1.0 / count)) / 2.0))


PAPER_STUDY, PAPER_DATASET = "newton_paper", "data/reference"


def paper_point_reading() -> list[float]:
    """The Newton solve at the paper's point against data/reference, in the order the page reads it."""
    zs = np.abs(bin_zs(PAPER_STUDY, PAPER_DATASET))
    fabric = [abs(welch_row(PAPER_STUDY, PAPER_DATASET, c)[6]) for c in VALIDATION_FABRIC if c != "Z"]
    return [
        welch_row(PAPER_STUDY, PAPER_DATASET, "eta_r")[7],
        welch_row(PAPER_STUDY, PAPER_DATASET, "Pi")[7],
        max(fabric),
        len(zs),
        int((zs > 2).sum()),
        0.0455 * len(zs),  # the normal expectation engine_validation.py prints
        zs.max(),
        sidak_bound(len(zs)),
    ]


QUOTES += [
    Quote(
        "BENCHMARKS.md",
        "| Z | {3.4984} +- {0.0056} ({8}) | {3.4994} +- {0.0052} ({16}) | "
        "{-0.0010} ({-0.0}%) | {-0.13} | {0.897} | "
        "| eta_r | {15.3865} +- {0.1801} ({8}) | {15.5348} +- {0.1447} ({16}) | "
        "{-0.1483} ({-1.0}%) | {-0.64} | {0.530} | "
        "| N1 | {-1.4174} +- {0.1891} ({8}) | {-1.2152} +- {0.1075} ({16}) | "
        "{-0.2021} ({-16.6}%) | {-0.93} | {0.372} | "
        "| N2 | {-5.2768} +- {0.1012} ({8}) | {-5.5605} +- {0.0977} ({16}) | "
        "{+0.2837} ({+5.1}%) | {+2.02} | {0.058} | "
        "| Pi | {12.2049} +- {0.2292} ({8}) | {12.2364} +- {0.1846} ({16}) | "
        "{-0.0315} ({-0.3}%) | {-0.11} | {0.916} |",
        lambda: [v for q in ("Z", "eta_r", "N1", "N2", "Pi") for v in welch_row(PAPER_STUDY, PAPER_DATASET, q)],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "The paper's point agrees: eta_r {-1.0}%, Pi {-0.3}%, every fabric component within {0.0025}; {140} transient "
        "bins, {5} with |z| > 2 ({6.4} expected by chance), the largest ({2.74}) inside the Sidak 95% bound ({3.56}).",
        paper_point_reading,
        None,
    ),
]


# the engine's rule against the map's first datasets (benchmarks/configs/engine_rule_points.yaml, now in data/campaign)
RULE_POINTS = {point: (f"data/campaign/{point}", f"first_{point}") for point in ("phi0.53_mu0", "phi0.55_mu0.5")}


def rule_row(point: str) -> list[float]:
    """A point's row: eta_r's paired difference with its 95% t-interval, Welch's p, the bins beyond |z| = 2
    and the largest |z|."""
    study, first = RULE_POINTS[point]
    zs = np.abs(bin_zs(study, first))
    return [
        *paired_interval(study, first, "startup", "eta_r", "2-5"),
        welch_row(study, first, "eta_r")[9],
        int((zs > 2).sum()),
        zs.max(),
    ]


def rule_ratio(point: str) -> float:
    """kn / (eta_f Pi) in units of 1e4 at the rule study's stiffness, Pi the steady pressure of the point's
    dataset in data/campaign (the first one, for a point the rule did not make again)."""
    import yaml

    config = yaml.safe_load((REPO / "benchmarks/configs/engine_rule_points.yaml").read_text())["forces"]
    return config["kn"] / (config["eta_f"] * steady_stress(f"data/campaign/{point}", "Pi")) / 1e4


def solver_reading() -> list[float]:
    """(0.55, 0.5): eta_r's paired change in percent of the first dataset's mean (lowered: positive) with its
    interval, Pi's change, the seeds' eta_r on both sides, the rerun's reversal recovery and both costs."""
    study, first = RULE_POINTS["phi0.55_mu0.5"]
    mean = steady_values(first, "eta_r").mean()
    change, low, high = (100 * v / mean for v in paired_interval(study, first, "startup", "eta_r", "2-5"))
    first_hours = validation_means(first).query("quantity == 'wall_time_s'")["value"].sum() / 3600
    return [
        -change,
        low,
        high,
        -welch_row(study, first, "Pi")[7],
        *steady_values(study, "eta_r"),
        *steady_values(first, "eta_r"),
        *paired_interval(study, first, "rotation_theta180", "n12", "{:g}-{:g}".format(*REVERSAL_WINDOW)),
        campaign_costs().loc["phi0.55_mu0.5", "core_hours"],
        first_hours,
    ]


QUOTES += [
    Quote(
        "BENCHMARKS.md",
        "(0.45, 1) at the ratio {3}e4, which the rule does not take",
        lambda: [rule_ratio("phi0.45_mu1")],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "| phi0.53_mu0 | kn 1.25e8, dt 1e-4 | kn 2.5e8, dt 5e-5 | {-0.02} [{-0.28}, {+0.25}]; {0.97} | {4} | {3.82} | "
        "| phi0.55_mu0.5 | Newton, extrapolated start, local solves, tol 3e-4 | Newton, tol 1e-3 | {-14.5} [{-21.0}, "
        "{-8.0}]; {0.13} | {12} | {4.95} |",
        lambda: rule_row("phi0.53_mu0") + rule_row("phi0.55_mu0.5"),
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "Welch's z of {4} against {4} seeds is heavy-tailed: for {140} independent normal bins {13} are expected "
        "beyond 2 and the largest beyond {7.12} in 5% of draws",
        lambda: [
            *(len(steady_values(s, "eta_r")) for s in RULE_POINTS["phi0.53_mu0"]),
            len(bin_zs(*RULE_POINTS["phi0.53_mu0"])),
            *welch_null(4, 4, len(bin_zs(*RULE_POINTS["phi0.53_mu0"]))),
        ],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "and the reason the rule's ratio lies above {3.1}e4. (0.53, 0), which the rule keeps at the default "
        "stiffness (ratio {3.7}e4), shows none: {+0.0016} [{-0.0040}, {+0.0072}].",
        lambda: [
            rule_ratio("phi0.45_mu1"),
            rule_ratio("phi0.53_mu0"),
            *paired_interval(*RULE_POINTS["phi0.53_mu0"], "rotation_theta180", "n12", "0.2-0.5"),
        ],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "the rule's solve lowers eta_r by {8.1}% (paired [{-11.8}, {-4.5}]%, all 4 packings) and Pi by {9.5}% "
        "against the first dataset; per packing {182}, {160}, {155}, {158} against {193}, {180}, {171}, {169}.",
        lambda: solver_reading()[:12],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "at this point carries a solver uncertainty of about {8}-{10}%.",
        lambda: [solver_reading()[0], solver_reading()[3]],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "later recovery as (0.45, 1), {+0.0090} [{+0.0022}, {+0.0157}] (not investigated). Its cost, {0.529} "
        "against {1.32} core-hours,",
        lambda: solver_reading()[12:],
        None,
    ),
]


# -- LF_DEM's critical-load friction against the project's (benchmarks/lfdem_critical_load.py --save) ------


@cache
def critical_load_runs() -> pd.DataFrame:
    """benchmarks/data/lfdem_critical_load.csv: a row per run, code and quantity."""
    return pd.read_csv(REPO / "benchmarks/data/lfdem_critical_load.csv", dtype={"window": str, "lfdem_dt_max": str})


def critical_load_values(kn: float, window: str, code: str, quantity: str, lfdem_dt_max: str = "own") -> np.ndarray:
    """The runs' values of one quantity at gammadot / gammadot_0 = 0.1, by seed, with LF_DEM's step its
    own or capped at ``lfdem_dt_max``."""
    table = critical_load_runs()
    rows = table[
        np.isclose(table["kn"], kn)
        & np.isclose(table["ratio"], 0.1)
        & (table["window"] == window)
        & (table["lfdem_dt_max"] == lfdem_dt_max)
        & (table["code"] == code)
        & (table["quantity"] == quantity)
    ].sort_values("seed")
    return rows["value"].to_numpy()


def critical_load_numbers() -> dict[str, float]:
    """The numbers docs/thickening.md ("Against LF_DEM") and BENCHMARKS.md quote from the table, by name."""
    eta, frictional, step = "eta_r - 1 - 2.5 phi", "frictional contacts per particle", "strain per step"
    project, peer = critical_load_values(5e7, "1-2", "project", eta), critical_load_values(5e7, "1-2", "LF_DEM", eta)
    difference = project - peer
    interval = t_interval(difference, 0.95)
    return {
        "stiff_lf": critical_load_values(5e9, "0.3-0.5", "LF_DEM", eta)[0],
        "soft_lf_early": critical_load_values(5e7, "0.3-0.5", "LF_DEM", eta)[0],
        "stiff_pr": critical_load_values(5e9, "0.3-0.5", "project", eta)[0],
        "stiff_lf_zf": critical_load_values(5e9, "0.3-0.5", "LF_DEM", frictional)[0],
        "stiff_pr_zf": critical_load_values(5e9, "0.3-0.5", "project", frictional)[0],
        "soft_pr_early": critical_load_values(5e7, "0.3-0.5", "project", eta)[0],
        "n": len(difference),
        "pr_zf": critical_load_values(5e7, "1-2", "project", frictional).mean(),
        "lf_zf": critical_load_values(5e7, "1-2", "LF_DEM", frictional).mean(),
        "pr": project.mean(),
        "pr_se": project.std(ddof=1) / np.sqrt(len(project)),
        "lf": peer.mean(),
        "lf_se": peer.std(ddof=1) / np.sqrt(len(peer)),
        "d": difference.mean(),
        "lo": interval.low,
        "hi": interval.high,
        "step_stiff": 1e5 * critical_load_values(5e9, "0.3-0.5", "LF_DEM", step)[0],
        "step_soft": 1e5 * critical_load_values(5e7, "0.3-0.5", "LF_DEM", step)[0],
        "k9": critical_load_values(1e9, "0.4-0.6", "LF_DEM", eta)[0],
        "k9_pr": critical_load_values(1e9, "0.4-0.6", "project", eta)[0],
        **step_cap_numbers(),
    }


def step_cap_numbers() -> dict[str, float]:
    """The second named test: LF_DEM continued from its strain-0.5 checkpoint at kn = 5e9 with its step
    capped at 2e-6 strain (T) or its own (C), over strain 0.52-0.55; this project's run from rest beside."""
    eta, frictional, step = "eta_r - 1 - 2.5 phi", "frictional contacts per particle", "strain per step"

    def value(code: str, quantity: str, cap: str = "own") -> float:
        return critical_load_values(5e9, "0.52-0.55", code, quantity, cap)[0]

    capped, own = value("LF_DEM", eta, "2e-06"), value("LF_DEM", eta)
    return {
        "cap_T": capped,
        "cap_C": own,
        "cap_ratio": capped / own,
        "cap_step_C": 1e5 * value("LF_DEM", step),
        "cap_step_ratio": value("LF_DEM", step) / value("LF_DEM", step, "2e-06"),
        "cap_zf_T": value("LF_DEM", frictional, "2e-06"),
        "cap_zf_C": value("LF_DEM", frictional),
        "cap_pr": value("project", eta),
        "cap_pr_zf": value("project", frictional),
    }


def critical_load_quote(page: str, passage: str, names: list[str]) -> Quote:
    return Quote(page, passage, lambda: [critical_load_numbers()[name] for name in names], None)


QUOTES += [
    critical_load_quote(
        "docs/thickening.md",
        "With the capped step LF_DEM gives {145.6}, with its own step ({7.8}$\\times10^{-5}$ strain per step "
        "there, {39} times the cap) {33.6}: T is {4.3} times C, each the mean of four snapshots. Contacts above "
        "the critical load: {2.52} per particle capped against {1.64} at its own step (this project: {2.46} over "
        "the same window).",
        ["cap_T", "cap_step_C", "cap_step_ratio", "cap_C", "cap_ratio", "cap_zf_T", "cap_zf_C", "cap_pr_zf"],
    ),
    critical_load_quote(
        "docs/thickening.md",
        "This project's run of the same packing from rest gives {101.5} over strain 0.52-0.55 (two table rows)",
        ["cap_pr"],
    ),
    critical_load_quote(
        "BENCHMARKS.md",
        "one run per arm: {145.6} with the step capped at 2e-6 strain, {33.6} at its own;",
        ["cap_T", "cap_C"],
    ),
    critical_load_quote(
        "docs/thickening.md",
        "**At the flow curves' stiffness LF_DEM falls far behind once friction engages, at its own step.** With $k_n = "
        "5\\times10^9$, on one packing, LF_DEM's $\\eta_r - 1 - 2.5\\phi$ over strain 0.3-0.5 is {30.5}, "
        "against {71.4} for LF_DEM on the same packing at $k_n = 5\\times10^7$ and {89.1} for this project at "
        "$5\\times10^9$, with {1.45} frictional contacts per particle against this project's {2.21}. "
        "Stiffening the spring lowers LF_DEM's value and raises this project's ({64.4} at $5\\times10^7$).",
        ["stiff_lf", "soft_lf_early", "stiff_pr", "stiff_lf_zf", "stiff_pr_zf", "soft_pr_early"],
    ),
    critical_load_quote(
        "docs/thickening.md",
        "**With a spring 100 times softer both codes thicken, LF_DEM about a quarter higher.** With $k_n = "
        "5\\times10^7$ (`benchmarks/configs/lfdem_soft_kn.yaml`), over strain 1-2 of {3} packings, this "
        "project has {3.46} frictional contacts per particle and LF_DEM {3.51}; $\\eta_r - 1 - 2.5\\phi$ is "
        "{227} ± {10} here and {280} ± {11} in LF_DEM (mean ± standard error over the packings), the "
        "difference per packing {-53} with a 95% t-interval of [{-59}, {-47}]. That paired interval assumes "
        "the codes' run-to-run scatter cancels in the differences, which nothing measured shows: the codes "
        "follow different trajectories and no run was repeated. Why LF_DEM is higher is not known: at constant "
        'friction the codes agree on the viscosity ([Benchmarks, "Against the peer code LF_DEM"]'
        "(benchmarks.md#against-the-peer-code-lf_dem)), and the "
        "soft spring's overlaps of several percent of a diameter, where dashpots and the regularised "
        "lubrication of overlapping pairs carry more of the stress, are a candidate.",
        ["n", "pr_zf", "lf_zf", "pr", "pr_se", "lf", "lf_se", "d", "lo", "hi"],
    ),
    critical_load_quote(
        "docs/thickening.md",
        "**A test named before its run refuted the simplest account.** LF_DEM's step is set by the largest "
        "displacement (at most $10^{-3}$ radii), not by the springs: over strain 0.3-0.5, "
        "{6.5}$\\times10^{-5}$ strain at $k_n = 5\\times10^9$ and {13.3}$\\times10^{-5}$ at $5\\times10^7$.",
        ["step_stiff", "step_soft"],
    ),
    critical_load_quote(
        "docs/thickening.md",
        "LF_DEM gives {159.4} there, and this project {132}: by the named test the step limit as the whole "
        "cause is refuted (one packing, one run), and at $10^9$ LF_DEM is "
        "again above this project, as at $5\\times10^7$.",
        ["k9", "k9_pr"],
    ),
    critical_load_quote(
        "BENCHMARKS.md",
        "At the flow curves' kn = 5e9 LF_DEM falls far behind once friction engages: eta_r - 1 - 2.5 phi "
        "{30.5} over strain 0.3-0.5 of one packing, against {71.4} for LF_DEM at kn = 5e7 on the same "
        "packing and {89.1} for the project at 5e9. At kn = 5e7 both thicken, LF_DEM about a quarter higher: "
        "{227} against {280} over strain 1-2, difference per packing {-53} [{-59}, {-47}] (95% t-interval "
        "over {3} packings). LF_DEM's explicit step ({6.5}e-5 strain at 5e9) is longer than the stiff "
        "tangential springs' relaxation. A first test named before its run (LF_DEM low at kn = 1e9 too) was "
        "refuted ({159.4} over strain 0.4-0.6);",
        ["stiff_lf", "soft_lf_early", "stiff_pr", "pr", "lf", "d", "lo", "hi", "n", "step_stiff", "k9"],
    ),
]


# -- docs/physics.md's reading of the solve's work against the step (benchmarks/bench_engine.py work) -----------


def solve_work_numbers() -> list[float]:
    """benchmarks/data/solve_work.csv in the order the page quotes it."""
    table = pd.read_csv(REPO / "benchmarks/data/solve_work.csv")
    row = {(solve, dt): r for solve, dt, r in zip(table["contact_solve"], table["dt"], table.itertuples())}
    lagged, newton, longest = row["lagged", 1e-4], row["newton", 5e-4], row["newton", 2e-3]
    return [
        lagged.iterations_per_strain,
        newton.iterations_per_strain,
        longest.iterations_per_strain,
        lagged.iterations_per_step,
        newton.iterations_per_step,
        longest.iterations_per_step,
        newton.max_overlap,
        longest.max_overlap,
        lagged.max_overlap,
    ]


QUOTES.append(
    Quote(
        "docs/physics.md",
        "At N = 1000 at the paper's point, a steady shear continued by 0.5 strain, the CG iterations per unit "
        "strain hardly fall with the step: {55910} for the lagged solve at dt = 1e-4, {47866} for the Newton "
        "solve at 5e-4 and {46204} at 2e-3, twenty times the lagged step (the lagged point also differs in its "
        "solve). The iterations per step (all Newton passes summed; how much is more passes and how much a "
        "harder solve is not separated) grow in proportion to the step ({5.6}, {23.9} and {92.4}).",
        lambda: solve_work_numbers()[:6],
        None,
    ),
)
QUOTES.append(
    Quote(
        "docs/physics.md",
        "The Newton solve's largest overlap (the largest of frames every 0.05 strain) grows in proportion to "
        "the step as well ({0.0065} d at 5e-4, {0.0254} d at 2e-3; the lagged solve's {0.0015} d),",
        lambda: solve_work_numbers()[6:],
        None,
    )
)


# -- BENCHMARKS.md's fuzz tests: the cases tests/package/test_fuzz.py asks for --------------------------------


@cache
def fuzz_counts() -> dict:
    """tests/package/test_fuzz.py's examples per target (CASES), its tests (one per parameter set) and, per
    target, its properties (one per parameter set)."""
    import inspect
    import math
    from collections import Counter

    spec = importlib.util.spec_from_file_location("fuzz_cases", REPO / "tests/package/test_fuzz.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    try:
        spec.loader.exec_module(module)
    finally:
        del sys.modules[spec.name]
    tests, properties = 0, Counter()
    for name, test in vars(module).items():
        if name.startswith("test_") and callable(test):
            marks = [mark for mark in getattr(test, "pytestmark", []) if mark.name == "parametrize"]
            cases = math.prod(len(mark.args[1]) for mark in marks)
            tests += cases
            target = re.search(r'@fuzz\("([^"]+)"', inspect.getsource(test))
            if target:
                properties[target.group(1)] += cases
    return {"examples": module.CASES, "extreme": len(module.EXTREME_CASES), "tests": tests, "properties": properties}


QUOTES += [
    Quote(
        "BENCHMARKS.md",
        "derandomized; {132} tests in",
        lambda: [fuzz_counts()["tests"]],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "Cases per target: config mutations {300}, sections as text {120}, NaN {100}, extreme numbers {238}",
        lambda: [
            *(fuzz_counts()["examples"][name] for name in ("config mutations", "config sections as text")),
            fuzz_counts()["examples"]["config NaN"],
            fuzz_counts()["extreme"],
        ],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "(exhaustive); file corruption {40} per (file, kind), {86} pairs; dataset run files {100}; frames {300} per "
        "property ({5}); model {300} per property ({5}); model rotations {150} per property and model ({4}); fabric "
        "models {150} per property and model ({7}).",
        lambda: [
            fuzz_counts()["examples"]["file corruption"],
            fuzz_counts()["properties"]["file corruption"],
            fuzz_counts()["examples"]["dataset run files"],
            *(
                figure
                for name in ("frames", "model", "model rotations", "fabric models")
                for figure in (fuzz_counts()["examples"][name], fuzz_counts()["properties"][name])
            ),
        ],
        None,
    ),
]


# -- BENCHMARKS.md's speed against LF_DEM (benchmarks/peer_speed.py report, benchmarks/data/peer_speed.csv) -----


def peer_ratio(point: str, n: int, engine: str) -> float:
    """LF_DEM's time per unit strain over the project's, at ``point`` with N = ``n`` and the project's ``engine``."""
    table = pd.read_csv(REPO / "benchmarks/data/peer_speed.csv")
    rows = table[(table["point"] == point) & (table["n"] == n) & (table["engine"] == engine)]
    if len(rows) != 1:
        raise LookupError(f"peer_speed.csv: {len(rows)} rows of {point}, N = {n}, {engine}")
    return float(rows["ratio"].iloc[0])


GENERATED_TABLES.append(
    GeneratedTable(
        "BENCHMARKS.md",
        "| point | N | kn | project engine |",
        lambda: printed_rows(lambda: benchmark_script("peer_speed").main(["report"])),
    )
)
QUOTES.append(
    Quote(
        "BENCHMARKS.md",
        "**At the paper's point the project is {70} times faster per unit strain**; at the dense point (0.50, "
        "0.5) {44} times with the lagged contact solve (its step falls with kn) and **{100} times** with the "
        "Newton solve at dt = 0.24 tau.",
        lambda: [
            peer_ratio("phi0.45_mu0.5", 500, "lagged dt 0.0001"),
            peer_ratio("phi0.50_mu0.5", 500, "lagged dt 2.5e-05"),
            peer_ratio("phi0.50_mu0.5", 500, "newton dt 0.00025"),
        ],
        None,
    )
)


# -- BENCHMARKS.md's costs of the thickening datasets (benchmarks/dataset_cost.py on their run records) ---------


@cache
def thickening_costs(name: str) -> pd.DataFrame:
    """dataset_cost.py's rows of data/<name>, one per point, with phi as a column."""
    script = benchmark_script("dataset_cost")
    with contextlib.chdir(REPO):
        return pd.DataFrame([script.dataset_cost(folder) for folder in script.folders([Path("data") / name])])


def cost_range(name: str, phi: float | None = None) -> list[float]:
    """The smallest and largest core-hours of a point of data/<name> (at ``phi``), then the same of the
    core-seconds per particle per strain."""
    table = thickening_costs(name)
    if phi is not None:
        table = table[np.isclose(table["phi"], phi)]
    hours, per_strain = table["core_hours"], table["core_s_per_particle_strain"]
    return [hours.min(), hours.max(), per_strain.min(), per_strain.max()]


def total_hours(name: str) -> float:
    return thickening_costs(name)["core_hours"].sum()


def rotation_costs() -> list[float]:
    table = thickening_costs("thickening_rotation").sort_values("dataset")  # stress 0.0106 before 1.157
    low, high = table.iloc[0], table.iloc[1]
    return [
        low["core_hours"],
        low["core_s_per_particle_strain"],
        high["core_hours"],
        high["core_s_per_particle_strain"],
        total_hours("thickening_rotation"),
    ]


QUOTES += [
    Quote(
        "BENCHMARKS.md",
        "at phi = 0.50 (kn = 1.25e9, dt = 1e-4) {0.0457} to {0.095} core-hours from gammadot/gammadot_0 = 0.003 to 1 "
        "({0.0164} to {0.0342} core-s per particle per strain); at phi = 0.54 (kn = 5e9, dt = 2.5e-5) {0.126} to "
        "{0.291} ({0.0454} to {0.105}); at phi = 0.56 (kn = 2e10, dt = 6.25e-6) {0.446} to {0.869} for the rates "
        "0.003 to 1 ({0.16} to {0.313}; beside other jobs); all: {6.64} core-hours.",
        lambda: [
            *(figure for phi in (0.50, 0.54, 0.56) for figure in cost_range("thickening", phi)),
            total_hours("thickening"),
        ],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "unthickened (stress 0.0106; 8 seeds, 32 runs, 80 strain) {0.57} core-hours, {0.0513} core-s per particle "
        "per strain; thickened (stress 1.157) {1.07} and {0.0959}; all: {1.64} core-hours.",
        rotation_costs,
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "{0.471} to {0.947} core-hours per stress from 0.01 to 0.5 ({0.17} to {0.341} core-s per particle per "
        "strain); all eight stresses: {5.05} core-hours.",
        lambda: [*cost_range("thickening_stress"), total_hours("thickening_stress")],
        None,
    ),
    Quote(
        "BENCHMARKS.md",
        "{0.666} to {0.958} per stress, {2.34} core-hours.",
        lambda: [*cost_range("thickening_stress_fresh")[:2], total_hours("thickening_stress_fresh")],
        None,
    ),
]

"""The results the README and the docs quote, written as Markdown fragments from a study's tables.

The docs include the fragments the reference study writes (``docs/generated/``), and the README
holds the headline verbatim between marker comments, so that no quoted number is typed by hand:
the reference rebuild's test compares each committed fragment with the one the workflow makes.

- [`fits_paragraph`][suspension_fabric.reporting.summary_fragments.fits_paragraph]: the fitted
  parameters (jackknife errors over seeds) and the steady fabric and stress (standard errors from
  the scatter of the seed means).
- [`choices_table`][suspension_fabric.reporting.summary_fragments.choices_table]: the claims'
  statistics under each analysis choice and comparison dataset.
- [`verdict_table`][suspension_fabric.reporting.summary_fragments.verdict_table]: each claim of the
  paper, its decision statistic and its verdict on the study's data and on each comparison dataset.
- [`headline_paragraph`][suspension_fabric.reporting.summary_fragments.headline_paragraph]: the
  README's summary: fits, verdicts, the best stress relation against G-W's.
"""

from __future__ import annotations

import pandas as pd

from suspension_fabric.models.fabric_models import load_model
from suspension_fabric.reporting.html_tables import format_interval
from suspension_fabric.reporting.verdicts_page import seeds_text

FABRIC_COMPONENTS = ("n11", "n22", "n33", "n12", "n13", "n23")
STRESS_QUANTITIES = ("eta_r", "N1", "N2", "Pi")
# the claims the headline names, grouped as the paper states them
SHEAR_ROTATION_CLAIMS = ("C1", "C2", "C3", "C4", "C5", "C6")


def _estimate(value: float, error: float) -> str:
    """value ± error with the error to two significant digits and the value to the same place."""
    if not error > 0:
        return f"{value:.4g}"
    digits = max(0, 1 - int(f"{error:e}".split("e")[1]))
    return f"{value:.{digits}f} ± {error:.{digits}f}"


def _paper(key: str) -> dict:
    return load_model(key).published or {}


def fits_paragraph(fits: dict, steady: pd.DataFrame, stress_steady: pd.DataFrame) -> str:
    """The fits and the steady state of one study: ``fits`` as in fits.json, ``steady`` and
    ``stress_steady`` the steady-state tables (tables/steady_state.csv, stress_steady_state.csv),
    quoted with the standard errors of the seed means."""
    gw, modified = fits["models"]["gw"], fits["models"]["modified"]
    paper_gw, paper_mod = _paper("gw"), _paper("modified")
    window = "-".join(f"{s:g}" for s in fits["steady_window"])
    seeds = fits["n_seeds"]
    table = pd.concat([steady, stress_steady]).set_index("quantity")
    names = {**{c: f"<nn>_{c[1:]}" for c in FABRIC_COMPONENTS}, "Z": "Z", **{q: q for q in STRESS_QUANTITIES}}
    state = ", ".join(
        f"{name} = {_estimate(table.loc[q, 'mean'], table.loc[q, 'sem_between_seeds'])}"
        for q, name in names.items()
        if q in table.index
    )
    return (
        f"Fitted parameters (seed-mean steady state over strain {window}; errors from a jackknife over the "
        f"{seeds} seeds of the whole fit): G-W beta = {_estimate(gw['parameters']['beta'], gw['errors']['beta'])} "
        f"(paper {paper_gw.get('beta', 'n/a')}); modified beta = "
        f"{_estimate(modified['parameters']['beta'], modified['errors']['beta'])}, A = "
        f"{_estimate(modified['parameters']['A'], modified['errors']['A'])} (paper {paper_mod.get('beta', 'n/a')}, "
        f"{paper_mod.get('A', 'n/a')}). Steady state: {state} (standard errors from the scatter of the {seeds} "
        "seed means).\n"
    )


def choices_table(choices: pd.DataFrame) -> str:
    """tables/verdict_choices.csv as a Markdown table: a row per choice or dataset, a column per
    claim, each cell ``T [interval] verdict`` (the verdict bold when decided)."""
    claims = list(dict.fromkeys(choices["claim"]))
    lines = ["| choice | " + " | ".join(claims) + " |", "|:---|" + ":---|" * len(claims)]
    for choice, rows in choices.groupby("choice", sort=False):
        by_claim = rows.set_index("claim")
        cells = []
        for claim in claims:
            if claim not in by_claim.index:
                cells.append("")
                continue
            row = by_claim.loc[claim]
            verdict = row["verdict"] if row["verdict"] == "undecided" else f"**{row['verdict']}**"
            cells.append(f"{format_interval(row['mean'], row['low'], row['high'])} {verdict}")
        lines.append(f"| {choice} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _cell_text(text) -> str:
    """A text for a Markdown table's cell: its pipes escaped (``|theta|``)."""
    return str(text).replace("|", "&#124;")


def verdict_table(choices: pd.DataFrame, label: str, datasets: list[str]) -> str:
    """tables/verdict_choices.csv as the verdict on each claim: a row per claim (the paper's text
    and the decision statistic T, ref the reference model and chal the challenger), a column for
    the study's own data under the primary choices (headed ``label``) and one per comparison
    dataset of ``datasets`` (the choice names of verdicts.comparisons, headed with their seeds),
    each cell ``T [interval] verdict`` with, when undecided, the seeds that would decide it."""
    columns = {"primary": label}
    for name in datasets:
        rows = choices[choices["choice"] == name]
        if len(rows):
            columns[name] = f"{name}, {int(rows['n_seeds'].max())} seeds"
    claims = choices[choices["choice"] == "primary"].set_index("claim")
    lines = [
        "| | claim of the paper | T (> 0: as the paper says) | " + " | ".join(columns.values()) + " |",
        "|---|---|---|" + "---|" * len(columns),
    ]
    for claim, row in claims.iterrows():
        cells = []
        for name in columns:
            mine = choices[(choices["choice"] == name) & (choices["claim"] == claim)]
            if not len(mine):
                cells.append("")
                continue
            r = mine.iloc[0]
            if r["verdict"] == "undecided":
                verdict = f"undecided ({seeds_text(r['seeds_needed'])} seeds would decide)"
            else:
                verdict = f"**{r['verdict']}**"
            cells.append(f"{format_interval(r['mean'], r['low'], r['high'])} {verdict}")
        lines.append(
            f"| {claim} | {_cell_text(row['text'])} | {_cell_text(row['statistic'])} | " + " | ".join(cells) + " |"
        )
    return "\n".join(lines) + "\n"


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"


def _claims_with(verdicts: pd.DataFrame, verdict: str) -> list[str]:
    rows = verdicts[verdicts["claim"].isin(SHEAR_ROTATION_CLAIMS) & (verdicts["verdict"] == verdict)]
    return list(rows["claim"])


def headline_paragraph(fits: dict, verdicts: pd.DataFrame, stress_board: pd.DataFrame, label: str) -> str:
    """The README's summary of one study (``label`` names it, e.g. "reference v2: N = 1000, 16 seeds")."""
    gw, modified = fits["models"]["gw"], fits["models"]["modified"]
    paper_gw, paper_mod = _paper("gw"), _paper("modified")
    decided = {v: _claims_with(verdicts, v) for v in ("confirmed", "refuted", "undecided")}
    parts = [
        f"What the data say, in short ({label}): G-W beta = "
        f"{_estimate(gw['parameters']['beta'], gw['errors']['beta'])}, modified beta = "
        f"{_estimate(modified['parameters']['beta'], modified['errors']['beta'])}, A = "
        f"{_estimate(modified['parameters']['A'], modified['errors']['A'])} (± one jackknife standard error over "
        f"seeds; paper: {paper_gw.get('beta')}; {paper_mod.get('beta')}, {paper_mod.get('A')})."
    ]
    listed = [f"{_and(decided[v])} {'is' if len(decided[v]) == 1 else 'are'} {v}" for v in decided if decided[v]]
    if listed:
        parts.append(f"Of the paper's shear-rotation claims, {'; '.join(listed)}.")
    held_out = stress_board[stress_board["quantity"] == "eta_r rotation"].dropna(subset=["held_out_mse"])
    if len(held_out) > 1 and "gw" in set(held_out["relation"]):
        best = held_out.loc[held_out["held_out_mse"].idxmin()]
        reference = held_out[held_out["relation"] == "gw"]["held_out_mse"].min()
        if best["relation"] != "gw":
            gain = 1.0 - best["held_out_mse"] / reference
            parts.append(
                f"Of the stress relations, “{best['label']}” ({best['mode']} fit) predicts the viscosity after a "
                f"rotation best: on angles its fit did not see (the same seeds), its mean square error is {gain:.0%} "
                "smaller than that of the G-W relation."
            )
    parts.append("Details, numbers and their intervals: the docs.")
    return " ".join(parts) + "\n"

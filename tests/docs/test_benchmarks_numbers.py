"""Every result number in BENCHMARKS.md is tied to a table by a test (issue #63).

A number of the page (prose, tables, a script's printed output; not dates, nor the commands, paths and
commits of its code) is tied when it lies inside a registered passage of the page (tests/quoted_numbers.py,
``QUOTES``) or in a table that a script prints again from the committed data (``GENERATED_TABLES``,
compared in tests/docs/test_quoted_numbers.py). Any other number must be a setting or an input the
allowlist names (``SETTINGS``) or a result with no committed table to tie it to (``UNTIED``, which
may only shrink): a result typed into the page without a tie fails here.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from quoted_numbers import GENERATED_TABLES, QUOTES, REPO, passage_text

PAGE = "BENCHMARKS.md"

# A number standing alone: not part of a name (phi0.45_mu0.5, N1, <nn>'_12, a commit such as 4e6495e,
# an exponent's digits, a version 6.170.15); "x" or "%" may follow it.
_NUMBER = re.compile(r"(?<![\w.'])(?<![A-Za-z_]-)[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?(?=x\b|%|[^\w.]|\.(?!\d)|$)")

#: Settings and inputs, not results: (section, or None for any; a pattern of the line; why). A number
#: inside a match is not a result.
SETTINGS: list[tuple[str | None, str, str]] = [
    (None, r"\b(?:N|kn|dt|phi|mu|tol|solver_tol)(?: = | )\d[\d.e+-]*", "a setting, named"),
    (None, r"\(0\.\d+, \d(?:\.\d+)?\)", "a state point (phi, mu)"),
    (None, r"\b\d+(?:-\d+)? (?:seeds|packings|states|rounds|ranks?|idle cores|cores)\b(?: against 1)?", "the runs"),
    (None, r"\bSeed \d+ of\b", "the packing's seed"),
    (
        "Shear thickening: critical-load friction",
        r"\d+ runs, \d+\b|seeds \d+-\d+ at [\d., ]+|gammadot_0 = 0\.1 \(|windows? [\d.-]+(?: and [\d.-]+)?|at 5e9\b",
        "the runs, stresses and strain windows",
    ),
    (None, r"\bon \d+ (?:and on \d+ ranks|rank)|\bmedians of \d+|\bnice \d+", "ranks, rounds, a priority"),
    (None, r"\b(?:to )?strain \d[\d.]*(?:-\d[\d.]*)?|\b[\d.]+ strain\b|\(\d+ steps\)", "the strain run"),
    (None, r"\| the target of engine III \| [\d.]+ \|", "a target the issues name"),
    (None, r"95%|\bz > 2\b|at most 1\b|window \d-\d|\b140 bins\b|\b6-vectors", "a criterion, a name"),
    (None, r"\d+x the reference's step \(dt = 5e-4 = [\d.]+ tau\)|at 1e-4\)", "the steps compared"),
    ("The campaign, per point", r"to 1\.25e9, dt = 1e-4 to 1e-5|1 / kn", "the engines' range"),
]

#: Results with no committed table to tie them to, left for their owners: (section, pattern, why).
#: A table committed for one turns it into a quote or a generated table, out of this list.
UNTIED: list[tuple[str | None, str, str]] = [
    ("Benchmarks", r"2-core|10-30%", "the machine's drift: no record"),
    # scripts that print their results but save no table
    ("Fabric models", r".*", "bench_models.py"),
    ("Fabric analysis", r".*", "bench_fabric.py"),
    ("Engine speed", r".*", "bench_engine.py measure; the default study's wall time"),
    ("Against the peer code LF_DEM", r".*", "lfdem_comparison.py"),
    ("The fault suite: bad input and faults, counted by how they end", r".*", "fault_suite.py"),
    ("The rebuilds under two floating-point configurations", r".*", "float_configs.py"),
    ("Pair stresslets against force dipoles", r".*", "stresslet_vs_dipole.py"),
    # edited on another branch now: to tie when it lands
    # runs whose records are not kept
    ("The cost per atom against N", r"~20% slow", "the slow run"),
    ("What the datasets cost", r"1\.32 and 1\.48 core-hours \(seeds 1-8, 9-16\)", "the remade runs"),
    ("The engine's own choices against the map's datasets", r"\| phi0\.45_mu1 \|.*", "(0.45, 1) by the rule"),
    (
        "The engine's own choices against the map's datasets",
        r"recovers later.*|^ *\+0\.0229\].*|.*the 140 bins",
        "ibid.",
    ),
    ("The engine's own choices against the map's datasets", r"only; [\d, ]+\)", "the run at solver_tol 1e-4"),
    ("The workflow's own cost", r"\d+ s\b|\d+ jobs", "the rebuilds' wall times"),
    ("Random kills", r"\d+ of \d+ result files|in \d+ files", "chaos.py keeps only the kills"),
    ("Fuzz tests: cases per target", r"in \d+ s on one core", "the run's time"),
]


@dataclass(frozen=True)
class Number:
    line: int  # 1-based
    section: str
    text: str  # the line
    column: int  # where the number starts in the line
    end: int  # where it ends in the line
    start: int  # where it starts in the page

    def __str__(self) -> str:
        return f"{PAGE}:{self.line} ({self.section}): {self.text[self.column : self.end]} in {self.text.strip()!r}"


def _blank(match: re.Match) -> str:
    return re.sub(r"[^\n]", " ", match.group(0))


def visible_text(text: str) -> str:
    """The page with its dates, its indented code and its inline code (a span may run over a line
    break) blanked; a fenced block's content, a script's printed output, stays."""
    text = re.sub(r"(?m)^(?:    .*|```.*)$", _blank, text)
    text = re.sub(r"`[^`]*`", _blank, text)
    return re.sub(r"\b\d{4}-\d{2}-\d{2}\b", _blank, text)


def page_numbers(text: str) -> list[Number]:
    """Every number of the page outside headings, code and dates."""
    numbers, section, offset = [], "", 0
    lines = zip(text.splitlines(keepends=True), visible_text(text).splitlines(keepends=True))
    for number, (line, visible) in enumerate(lines, start=1):
        if line.startswith("#"):
            section = line.strip("# \n")
        else:
            for match in _NUMBER.finditer(visible):
                numbers.append(Number(number, section, line, match.start(), match.end(), offset + match.start()))
        offset += len(line)
    return numbers


def flat_positions(text: str) -> tuple[str, list[int]]:
    """The text with each run of whitespace one space (as quoted_numbers compares passages), and
    each character's place in it."""
    flat, where = [], []
    for char in text:
        if char.isspace():
            if flat and flat[-1] != " ":
                flat.append(" ")
            where.append(len(flat) - 1)
        else:
            where.append(len(flat))
            flat.append(char)
    return "".join(flat), where


def quoted_spans(flat: str) -> list[tuple[int, int]]:
    """Where the page's registered passages are in the flattened page."""
    spans = []
    for quote in QUOTES:
        if quote.page == PAGE:
            passage = re.sub(r"\s+", " ", passage_text(quote)).strip()
            spans += [(m.start(), m.end()) for m in re.finditer(re.escape(passage), flat)]
    return spans


def generated_lines(text: str) -> set[int]:
    """The line numbers of the page's generated tables (head to last row)."""
    lines, found = text.splitlines(), set()
    for table in GENERATED_TABLES:
        first = next((k for k, line in enumerate(lines) if line.startswith(table.head)), None)
        if table.page != PAGE or first is None:
            continue
        last = first
        while last + 1 < len(lines) and lines[last + 1].startswith("|"):
            last += 1
        found |= set(range(first + 1, last + 2))
    return found


def allowed(number: Number, entries) -> bool:
    """Whether an entry of its section covers the number."""
    return any(
        match.start() <= number.column and number.end <= match.end()
        for section, pattern, _ in entries
        if section in (None, number.section)
        for match in re.finditer(pattern, number.text)
    )


def classified(text: str) -> list[tuple[Number, str]]:
    """Each number of the page with what covers it: "quoted", "generated", "setting", "untied" or ""."""
    flat, where = flat_positions(text)
    spans, generated = quoted_spans(flat), generated_lines(text)
    found = []
    for number in page_numbers(text):
        if any(start <= where[number.start] < end for start, end in spans):
            found.append((number, "quoted"))
        elif number.line in generated:
            found.append((number, "generated"))
        elif allowed(number, SETTINGS):
            found.append((number, "setting"))
        else:
            found.append((number, "untied" if allowed(number, UNTIED) else ""))
    return found


def test_every_result_number_of_benchmarks_is_tied():
    left = [str(number) for number, cover in classified((REPO / PAGE).read_text()) if not cover]
    assert not left, f"{len(left)} numbers neither tied nor allowed:\n" + "\n".join(left)


def test_every_allowlist_entry_still_covers_a_number():
    """An entry whose number has gone or been tied goes too."""
    numbers = [number for number, cover in classified((REPO / PAGE).read_text()) if cover in ("setting", "untied")]
    stale = [entry for entry in SETTINGS + UNTIED if not any(allowed(number, [entry]) for number in numbers)]
    assert not stale, stale


def test_an_untied_result_is_caught():
    """A result typed into a page without a tie fails; a setting, a date or code does not."""
    page = "## A section\n\nThe run (N = 500, 2026-12-07, `--seed 7`) took 12.5 s.\n"
    assert [(n.text[n.column : n.end], cover) for n, cover in classified(page)] == [("500", "setting"), ("12.5", "")]

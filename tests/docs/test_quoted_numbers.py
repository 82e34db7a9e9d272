"""The result numbers typed in the docs' prose (tests/quoted_numbers.py) are still where the
registry says: each registered passage is in its page, and the numbers read from the committed
datasets alone (their records, sizes and steady states) are the data's, at the precision printed.
The numbers of a rebuilt study are compared with its tables inside its rebuild test
(tests/workflow/test_reference.py)."""

import re

import pytest

import quoted_numbers
from quoted_numbers import (
    GENERATED_TABLES,
    QUOTES,
    REPO,
    Quote,
    fragment_problems,
    passage_problems,
    printed,
    value_problems,
)


def test_every_quoted_passage_is_in_its_page():
    problems = passage_problems(QUOTES)
    assert not problems, "\n".join(problems)


def test_the_numbers_quoted_from_the_committed_datasets_are_theirs():
    problems = value_problems([q for q in QUOTES if q.study is None], {})
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("table", GENERATED_TABLES, ids=lambda table: f"{table.page} {table.head}")
def test_each_generated_table_is_what_its_script_prints_now(table):
    """Each row of the page's table (its head too) is a row the script prints from the committed data
    now, to a unit in the last digit."""
    lines = (REPO / table.page).read_text().splitlines()
    first = next(k for k, line in enumerate(lines) if line.startswith(table.head))
    last = first
    while last + 1 < len(lines) and lines[last + 1].startswith("|"):
        last += 1
    page_rows = [lines[first], *lines[first + 2 : last + 1]]  # the head and the rows, not the delimiter
    made = [re.sub(r"\s+", " ", row) for row in table.rows()]
    problems = [row for row in page_rows if not any(not fragment_problems(m, re.sub(r"\s+", " ", row)) for m in made)]
    assert not problems, "no row the script prints now matches:\n" + "\n".join(problems)


def test_every_quote_reads_a_known_study():
    assert {q.study for q in QUOTES} <= {None, "reference", "default_reference"}


@pytest.mark.parametrize(
    "value, like, text",
    [
        (0.0262, "0.026", "0.026"),
        (0.04809, "+0.048", "+0.048"),
        (-0.0004, "0.00", "0.00"),  # no "-0.00"
        (60.04, "60", "60"),
        (-4.557, "-4.6", "-4.6"),
    ],
)
def test_a_value_is_printed_as_the_page_prints_it(value, like, text):
    assert printed(value, like) == text


def test_a_drifted_passage_or_a_changed_value_is_caught(tmp_path, monkeypatch):
    """A typed number edited in the page no longer matches its passage; a value that changes in
    the data no longer rounds to the typed number."""
    page = tmp_path / "page.md"
    page.write_text("The deficit is 0.073 [0.024,\n0.122] at 90 degrees.\n")
    monkeypatch.setattr(quoted_numbers, "REPO", tmp_path)
    quote = Quote("page.md", "The deficit is {0.073} [{0.024}, {0.122}] at 90", lambda: [0.0728, 0.0236, 0.1220], None)
    assert passage_problems([quote]) == [] and value_problems([quote], {}) == []
    page.write_text("The deficit is 0.074 [0.024, 0.122] at 90 degrees.\n")
    assert passage_problems([quote])
    moved = Quote("page.md", quote.passage, lambda: [0.0728, 0.0236, 0.1231], None)
    assert value_problems([moved], {})

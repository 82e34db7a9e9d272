"""The docs say only what was checked, cite it where a referee can check it, and describe the work
as it stands.

Every page of docs/ (the Markdown the site is built from, with the files it includes, such as
BENCHMARKS.md and config/README.md; not docs/generated, which the workflow writes) is read for three
kinds of text:

- a mark of an unchecked statement ("[M]", "from memory", "not verified"): a statement is checked
  against its source and cited, or removed;
- a citation through an aggregator site (arxiver, awesomepapers, arxiv-vanity, ouci.dntb.gov.ua)
  instead of the publisher's or arXiv's record;
- the history of the work ("Until November ...", "earlier versions", "the former default study",
  "the points were made again", "the models added since", "before the engine change"): the commit
  messages hold it.
"""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"

#: What each rule finds, by the rule's name.
RULES = {
    "unchecked statement": re.compile(r"\[M\]|(?i:from memory|not verified)"),
    "aggregator citation": re.compile(r"arxiver|awesomepapers|arxiv-vanity|ouci\.dntb", re.I),
    "history of the work": re.compile(
        r"until november|earlier versions|the former\b|made again|first made|written here on|added since"
        r"|before the (?:[\w'-]+ ){0,3}change\b",
        re.I,
    ),
}
#: A file a page includes (pymdownx.snippets, paths from the repository's root).
_INCLUDE = re.compile(r'^--8<-- "([^"]+)"\s*$', re.M)
#: The pages of the site (docs/*.md, not docs/generated/).
PAGES = sorted(page.stem for page in DOCS.glob("*.md"))
#: Known failures whose fix is in a page these tests' author may not edit; strict, so the marker
#: goes as soon as the page is fixed. (page, rule): the text to fix.
KNOWN: dict[tuple[str, str], str] = {}


def findings(text: str, rule: str) -> list[str]:
    """Each line of ``text`` that ``rule`` finds, as "line number: line"."""
    return [
        f"{number}: {line.strip()[:160]}"
        for number, line in enumerate(text.splitlines(), start=1)
        if RULES[rule].search(line)
    ]


def _cases() -> list:
    cases = []
    for page in PAGES:
        for rule in RULES:
            marks = ()
            if (page, rule) in KNOWN:
                marks = pytest.mark.xfail(strict=True, reason=f"docs/{page}.md: {KNOWN[page, rule]}")
            cases.append(pytest.param(page, rule, marks=marks, id=f"{page}-{rule.replace(' ', '_')}"))
    return cases


def sources(page: str) -> list[Path]:
    """The page's file and the files it includes, but not the fragments of docs/generated."""
    path = DOCS / f"{page}.md"
    included = [REPO / name for name in _INCLUDE.findall(path.read_text()) if not name.startswith("docs/generated/")]
    return [path, *included]


@pytest.mark.parametrize("page, rule", _cases())
def test_page_has_no(page, rule):
    found = [
        f"{source.relative_to(REPO)}:{line}" for source in sources(page) for line in findings(source.read_text(), rule)
    ]
    assert not found, f"docs/{page}.md, {rule}:\n" + "\n".join(found)


def test_the_included_files_are_read():
    assert sources("configuration") == [DOCS / "configuration.md", REPO / "config" / "README.md"]
    assert REPO / "BENCHMARKS.md" in sources("benchmarks")
    assert sources("results") == [DOCS / "results.md"]


def test_the_pages_are_read():
    assert "gw_stress_relation" in PAGES and "api" in PAGES
    assert not any(page.startswith("generated") for page in PAGES)


@pytest.mark.parametrize(
    "line, rule",
    [
        ("Batchelor-Green's 5.2-7.6 phi^2 [M], since", "unchecked statement"),
        ("from memory of the literature", "unchecked statement"),
        ("**Not verified** (the full text was not consulted)", "unchecked statement"),
        ("([S]: abstract on awesomepapers.org)", "aggregator citation"),
        ("the arXiv number from the arxiver listing", "aggregator citation"),
        ("([S] for title and authors: arxiv-vanity 1707.01828)", "aggregator citation"),
        ("| [S] (ouci.dntb.gov.ua record) |", "aggregator citation"),
        ("Until November 2026 the modules sat side by side", "history of the work"),
        ("overshoot values of earlier versions stay", "history of the work"),
        ("- `data/default`: the tables of the former default study", "history of the work"),
        ("the runs of `config/paper.yaml` were made again with the same seeds", "history of the work"),
        ("than the pilots' hand settings the map was first made with", "history of the work"),
        ("The test of it was written here on 2026-12-07", "history of the work"),
        ("(the models added since, G-W with the hybrid closure)", "history of the work"),
        ("The N = 500 study (the default study before the engine change)", "history of the work"),
        ("measured before the solver's default change", "history of the work"),
    ],
)
def test_each_rule_finds_its_text(line, rule):
    page = f"A checked sentence.\n{line}\nAnother one.\n"
    assert findings(page, rule) == [f"2: {line}"]
    assert all(not findings(page, other) for other in RULES if other != rule)


def test_ordinary_text_passes():
    page = (
        "A matrix [m] of masses, verified against the data; the model of 2025 (arXiv:2506.05222).\n"
        "The tables after it are rebuilt, identical; the change of direction before the rotation.\n"
    )
    assert all(not findings(page, rule) for rule in RULES)

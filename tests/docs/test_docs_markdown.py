"""The Markdown of the pages (docs/*.md and the files they include, not docs/generated) says what a
reader of the site needs:

- every table row has at most as many cells as its header: Python-Markdown drops the cells past the
  header's without a warning, so a bare ``|`` in a cell's text cuts the cell short;
- a section of another page is named by a link to it, not as quoted text or a file path;
- the layout of the workflow page names every folder of the package, and only paths that exist.
"""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"
#: The pages of the site, by file stem.
PAGES = sorted(page.stem for page in DOCS.glob("*.md"))

_FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
#: A table's delimiter row: dashes (with optional colons) between pipes.
_DELIMITER = re.compile(r"^ {0,3}\|?\s*:?-+:?\s*(?:\|\s*:?-+:?\s*)*\|?\s*$")
#: A line that includes a file (pymdownx.snippets); the workflow's fragments are not checked here.
_SNIPPET = re.compile(r'^--8<-- "([^"]+)"\s*$')
_GENERATED = "docs/generated/"


def source_lines(path: Path):
    """(where, line) of a Markdown file outside fenced code, with the files it includes (but the
    workflow's fragments) read in their place."""
    fence = None
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        opening = _FENCE.match(line)
        if fence:
            if opening and opening.group(1)[0] == fence[0] and len(opening.group(1)) >= len(fence):
                fence = None
            continue
        if opening:
            fence = opening.group(1)
            continue
        snippet = _SNIPPET.match(line)
        if snippet and not snippet.group(1).startswith(_GENERATED):
            yield from source_lines(REPO / snippet.group(1))
            continue
        yield f"{path.relative_to(REPO)}:{number}", line


def table_cells(row: str) -> list[str]:
    """The cells of a table row as Python-Markdown splits it: at each pipe that is neither escaped
    (``\\|``) nor inside a code span."""
    row = row.strip().removeprefix("|")
    cells, cell, i = [], "", 0
    while i < len(row):
        if row[i] == "\\" and i + 1 < len(row):
            cell, i = cell + row[i : i + 2], i + 2
        elif row[i] == "`":
            ticks = re.match(r"`+", row[i:]).group(0)
            closing = re.compile(rf"(?<!`){ticks}(?!`)").search(row, i + len(ticks))
            end = closing.end() if closing else i + len(ticks)
            cell, i = cell + row[i:end], end
        elif row[i] == "|":
            cells.append(cell)
            cell, i = "", i + 1
        else:
            cell, i = cell + row[i], i + 1
    if cell.strip() or not cells:
        cells.append(cell)
    return cells


def wide_rows(lines: list[tuple[str, str]]) -> list[str]:
    """Each table row with more cells than its table's header, as "where: count and row"."""
    found, header = [], None
    for k, (where, line) in enumerate(lines):
        if header is not None:
            if not line.strip() or "|" not in line:
                header = None
            elif len(table_cells(line)) > header:
                found.append(f"{where}: {len(table_cells(line))} cells, header {header}: {line.strip()[:120]}")
        elif (
            "|" in line
            and not line.startswith("    ")
            and k + 1 < len(lines)
            and "|" in lines[k + 1][1]
            and _DELIMITER.match(lines[k + 1][1])
        ):
            header = len(table_cells(line))
    return found


@pytest.mark.parametrize("page", PAGES)
def test_table_rows_fit_their_header(page):
    """No row of a table has more cells than its header (a bare ``|`` in a cell's text: write
    ``\\|``, or put it in a code span)."""
    assert wide_rows(list(source_lines(DOCS / f"{page}.md"))) == []


def test_tables_are_found():
    tables = 0
    for page in PAGES:
        lines = [line for _, line in source_lines(DOCS / f"{page}.md")]
        tables += sum("|" in line and _DELIMITER.match(after) is not None for line, after in zip(lines, lines[1:]))
    assert tables > 20


@pytest.mark.parametrize(
    ("row", "cells"),
    [
        ("| a | b |", 2),
        ("| `x.csv` | rms and max |model - simulation| per angle |", 4),
        (r"| `x.csv` | rms and max \|model - simulation\| per angle |", 2),
        ("| `a|b` | ``c`|`d`` |", 2),
        ("a | b", 2),
    ],
)
def test_cells_are_split_as_python_markdown_splits_them(row, cells):
    assert len(table_cells(row)) == cells


def test_a_bare_pipe_in_a_cell_is_caught():
    lines = [("x:1", "| output | content |"), ("x:2", "|---|---|"), ("x:3", "| `e.csv` | rms and max |a - b| / |c| |")]
    assert len(wide_rows(lines)) == 1
    assert wide_rows(lines[:2] + [("x:3", r"| `e.csv` | rms and max \|a - b\| / \|c\| |")]) == []


# --- Sections of other pages are links -------------------------------------------------------

#: Known failures whose fix is in a page these tests' author may not edit; strict, so the marker
#: goes as soon as the page is fixed. page: the text to fix.
KNOWN: dict[str, str] = {}
_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\([^)]*\)")
_CODE_SPAN = re.compile(r"(`+).+?\1", re.S)
_HEADING = re.compile(r"^#{1,6}\s+(.+?)\s*(?:\{[^}]*\})?\s*$", re.M)
_PAGE_PATH = re.compile(r"\bdocs/(\w+)\.md\b")


def _prose(page: str) -> str:
    """A page's own Markdown without fenced code, code spans and links (the files it includes are
    read on GitHub too, where a link to a page of the site would not work)."""
    text = "\n".join(line for where, line in source_lines(DOCS / f"{page}.md") if where.startswith("docs/"))
    return _LINK.sub("", _CODE_SPAN.sub("", text))


def _headings(page: str) -> set[str]:
    return set(_HEADING.findall("\n".join(line for _, line in source_lines(DOCS / f"{page}.md"))))


def unlinked(prose: str, own: set[str]) -> list[str]:
    """Each page that ``prose`` names by its path (docs/physics.md) and each section of another
    page it names as quoted text; ``own``: the sections of its own page."""
    found = [f"docs/{m.group(1)}.md" for m in _PAGE_PATH.finditer(prose) if m.group(1) in PAGES]
    for other in PAGES:
        for title in sorted(_headings(other) - own):
            if re.search(rf"[\"“]{re.escape(title)}[\"”]", prose):
                found.append(f'"{title}" ({other})')
    return found


@pytest.mark.parametrize(
    "page",
    [
        pytest.param(page, marks=pytest.mark.xfail(strict=True, reason=KNOWN[page])) if page in KNOWN else page
        for page in PAGES
    ],
)
def test_sections_of_other_pages_are_linked(page):
    """A section of another page is a link to its anchor ([Physics, "How the engine's defaults were
    chosen"](physics.md#how-the-engines-defaults-were-chosen)), not its title in quotes or the page's
    path, which a browser cannot follow."""
    assert unlinked(_prose(page), _headings(page)) == []


def test_an_unlinked_section_is_caught():
    named = 'costs 0.012 core-s (docs/physics.md, "How the engine\'s defaults were chosen").'
    linked = (
        'costs ([Physics, "How the engine\'s defaults were chosen"](physics.md#how-the-engines-defaults-were-chosen)).'
    )
    assert unlinked(named, set()) == ["docs/physics.md", '"How the engine\'s defaults were chosen" (physics)']
    assert unlinked(_LINK.sub("", linked), set()) == []


# --- The workflow page's layout --------------------------------------------------------------

_LAYOUT_ENTRY = re.compile(r"^(?: {4}|\t)( *)(\S+)")


def layout_paths() -> set[str]:
    """The paths the layout block of docs/workflow.md names, each with its parent folders (an
    entry indented under a folder is inside it)."""
    text = (DOCS / "workflow.md").read_text()
    block = text[text.index("## Layout") :].split("\n\n", 2)[1]
    paths, parents = set(), []
    for line in block.splitlines():
        entry = _LAYOUT_ENTRY.match(line)
        indent, name = len(entry.group(1)), entry.group(2)
        parents = [(level, folder) for level, folder in parents if level < indent]
        path = "".join(folder for _, folder in parents) + name
        parts = path.rstrip("/").split("/")
        paths |= {"/".join(parts[: k + 1]) for k in range(len(parts))}
        if name.endswith("/"):
            parents.append((indent, name))
    return paths


def test_the_layout_names_every_folder_of_the_package():
    """Every folder of src/suspension_fabric/ is in the layout of docs/workflow.md."""
    package = REPO / "src" / "suspension_fabric"
    folders = {
        str(folder.relative_to(REPO))
        for folder in package.rglob("*")
        if folder.is_dir() and "__pycache__" not in folder.parts and any(folder.iterdir())
    }
    named = layout_paths()
    assert "src/suspension_fabric/evaluation" in named
    assert folders - named == set()


def test_the_layout_names_only_paths_that_exist():
    missing = [path for path in layout_paths() if not any(REPO.glob(path))]
    assert missing == []

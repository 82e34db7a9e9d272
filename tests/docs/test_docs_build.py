"""The documentation site builds with warnings as errors (mkdocs --strict: broken links, missing
pages, API reference from the docstrings, BENCHMARKS.md included), so docs that rot fail CI.

The site is built once per session (the ``site`` fixture, shared with tests/docs/test_api_docs.py) and
its HTML checked: the equations, LaTeX in the Markdown and the docstrings, are rendered to MathML
at build time (docs/hooks/mathml.py), the site loads nothing from outside itself (no script,
stylesheet or web font), and every page shows what its Markdown meant: lists as lists, brackets
as written, every image it names, and links where it names another page."""

import html
import importlib.util
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest
from filelock import FileLock

from workflow_helpers import session_folder

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"

#: Pages with display equations, and the labelled equations each must show (anchor, tag).
EQUATION_PAGES = {
    "fabric_models": [("eq-rates", "(1)"), ("eq-closure-linear", "(2)"), ("eq-stress-relation", "(8)")],
    "gw_stress_relation": [("eq-closure", "(2)"), ("eq-rotated-stress", "(6)"), ("eq-prediction", "(13)")],
    "physics": [("eq-rotary", "(1)")],
    "verdict_statistics": [("eq-t-interval", "(2)"), ("eq-dmse", "(6)")],
    "campaign": [("eq-bgp", "(1)")],
    "api": [],
}
#: Modules whose docstrings carry their central equation in LaTeX (rendered on the API page).
EQUATION_MODULES = (
    "suspension_fabric.models.gillissen_wilson",
    "suspension_fabric.models.fabric_models",
    "suspension_fabric.models.closures",
    "suspension_fabric.models.sparse_fabric",
    "suspension_fabric.models.stress_relations",
    "suspension_fabric.analysis.fabric",
    "suspension_fabric.analysis.stress",
)
_DISPLAY = re.compile(r"\$\$(.+?)\$\$", re.S)
_CODE = re.compile(r"<pre\b.*?</pre>|<code\b.*?</code>", re.S)
_CODE_BLOCK = re.compile(r"<pre\b.*?</pre>", re.S)
_OUTSIDE = re.compile(r"""<(?:script|link|img|iframe)\b[^>]*\b(?:src|href)=["']?(?:https?:)?//""", re.I)
#: The built site, shared by the docs tests of one session.
_BUILT: dict[str, Path] = {}


def build_site(tmp_path_factory) -> Path:
    """The site, built strictly once per test session (tests/docs/test_api_docs.py reads it too;
    under pytest-xdist the first worker to ask builds it where every worker finds it, and the
    others wait for it). No test changes it."""
    if "site" not in _BUILT:
        folder = session_folder(tmp_path_factory)
        with FileLock(folder / "docs_site.lock"):
            if not (folder / "docs_site").is_dir():
                _build(folder / "docs_site.part").rename(folder / "docs_site")
        _BUILT["site"] = folder / "docs_site"
    return _BUILT["site"]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site, built strictly (once per session, see build_site)."""
    return build_site(tmp_path_factory)


def _build(out: Path) -> Path:
    mkdocs = Path(sys.executable).with_name("mkdocs")
    result = subprocess.run(
        [str(mkdocs), "build", "--strict", "-d", str(out)],  # not --quiet: it hides the warnings --strict counts
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
        env={"NO_MKDOCS_2_WARNING": "1", "PATH": "/usr/bin:/bin"},
    )
    assert result.returncode == 0, result.stderr[-3000:]
    return out


def _page(site: Path, name: str) -> str:
    return (site / name / "index.html").read_text()


def _mathml_hook():
    spec = importlib.util.spec_from_file_location("mathml_hook", DOCS / "hooks" / "mathml.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_docs_build_strict(site):
    api = _page(site, "api")
    assert "suspension_fabric.models.stress_relations" in api and "with_lubrication_stress" in api
    assert "Pair stresslets against force dipoles" in _page(site, "benchmarks")
    assert "&lt;nn&gt;" in _page(site, "fabric_models")  # ASCII <nn> in prose survives as text


@pytest.mark.parametrize("name", sorted(EQUATION_PAGES))
def test_equations_are_mathml(site, name):
    page = _page(site, name)
    text = _CODE.sub("", page)  # code may show a dollar sign as written
    assert "<math" in page and 'display="block"' in page
    assert "$$" not in text and "\\(" not in text and "\\[" not in text, "math left unrendered"
    assert 'class="arithmatex"' not in page
    for anchor, tag in EQUATION_PAGES[name]:
        equation = rf'<div class="equation" id="{anchor}">(?:(?!</div>).)*</math>'
        equation += r'<span class="equation-tag">([^<]*)</span>'
        match = re.search(equation, page, re.S)
        assert match and match.group(1) == tag, f"{name}: equation #{anchor} with tag {tag}"
    # a tensor bracket of a docstring or page is text, not an (invisible) HTML tag
    assert not re.search(r"<n+[>_'\s0-9^]", page)


def test_site_loads_nothing_from_outside(site):
    """No script, stylesheet, font or image from another host (Material loads Google fonts unless
    theme.font is false)."""
    pages = sorted(site.rglob("*.html"))
    assert len(pages) > 10
    for page in pages:
        found = _OUTSIDE.findall(page.read_text())
        assert not found, f"{page.relative_to(site)} loads {found} from outside the site"
    for stylesheet in site.rglob("*.css"):
        assert not re.search(r"""(?:@import|url\()\s*["']?(?:https?:)?//""", stylesheet.read_text()), stylesheet


def _display_equations():
    for page in sorted(DOCS.glob("*.md")):
        for latex in _DISPLAY.findall(page.read_text()):
            yield f"docs/{page.name}", latex
    for name in EQUATION_MODULES:
        module = importlib.import_module(name)
        docs = [module.__doc__] + [getattr(obj, "__doc__", None) for obj in vars(module).values() if callable(obj)]
        for doc in filter(None, docs):
            for latex in _DISPLAY.findall(doc):
                yield name, latex


def test_display_equations_convert():
    """Every display equation of the pages and the docstrings converts to MathML that browsers
    render (no unknown command, no alignment MathML Core drops)."""
    hook = _mathml_hook()
    equations = list(_display_equations())
    assert len(equations) > 40
    for source, latex in equations:
        assert hook.problems(latex) == [], f"{source}: {latex.strip()[:120]}"
        assert "<math" in hook.to_mathml(hook.split_label(latex)[0], display=True)
    sources = {source for source, _ in equations}
    assert set(EQUATION_MODULES) <= sources, set(EQUATION_MODULES) - sources


# --- Pages a reader can use: what the Markdown meant is what the page shows ---------------------

#: Every page of the site, by its folder in the built site ("" for the home page).
PAGES = sorted("" if page.stem == "index" else page.stem for page in DOCS.glob("*.md"))
#: A list item that did not become one: a paragraph line starting with a list marker.
_LIST_LINE = re.compile(r"^[ \t]*(?:[-*]|\d+\.)[ \t]+\S", re.M)
#: A docs page named as a file in a code span, where a link to the page belongs.
_PAGE_AS_CODE = re.compile(r"<code>(?:docs/)?(\w+)\.md(?:#[^<]*)?</code>")
#: Files outside docs/ that are pages of the site (included whole): a link to the page belongs.
_PAGE_SOURCES = {"config/README.md": "configuration", "BENCHMARKS.md": "benchmarks"}
#: The elements the pages are made of: HTML, and the SVG of the theme's icons and the MathML of the
#: equations. Any other name is text the browser swallowed as a tag (`<account>` of a command that
#: did not render as code).
_HTML_ELEMENTS = set(
    "html head body title meta link script style noscript base main header footer nav article aside section "
    "h1 h2 h3 h4 h5 h6 p div span a em strong b i u s small sub sup code pre kbd samp var mark q cite abbr "
    "br hr wbr img picture source figure figcaption ul ol li dl dt dd table caption colgroup col thead "
    "tbody tfoot tr th td blockquote details summary form input label button select option textarea "
    "template time dfn del ins iframe video audio canvas object embed".split()
)
_ELEMENTS = _HTML_ELEMENTS | set(
    "svg path g circle rect line polyline polygon ellipse defs use symbol desc clippath lineargradient "
    "math semantics annotation annotation-xml mrow mi mn mo ms mtext mspace mfrac msqrt mroot mstyle merror "
    "mpadded mphantom menclose msub msup msubsup munder mover munderover mmultiscripts mprescripts none "
    "mtable mtr mtd mlabeledtr maligngroup malignmark".split()
)
#: An HTML tag shown as text (&lt;br&gt;, &lt;/p&gt;, &lt;img src=...): markup escaped by mistake. A
#: tensor bracket (&lt;nn&gt;), a comparison (&lt; 0, &lt;= 1) or a placeholder (&lt;account&gt;)
#: is text.
_ESCAPED_TAG = re.compile(
    r"&lt;/?(?:" + "|".join(sorted(_HTML_ELEMENTS, key=len, reverse=True)) + r")(?=[\s/>]|&gt;)", re.I
)


class _Reading(HTMLParser):
    """What a reader gets of a page: the text of each paragraph (a <br> as a line break), the
    raw text outside code, math, script and style (entities kept as written), every element's
    name and every image's source."""

    _HIDDEN = ("code", "pre", "math", "script", "style", "kbd", "samp")

    def __init__(self):
        super().__init__(convert_charrefs=False)
        self.paragraphs: list[str] = []
        self.text: list[str] = []
        self.elements: set[str] = set()
        self.images: list[str] = []
        self._paragraph: list[str] | None = None
        self._hidden = 0

    def handle_starttag(self, tag, attrs):
        self.elements.add(tag)
        if tag == "img":
            self.images.append(dict(attrs).get("src") or "")
        elif tag == "br" and self._paragraph is not None:
            self._paragraph.append("\n")
        elif tag == "p":
            self._paragraph = []
        elif tag in self._HIDDEN:
            self._hidden += 1

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)

    def handle_endtag(self, tag):
        if tag == "p" and self._paragraph is not None:
            self.paragraphs.append("".join(self._paragraph))
            self._paragraph = None
        elif tag in self._HIDDEN:
            self._hidden = max(self._hidden - 1, 0)

    def handle_data(self, data):
        if self._paragraph is not None:
            self._paragraph.append(data)
        if not self._hidden:
            self.text.append(data)

    def handle_entityref(self, name):
        self.handle_data(f"&{name};")

    def handle_charref(self, name):
        self.handle_data(f"&#{name};")


def _reading(site: Path, name: str) -> _Reading:
    reading = _Reading()
    reading.feed(_page(site, name))
    reading.close()
    return reading


#: Known failures whose fix is in a file these tests' author may not edit; strict, so the marker
#: goes as soon as the source is fixed. (rule, page): the fix.


@pytest.mark.parametrize("name", PAGES)
def test_lists_render_as_lists(site, name):
    """No paragraph holds a line that starts with a list marker: a list written without the blank
    line before it, or indented 2 spaces under an item, runs into the paragraph (Python-Markdown)."""
    for paragraph in _reading(site, name).paragraphs:
        assert not _LIST_LINE.search(paragraph), f"{name or 'index'}: a list ran into a paragraph: {paragraph[:300]!r}"


@pytest.mark.parametrize("name", PAGES)
def test_brackets_render_as_written(site, name):
    """Angle brackets show as written: no text swallowed as an unknown tag (a placeholder <account>
    outside code), and no escaped bracket of markup shown as text (&lt;div) outside code and math."""
    reading = _reading(site, name)
    unknown = reading.elements - _ELEMENTS
    assert not unknown, f"{name or 'index'}: text swallowed as HTML tags: {sorted(unknown)}"
    text = "".join(reading.text)
    escaped = [text[max(m.start() - 40, 0) : m.end() + 40] for m in _ESCAPED_TAG.finditer(text)]
    escaped += [text[max(m.start() - 40, 0) : m.end() + 40] for m in re.finditer(r"&amp;(?:lt|gt|amp);", text)]
    assert not escaped, f"{name or 'index'}: markup shown as text: {escaped}"


@pytest.mark.parametrize("name", PAGES)
def test_images_exist(site, name):
    """Every image a page shows is a file of the built site."""
    page = site / name / "index.html"
    for source in _reading(site, name).images:
        assert not re.match(r"[a-z]+:", source), f"{name or 'index'}: image from outside the site: {source}"
        assert (page.parent / source.split("#")[0]).resolve().is_file(), f"{name or 'index'}: no image {source}"


def test_map_page_shows_its_figures(site):
    """The map page shows the map figures (docs/figures/map_*.png, copied from the map study's
    results/map/figures/), not their paths."""
    from suspension_fabric.reporting.map_figures import MAP_FIGURES

    shown = {Path(source).name for source in _reading(site, "map").images}
    assert {f"{figure}.png" for figure in MAP_FIGURES} <= shown, shown


@pytest.mark.parametrize("name", PAGES)
def test_pages_are_linked_not_named(site, name):
    """A docs page is named by a link to it, not as a file in backticks (`docs/campaign.md`)."""
    pages = {"index" if page == "" else page for page in PAGES}
    prose = _CODE_BLOCK.sub("", _page(site, name))
    named = [m.group(0) for m in _PAGE_AS_CODE.finditer(prose) if m.group(1) in pages]
    named += [f"<code>{source}</code>" for source in _PAGE_SOURCES if f"<code>{source}</code>" in prose]
    assert not named, f"{name or 'index'}: pages named as files, not linked: {named}"


def _article(site: Path, name: str) -> str:
    """A page's own content, without the theme's navigation."""
    return re.search(r"<article\b.*?</article>", _page(site, name), re.S).group(0)


def _links(site: Path, name: str) -> set[str]:
    return set(re.findall(r'<a\b[^>]*\bhref="([^"]*)"', _article(site, name)))


def test_home_page_lists_every_page_and_states_the_headline(site):
    """The home page links every page of the site and states the main result with the generated
    headline (docs/generated/headline.md, the fragment README.md quotes), not prose of its own."""
    linked = {href.split("#")[0].rstrip("/") for href in _links(site, "")}
    assert {"protocols", "thickening", "configuration"} <= linked
    assert set(PAGES) - {""} - linked == set()
    headline = (DOCS / "generated" / "headline.md").read_text().strip()
    paragraphs = [html.unescape(paragraph).strip() for paragraph in _reading(site, "").paragraphs]
    assert headline in paragraphs
    assert '--8<-- "docs/generated/headline.md"' in (DOCS / "index.md").read_text()


def test_protocols_page_links_how_to_write_a_protocol(site):
    """The protocols page links the workflow page's section on protocols as config entries."""
    assert "../workflow/#protocols-any-flow-history" in _links(site, "protocols")
    assert 'id="protocols-any-flow-history"' in _page(site, "workflow")


def test_configuration_page_is_config_readme(site):
    """config/README.md, the one source of the configuration reference, is the configuration page
    (included, not copied), with its tables."""
    assert (DOCS / "configuration.md").read_text().strip() == '--8<-- "config/README.md"'
    page = _article(site, "configuration")
    for title in re.findall(r"^##? (.+)$", (REPO / "config" / "README.md").read_text(), re.M):
        assert f">{html.escape(title, quote=False)}<" in page, title
    assert page.count("<table") >= 3
    assert "../configuration/" in _links(site, "workflow")


def test_output_table_cells_are_whole(site):
    """The outputs table of Getting started shows each description whole: a bare | in a cell's
    Markdown would cut it short (tests/docs/test_docs_markdown.py checks every table's source)."""
    row = re.search(
        r"<td><code>tables/model_errors.csv</code></td>\s*<td>(.*?)</td>", _page(site, "getting_started"), re.S
    )
    assert row and "per protocol, model, angle and component" in row.group(1), row

"""The documentation site builds with warnings as errors (mkdocs --strict: broken links, missing
pages, API reference from the docstrings, BENCHMARKS.md included), so docs that rot fail CI.

The site is built once per session (the ``site`` fixture, shared with tests/test_api_docs.py) and
its HTML checked: the equations, LaTeX in the Markdown and the docstrings, are rendered to MathML
at build time (docs/hooks/mathml.py) and the site loads nothing from outside itself (no script,
stylesheet or web font)."""

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
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
_OUTSIDE = re.compile(r"""<(?:script|link|img|iframe)\b[^>]*\b(?:src|href)=["']?(?:https?:)?//""", re.I)
#: The built site, shared by the docs tests of one session.
_BUILT: dict[str, Path] = {}


def build_site(tmp_path_factory) -> Path:
    """The site, built strictly once per test session (tests/test_api_docs.py reads it too)."""
    if "site" not in _BUILT:
        _BUILT["site"] = _build(tmp_path_factory.mktemp("docs") / "site")
    return _BUILT["site"]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site, built strictly (once per session, see build_site)."""
    return build_site(tmp_path_factory)


def _build(out: Path) -> Path:
    mkdocs = Path(sys.executable).with_name("mkdocs")
    result = subprocess.run(
        [str(mkdocs), "build", "--strict", "--quiet", "-d", str(out)],
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
    assert "&lt;nn&gt;" in _page(site, "results")


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

"""The API reference (docs/api.md, rendered by mkdocstrings from the numpy-style docstrings) shows
every docstring as written: no Sphinx role (``:func:`x```) left as literal text, and no word lost
on the way (a tensor bracket such as <nn> once vanished as an unknown HTML tag).

Reads the site built once per session by tests/docs/test_docs_build.py (its ``build_site``)."""

import importlib
import inspect
import re
from html.parser import HTMLParser

import pytest
from test_docs_build import DOCS, _page, build_site

#: A Sphinx role as it shows in the text of the page (code spans shown between backticks).
_ROLE = re.compile(r":(func|mod|class|meth|data|attr|obj|exc):`")
#: The ::: directives of the API page and their options.
_DIRECTIVE = re.compile(r"^::: (\S+)\n((?:[ \t]+\S.*\n)*)", re.M)
#: LaTeX, rendered to MathML (the words of an equation are not compared).
_MATH = re.compile(r"\$\$.*?\$\$|(?<![\\$])\$(?=\S)(?:\\.|[^\\$\n])+?(?<=\S)\$(?!\$)|\\\(.*?\\\)", re.S)
#: A word; the angle brackets of a tensor bracket (<nn>, <nnnn>) belong to it.
_WORD = re.compile(r"<*\w+>*")


@pytest.fixture(scope="module")
def api(tmp_path_factory) -> str:
    return _page(build_site(tmp_path_factory), "api")


class _PageText(HTMLParser):
    """The text of a page as a reader sees it, code between backticks, with the extent of each
    mkdocstrings object (``<div class="doc doc-object ...">``): by its heading's id, and the
    top-level ones (one per ::: directive, headed or not) in order."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.parts: list[str] = []
        self.length = 0
        self.divs: list[list] = []  # per open div: [is a doc object, start, id]
        self.objects: dict[str, tuple[int, int]] = {}
        self.top_level: list[tuple[int, int]] = []
        self.hidden = 0  # inside script, style or math

    def _add(self, text: str) -> None:
        self.parts.append(text)
        self.length += len(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag in ("script", "style", "math"):
            self.hidden += 1
        elif tag == "div":
            self.divs.append(["doc-object" in (attrs.get("class") or "").split(), self.length, None])
        elif tag == "code":
            self._add("`")
        elif re.fullmatch(r"h[1-6]", tag) and (attrs.get("id") or "").startswith("suspension_fabric"):
            owner = next((div for div in reversed(self.divs) if div[0]), None)
            if owner is not None and owner[2] is None:
                owner[2] = attrs["id"]
        if tag in ("p", "li", "td", "th", "br", "div", "pre") or re.fullmatch(r"h[1-6]", tag):
            self._add("\n")

    def handle_endtag(self, tag):
        if tag in ("script", "style", "math"):
            self.hidden -= 1
        elif tag == "code":
            self._add("`")
        elif tag == "div" and self.divs:
            is_object, start, ident = self.divs.pop()
            if is_object:
                if ident:
                    self.objects[ident] = (start, self.length)
                if not any(div[0] for div in self.divs):
                    self.top_level.append((start, self.length))
        self._add(" ")

    def handle_data(self, data):
        if not self.hidden:
            self._add(data)

    @property
    def text(self) -> str:
        return "".join(self.parts)


def _parse(page: str) -> _PageText:
    parser = _PageText()
    parser.feed(page)
    parser.close()
    return parser


def _words(text: str) -> list[str]:
    """The words of a text, whatever the markup around them (``_x_`` emphasis shows x)."""
    words = (word.strip("_") for word in _WORD.findall(text))
    return [word for word in words if word.strip("<>")]


def _docstring_words(doc: str) -> list[str]:
    """The words a reader must find on the page: the docstring without its markup (a cross-reference
    ``[x][y]`` or a link ``[x](y)`` shows x, an autolink its address, a numbered list no numbers)
    and without its LaTeX."""
    doc = _MATH.sub(" ", doc)
    doc = re.sub(r"(?<![\w\]])\[([^\]\n]*)\]\[[^\]\n]*\]", r"\1", doc)
    doc = re.sub(r"(?<![\w\]])\[([^\]\n]*)\]\([^)\n]*\)", r"\1", doc)
    doc = re.sub(r"^(\s*)\d+\.(?=\s)", r"\1", doc, flags=re.M)  # the number of a list item
    doc = re.sub(r"<((?:https?|mailto):[^>\s]+)>", r"\1", doc)
    return _words(doc)


def _missing(words: list[str], text: str) -> list[str]:
    """The first word not found in order in the text (a subsequence: a word left out is not made
    up for by the same word further on) and the words around it; empty if all are there."""
    rendered = _words(text)
    position = 0
    for n, word in enumerate(words):
        try:
            position = rendered.index(word, position) + 1
        except ValueError:
            return [word, " ".join(words[max(0, n - 6) : n + 6])]
    return []


def _documented() -> list[tuple[int, str, object]]:
    """(index of its ::: directive, dotted path, object) of every module of the API page and of the
    public classes, functions and methods with a docstring that mkdocstrings renders in them."""
    found = []
    for index, (name, options) in enumerate(_DIRECTIVE.findall((DOCS / "api.md").read_text())):
        module = importlib.import_module(name)
        found.append((index, name, module))
        if "members: false" in options:
            continue
        for attribute, value in vars(module).items():
            if attribute.startswith("_") or not (inspect.isfunction(value) or inspect.isclass(value)):
                continue
            if value.__module__ != name or value.__qualname__ != attribute or not _own_doc(value):
                continue
            found.append((index, f"{name}.{attribute}", value))
            if inspect.isclass(value):
                for member, method in vars(value).items():
                    method = getattr(method, "__func__", method)
                    if not member.startswith("_") and inspect.isfunction(method) and method.__doc__:
                        found.append((index, f"{name}.{attribute}.{member}", method))
    return found


def _own_doc(value) -> str | None:
    """The docstring written for the object (not the signature a dataclass makes up)."""
    doc = value.__doc__
    if inspect.isclass(value) and doc and doc.startswith(f"{value.__name__}("):
        return None
    return doc


def test_api_page_shows_no_sphinx_roles(api):
    text = _parse(api).text
    roles = sorted({text[max(0, m.start() - 40) : m.end() + 40].replace("\n", " ") for m in _ROLE.finditer(text)})
    assert not roles, f"{len(roles)} Sphinx roles shown as text, e.g. {roles[:5]}"


def test_api_page_shows_every_docstring_word(api):
    """Each documented object's docstring, word for word and in order, within that object on the
    page (module docstrings of the directives without a heading: within their directive)."""
    page = _parse(api)
    text = page.text
    documented = _documented()
    assert len(documented) > 400
    assert len(page.top_level) == len({index for index, _, _ in documented})
    problems = []
    for index, path, value in documented:
        start, end = page.objects.get(path) or (page.top_level[index] if inspect.ismodule(value) else (0, 0))
        if end == 0:
            problems.append(f"{path}: not on the API page")
            continue
        lost = _missing(_docstring_words(inspect.cleandoc(value.__doc__ or "")), text[start:end])
        if lost:
            problems.append(f"{path}: lost {lost[0]!r} in {lost[1]!r}")
    assert not problems, "\n".join(problems)


def test_lost_word_is_caught():
    """The check catches the old bug: <nn> dropped as an unknown HTML tag."""
    doc = "Fourth moment from <nn> by the paper's closure."
    assert _missing(_docstring_words(doc), "Fourth moment from by the paper's closure.") != []
    assert _missing(_docstring_words(doc), "Fourth moment from <nn> by the paper's closure.") == []
    text = _parse("<p>Fourth moment from <nn> by the paper's closure.</p>").text
    assert _missing(_docstring_words(doc), text) != []
    text = _parse("<p>See <code>x</code>, [<code>y</code>][a.y] and :func:<code>z</code>.</p>").text
    assert _docstring_words("See ``x``, [`y`][a.y] and") == ["See", "x", "y", "and"]
    assert _ROLE.search(text)

r"""MkDocs hook: the LaTeX math of the pages and docstrings rendered at build time to MathML.

The Markdown writes math as LaTeX, inline ``$...$`` and display ``$$...$$`` (a block of its own);
``pymdownx.arithmatex`` in generic mode keeps it from the Markdown (no emphasis, no escapes, no
HTML) and leaves it in ``<span class="arithmatex">\(...\)</span>`` and
``<div class="arithmatex">\[...\]</div>``. This hook converts each to MathML with ``latex2mathml``,
which browsers display natively: the site loads no JavaScript and no web font for its math.

A display equation may carry ``\tag{...}`` (shown at its right, in parentheses) and
``\label{name}`` (its anchor, ``#eq-name``, which links in the page may name); both are taken out
of the LaTeX before conversion. The LaTeX source stays in the MathML as its TeX annotation (not
shown; read by screen readers and copied with the equation).

latex2mathml writes some constructs that MathML Core (what browsers render) does not display
(``aligned`` and ``gathered`` environments: a literal ``&`` and a line break that browsers
ignore) and keeps an unknown command as text; `problems` names them, and the build warns
(so ``mkdocs build --strict`` fails) on every equation that has one. Multi-line equations use
``\begin{array}{rl}`` or ``\begin{split}``.
"""

from __future__ import annotations

import html
import logging
import re

from latex2mathml.converter import convert

log = logging.getLogger("mkdocs.hooks.mathml")

_DISPLAY = re.compile(r'<div class="arithmatex">\\\[(.*?)\\\]</div>', re.S)
_INLINE = re.compile(r'<span class="arithmatex">\\\((.*?)\\\)</span>', re.S)
_TAG = re.compile(r"\\tag\{([^{}]*)\}")
_LABEL = re.compile(r"\\label\{([A-Za-z0-9_:.-]+)\}")
# a command latex2mathml did not know survives as text (e.g. <mi>\foo</mi>, <mo>\langle</mo>)
_UNKNOWN_COMMAND = re.compile(r">[^<]*\\[^<]*<")
# operators latex2mathml writes as identifiers (no spacing around them): the contraction colon
# A:B, plus-minus, and \sim, which it writes as a tilde
_OPERATORS = {
    "<mi>:</mi>": "<mo>:</mo>",
    "<mi>&#x0003A;</mi>": "<mo>:</mo>",
    "<mi>&#x000B1;</mi>": "<mo>&#x000B1;</mo>",
    "<mi>&#x0007E;</mi>": "<mo>&#x0223C;</mo>",
    # a slash between quantities is spaced as a letter, as in TeX
    "<mo>&#x0002F;</mo>": '<mo lspace="0" rspace="0">&#x0002F;</mo>',
}
# latex2mathml puts brackets in the same row as their neighbours, so a sign after an operator or
# an opening bracket (x = -1, (-a, b)) would be spaced as a binary one: it is a prefix
_SIGN_AFTER_OPERATOR = re.compile(
    r"(<mo(?: [^>]*)?>(?!&#x00029;|&#x0005D;|&#x0007D;|&#x027E9;|&#x02032;|&#x0007C;|&#x02016;)[^<]*</mo>)"
    r"<mo>(&#x02212;|&#x0002B;|&#x000B1;)</mo>"
)


def split_label(latex: str) -> tuple[str, str | None, str | None]:
    """(the LaTeX without its \\tag and \\label, the tag, the label)."""
    tag = _TAG.search(latex)
    label = _LABEL.search(latex)
    body = _LABEL.sub("", _TAG.sub("", latex)).strip()
    return body, tag.group(1).strip() if tag else None, label.group(1) if label else None


def to_mathml(latex: str, display: bool) -> str:
    """MathML of one equation (without \\tag and \\label), its LaTeX kept as the annotation."""
    mathml = convert(latex, display="block" if display else "inline")
    for identifier, operator in _OPERATORS.items():
        mathml = mathml.replace(identifier, operator)
    mathml = _SIGN_AFTER_OPERATOR.sub(r'\1<mo form="prefix">\2</mo>', mathml)
    head, _, rest = mathml.partition(">")
    body = rest[: -len("</math>")]
    annotation = f'<annotation encoding="application/x-tex">{html.escape(latex, quote=False)}</annotation>'
    return f"{head}><semantics>{body}{annotation}</semantics></math>"


def problems(latex: str, display: bool = True) -> list[str]:
    """What would not render of one equation's LaTeX (empty if it converts cleanly)."""
    body = split_label(latex)[0] if display else latex
    try:
        mathml = convert(body, display="block" if display else "inline")
    except Exception as error:  # latex2mathml raises plain exceptions of several kinds
        return [f"latex2mathml failed: {type(error).__name__}: {error}"]
    found = []
    if unknown := _UNKNOWN_COMMAND.findall(mathml):
        found.append(f"unknown commands {sorted({u[1:-1] for u in unknown})}")
    if ">&<" in mathml:
        found.append("a literal & (an alignment environment MathML Core does not render: use array or split)")
    if 'linebreak="newline"' in mathml:
        found.append("a line break MathML Core ignores (use array or split)")
    if 'width="negative' in mathml:
        found.append("a negative named space MathML Core ignores (\\!)")
    if "\\tag" in body or "\\label" in body:
        found.append("\\tag or \\label in inline math, or more than one in an equation")
    return found


def _display(match: re.Match, page, ids: set[str]) -> str:
    latex = html.unescape(match.group(1))
    body, tag, label = split_label(latex)
    for problem in problems(latex):
        log.warning("%s: equation %r: %s", page.file.src_uri, latex.strip()[:80], problem)
    anchor = ""
    if label:
        anchor = f' id="eq-{label}"'
        if f"eq-{label}" in ids:
            log.warning("%s: equation label %r used twice", page.file.src_uri, label)
        ids.add(f"eq-{label}")
    number = f'<span class="equation-tag">({html.escape(tag)})</span>' if tag else ""
    return f'<div class="equation"{anchor}>{to_mathml(body, display=True)}{number}</div>'


def _inline(match: re.Match, page) -> str:
    latex = html.unescape(match.group(1))
    for problem in problems(latex, display=False):
        log.warning("%s: inline math %r: %s", page.file.src_uri, latex[:80], problem)
    return to_mathml(latex, display=False)


def render_math(content: str, page) -> tuple[str, set[str]]:
    """The page's HTML with its arithmatex math as MathML, and the equations' anchors."""
    ids: set[str] = set()
    content = _DISPLAY.sub(lambda match: _display(match, page, ids), content)
    content = _INLINE.sub(lambda match: _inline(match, page), content)
    return content, ids


def on_page_content(html_content, page, **kwargs):
    content, ids = render_math(html_content, page)
    if page.present_anchor_ids is not None:
        page.present_anchor_ids |= ids  # links to #eq-<label> are validated like any other anchor
    return content

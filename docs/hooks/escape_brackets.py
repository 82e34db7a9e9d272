"""MkDocs hook: show the tensor brackets of the text (<nn>, <nnnn>) instead of reading them as HTML
tags, outside code blocks, code spans and math (where they already show as written; the math is
LaTeX, rendered by the hook mathml.py). The pages' Markdown is escaped before it is rendered; the
docstrings of the API reference, which mkdocstrings renders inside the page, after it."""

import re

_CODE = re.compile(
    r"(```.*?```|`[^`\n]*`"  # code blocks and spans
    r"|\$\$.*?\$\$"  # display math
    r"|(?<![\\$])\$(?=\S)(?:\\.|[^\\$\n])+?(?<=\S)\$(?!\$))",  # inline math (arithmatex's smart dollars)
    re.S,
)
_TAG_LIKE = re.compile(r"<(?=n+[>_'\s0-9^])")


def on_page_markdown(markdown, **kwargs):
    pieces = _CODE.split(markdown)
    return "".join(piece if n % 2 else _TAG_LIKE.sub("&lt;", piece) for n, piece in enumerate(pieces))


def on_page_content(html, **kwargs):
    # no HTML element is named n, nn, ...: what is left is a docstring's bracket (code in the HTML
    # has its brackets escaped already)
    return _TAG_LIKE.sub("&lt;", html)

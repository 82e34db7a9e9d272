"""MkDocs hook: show the tensor brackets of the text (<nn>, <nnnn>) instead of reading them as HTML
tags, outside code blocks and code spans (where they already show as written)."""

import re

_CODE = re.compile(r"(```.*?```|`[^`\n]*`)", re.S)
_TAG_LIKE = re.compile(r"<(?=n+[>_'\s0-9^])")


def on_page_markdown(markdown, **kwargs):
    pieces = _CODE.split(markdown)
    return "".join(piece if n % 2 else _TAG_LIKE.sub("&lt;", piece) for n, piece in enumerate(pieces))

"""MkDocs hook: the equations of the pages as MathML, written into the HTML at build time.

pymdownx.arithmatex (generic mode) marks each equation; this hook converts its LaTeX with
latex2mathml, so the site shows its maths with no script and no network (browsers render
MathML natively).
"""

from __future__ import annotations

import html
import re
from typing import Any

from latex2mathml.converter import convert

_BLOCK = re.compile(r'<div class="arithmatex">\s*\\\[(.*?)\\\]\s*</div>', re.S)
_INLINE = re.compile(r'<span class="arithmatex">\\\((.*?)\\\)</span>', re.S)


def _mathml(latex: str, display: str) -> str:
    return convert(html.unescape(latex).strip(), display=display)


def on_page_content(content: str, **kwargs: Any) -> str:
    content = _BLOCK.sub(lambda m: f'<div class="math">{_mathml(m[1], "block")}</div>',
                         content)
    return _INLINE.sub(lambda m: _mathml(m[1], "inline"), content)

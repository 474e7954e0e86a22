"""MkDocs hook of the site (mkdocs.yml ``hooks``): the docstrings' cross-reference roles
(``:class:`~mcl.Axis```) shown as the name they refer to, as Sphinx would show them."""

from __future__ import annotations

import re
from typing import Any

ROLE = re.compile(r":(?:mod|class|func|meth|attr|data|exc|obj|const):<code>(~?)([^<]*)</code>")
"""A role before the inline code mkdocstrings made of its target."""


def on_page_content(html: str, **_: Any) -> str:
    """The page's HTML with each role dropped (``~`` keeps the last part of the name)."""
    return ROLE.sub(lambda m: f"<code>{m[2].rsplit('.', 1)[-1] if m[1] else m[2]}</code>", html)

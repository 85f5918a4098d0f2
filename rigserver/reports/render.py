"""The Jinja2 environment of the reports; templates live beside this module."""

from __future__ import annotations

import base64
from functools import lru_cache
from typing import Any

from jinja2 import Environment, PackageLoader, select_autoescape
from markupsafe import Markup

from rigserver.reports.formatting import html_symbol


def symbols(text: str) -> Markup:
    """The ``sym`` filter: plain text with its symbols' scripts as ``<sub>``/``<sup>``;
    markup (already converted) passes as it is."""
    return text if isinstance(text, Markup) else html_symbol(text)


def base64_text(text: str) -> str:
    """The ``b64`` filter: ``text`` (UTF-8) in base64, for a ``data:`` URL."""
    return base64.b64encode(text.encode()).decode("ascii")


@lru_cache
def environment() -> Environment:
    env = Environment(
        loader=PackageLoader("rigserver.reports", "templates"),
        autoescape=select_autoescape(["html"]),
        trim_blocks=True,
        lstrip_blocks=True,
    )
    env.filters["sym"] = symbols
    env.filters["b64"] = base64_text
    return env


def render(template: str, **context: Any) -> str:
    return environment().get_template(template).render(**context)

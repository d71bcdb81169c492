"""docs/inspector-api.md documents every route of the inspector's web server, and only those
(read from the application itself, rason.inspector.web.make_app); its JSON examples parse."""

from __future__ import annotations

import json
import re
from pathlib import Path

from aiohttp import web

from rason.inspector.store import InspectorStore
from rason.inspector.web import make_app

DOC = Path(__file__).resolve().parents[2] / "docs" / "inspector-api.md"


def _served() -> set[str]:
    app = make_app(InspectorStore(), clock=lambda: 0.0)
    routes = set()
    for route in app.router.routes():
        if route.method != "GET":
            continue                       # HEAD, added beside every GET
        path = route.resource.canonical
        if isinstance(route.resource, web.StaticResource):
            path += "/{file}"
        routes.add(f"GET {path}")
    return routes


def _text() -> str:
    return DOC.read_text(encoding="utf-8")


def test_every_route_has_a_section_and_a_row_and_nothing_else_does():
    served = _served()
    sections = set(re.findall(r"^### `(GET [^`]+)`$", _text(), flags=re.M))
    rows = set(re.findall(r"^\| `(GET [^`]+)` \|", _text(), flags=re.M))
    assert sections == served, f"sections: missing {served - sections}, extra {sections - served}"
    assert rows == served, f"table rows: missing {served - rows}, extra {rows - served}"


def test_the_json_examples_parse():
    blocks = re.findall(r"^```json\n(.*?)^```", _text(), flags=re.M | re.S)
    assert len(blocks) >= 3
    for block in blocks:
        json.loads(block)

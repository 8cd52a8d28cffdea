"""The entity lump: `{ "key" "value" ... }` blocks, the first one being worldspawn."""

from __future__ import annotations

import re

from .errors import BspError

# A token is a brace, a quoted string (may be empty) or a bare word; `//` comments are skipped,
# as the engine's COM_Parse does.
_TOKEN = re.compile(r'//[^\n]*|(\{)|(\})|"([^"]*)"|(")|([^\s{}"]+)')


def parse_entities(text: str, file_name: str) -> list[dict[str, str]]:
    """Entities in file order as key -> value dicts (a repeated key keeps its last value)."""
    where = f"{file_name}: lump 0 (entities)"
    entities: list[dict[str, str]] = []
    current: dict[str, str] | None = None
    pending_key: str | None = None
    for match in _TOKEN.finditer(text):
        opening, closing, quoted, lone_quote, bare = match.groups()
        position = match.start()
        if lone_quote:
            raise BspError(f"{where}: byte {position}: unterminated quoted string")
        if opening is None and closing is None and quoted is None and bare is None:
            continue  # comment
        if opening:
            if current is not None:
                raise BspError(f"{where}: byte {position}: '{{' inside entity {len(entities)} (missing '}}')")
            current, pending_key = {}, None
        elif closing:
            if current is None:
                raise BspError(f"{where}: byte {position}: '}}' without an open entity")
            if pending_key is not None:
                raise BspError(f"{where}: byte {position}: key {pending_key!r} of entity {len(entities)} has no value")
            entities.append(current)
            current = None
        else:
            token = quoted if quoted is not None else bare
            if current is None:
                raise BspError(f"{where}: byte {position}: text {token!r} outside an entity's braces")
            if pending_key is None:
                pending_key = token
            else:
                current[pending_key] = token
                pending_key = None
    if current is not None:
        raise BspError(f"{where}: entity {len(entities)} is not closed (missing '}}' at the end)")
    return entities


def light_entities(entities: list[dict[str, str]]) -> list[dict[str, str]]:
    """Entities whose classname starts with 'light' (case-insensitive), as the light compiler reads them."""
    return [e for e in entities if e.get("classname", "").lower().startswith("light")]


def parse_vector(text: str, count: int, what: str) -> tuple[float, ...]:
    """`"x y z"` -> floats; raises BspError naming `what` when it is not `count` finite numbers."""
    parts = text.split()
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        values = ()
    if len(values) != count or not all(v == v and abs(v) != float("inf") for v in values):
        raise BspError(f"{what}: {text!r} is not {count} finite numbers")
    return values

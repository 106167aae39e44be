"""A TOML emitter (tomllib only reads) for the plain-data form of a scene: tables,
strings, numbers, booleans and arrays of those; floats as their shortest exact repr."""

from __future__ import annotations

import math
import re
from typing import Any

__all__ = ["toml_document"]

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")
_INLINE_WIDTH = 88
_ARRAY_WIDTH = 88


def _toml_key(key: str) -> str:
    return key if _BARE_KEY.match(key) else _toml_string(key)


def _toml_string(text: str) -> str:
    out = ['"']
    for ch in text:
        code = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\t":
            out.append("\\t")
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04X}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def _toml_value(value: Any, indent: str = "") -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"cannot write non-finite number {value} to a scene")
        return repr(value)
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, list | tuple):
        items = [_toml_value(v, indent + "    ") for v in value]
        flat = "[" + ", ".join(items) + "]"
        if len(flat) + len(indent) <= _ARRAY_WIDTH:
            return flat
        lines, line = [], ""
        for item in items:
            if line and len(indent) + 4 + len(line) + len(item) + 2 > _ARRAY_WIDTH:
                lines.append(line.rstrip())
                line = ""
            line += item + ", "
        lines.append(line.rstrip())
        body = "".join(f"\n{indent}    {ln}" for ln in lines)
        return f"[{body}\n{indent}]"
    if isinstance(value, dict):
        items = [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items() if v is not None]
        return "{ " + ", ".join(items) + " }" if items else "{}"
    raise TypeError(f"cannot write {type(value).__name__} to TOML")


def _inline_ok(key: str, value: dict[str, Any]) -> bool:
    if any(isinstance(v, dict) for v in value.values()):
        return False
    return len(f"{key} = {_toml_value(value)}") <= _INLINE_WIDTH


def toml_document(data: dict[str, Any]) -> str:
    lines: list[str] = []
    _emit_table(lines, [], data)
    return "\n".join(lines).lstrip("\n") + "\n"


def _emit_table(lines: list[str], path: list[str], table: dict[str, Any]) -> None:
    simple, subtables = [], []
    for key, value in table.items():
        if value is None or (not path and value == {}):
            # an empty top-level table ([forces] of a scene without force elements) loads
            # back as its default, so it is left out
            continue
        # small leaf tables inside a body or joint (points, materials, laws) go inline;
        # the named entries of [bodies] and [joints] always get their own header
        if isinstance(value, dict) and not (len(path) >= 2 and _inline_ok(key, value)):
            subtables.append((key, value))
        else:
            simple.append(f"{_toml_key(key)} = {_toml_value(value)}")
    if path and (simple or not subtables):
        lines.append("")
        lines.append("[" + ".".join(_toml_key(p) for p in path) + "]")
    lines.extend(simple)
    for key, value in subtables:
        _emit_table(lines, [*path, key], value)

"""What an invalid scene says: :class:`SceneError`, and one line per field-validation
error of pydantic with its key path, the accepted range and the unit, e.g.
``joints.C.clearance: must be > 0 (m); got -0.001``, found by walking the dataclass
annotations from the root type along the error's location."""

from __future__ import annotations

import dataclasses
import functools
import json
import re
import types
import typing
from collections.abc import Iterable, Sequence
from typing import Annotated, Any

import annotated_types as at
from pydantic import Tag, ValidationError

from ._model import Unit

__all__ = [
    "SceneError",
    "describe_errors",
    "format_number",
    "type_hints",
    "union_tags",
    "unwrap_type",
]


class SceneError(ValueError):
    """An invalid scene: each entry of ``problems`` starts with the key path it concerns."""

    def __init__(self, problems: Sequence[str] | str, *, source: str | None = None) -> None:
        self.problems = (problems,) if isinstance(problems, str) else tuple(problems)
        self.source = source
        where = f" ({source})" if source else ""
        if len(self.problems) == 1:
            message = f"{self.problems[0]}{where}"
        else:
            lines = "\n".join(f"  - {p}" for p in self.problems)
            message = f"{len(self.problems)} problems in scene{where}:\n{lines}"
        super().__init__(message)


@functools.cache
def type_hints(cls: type) -> dict[str, Any]:
    return typing.get_type_hints(cls, include_extras=True)


def unwrap_type(tp: Any) -> tuple[Any, list[Any]]:
    """Strip ``Annotated`` and ``| None``; return the bare type and the metadata."""
    meta: list[Any] = []
    while True:
        if typing.get_origin(tp) is Annotated:
            base, *extra = typing.get_args(tp)
            meta.extend(extra)
            tp = base
            continue
        if _is_union(tp):
            members = [a for a in typing.get_args(tp) if a is not type(None)]
            if len(members) == 1:
                tp = members[0]
                continue
        return tp, meta


def _is_union(tp: Any) -> bool:
    return typing.get_origin(tp) in (typing.Union, types.UnionType)


def union_tags(tp: Any) -> dict[str, Any]:
    """For a tagged union (bodies, joints, drive): tag → member class."""
    out = {}
    if _is_union(tp):
        for member in typing.get_args(tp):
            if typing.get_origin(member) is Annotated:
                base, *extra = typing.get_args(member)
                for item in extra:
                    if isinstance(item, Tag):
                        out[item.tag] = base
    return out


@dataclasses.dataclass
class _Location:
    path: str  # key path shown to the user
    tp: Any  # bare type at the location (None if unknown)
    meta: list[Any]  # constraints and Unit at the location
    unit: str | None
    parent: Any  # bare type of the container


def _locate(root: type, loc: Sequence[int | str]) -> _Location:
    tp: Any = root
    parent: Any = None
    unit: str | None = None
    meta: list[Any] = []
    parts: list[str] = []
    for item in loc:
        tp, meta = unwrap_type(tp)
        unit = _unit(meta, unit)
        tags = union_tags(tp)
        if tags:
            if item in tags:  # pydantic puts the union tag into the location
                tp = tags[item]
                continue
        parent = tp
        if dataclasses.is_dataclass(tp) and isinstance(tp, type):
            parts.append(f".{item}")
            tp = type_hints(tp).get(str(item))
            unit = None
        elif typing.get_origin(tp) is dict:
            parts.append(f".{item}")
            tp = typing.get_args(tp)[1]
        elif typing.get_origin(tp) is tuple and isinstance(item, int):
            parts.append(f"[{item}]")
            args = typing.get_args(tp)
            if len(args) == 2 and args[1] is Ellipsis:
                tp = args[0]
            else:
                tp = args[item] if item < len(args) else None
        else:
            parts.append(f".{item}")
            tp = None
    tp, meta = unwrap_type(tp)
    unit = _unit(meta, unit)
    return _Location("".join(parts).lstrip("."), tp, meta, unit, parent)


def _unit(meta: Iterable[Any], default: str | None) -> str | None:
    for item in meta:
        if isinstance(item, Unit):
            default = item.symbol
    return default


def format_number(x: Any) -> str:
    if isinstance(x, float):
        return f"{x:g}"
    return str(x)


def _range(meta: Iterable[Any]) -> str:
    lo: tuple[str, Any] | None = None
    hi: tuple[str, Any] | None = None
    for item in meta:
        if isinstance(item, at.Gt):
            lo = ("(", item.gt)
        elif isinstance(item, at.Ge):
            lo = ("[", item.ge)
        elif isinstance(item, at.Lt):
            hi = (")", item.lt)
        elif isinstance(item, at.Le):
            hi = ("]", item.le)
    if lo and hi:
        return f"in {lo[0]}{format_number(lo[1])}, {format_number(hi[1])}{hi[0]}"
    if lo:
        return f"{'>' if lo[0] == '(' else '>='} {format_number(lo[1])}"
    if hi:
        return f"{'<' if hi[0] == ')' else '<='} {format_number(hi[1])}"
    return ""


def _units(unit: str | None) -> str:
    return f" ({unit})" if unit not in (None, "", "1") else ""


def _show(value: Any) -> str:
    text = json.dumps(value, default=repr) if not isinstance(value, str) else repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _expected(where: _Location) -> str:
    """What a location accepts, e.g. 'a number > 0 (kg)' or 'an array of 2 numbers (m)'."""
    tp, rng = where.tp, _range(where.meta)
    if tp is bool:
        return "true or false"
    if tp is float:
        return f"a number{' ' + rng if rng else ''}{_units(where.unit)}"
    if tp is int:
        return f"an integer{' ' + rng if rng else ''}"
    if tp is str:
        return "a string"
    if typing.get_origin(tp) is typing.Literal:
        return "one of " + ", ".join(repr(a) for a in typing.get_args(tp))
    if typing.get_origin(tp) is tuple:
        args = typing.get_args(tp)
        elem, _ = unwrap_type(args[0])
        kind = "numbers" if elem is float else "names" if elem is str else "values"
        if len(args) == 2 and args[1] is Ellipsis:
            return f"an array of {kind}{_units(where.unit)}"
        return f"an array of {len(args)} {kind}{_units(where.unit)}"
    if typing.get_origin(tp) is dict or dataclasses.is_dataclass(tp) or union_tags(tp):
        return "a table"
    return "a valid value"


_ENTRY = re.compile(r"^(?P<array>.*)\[(?P<index>\d+)\]: (?P<problem>.*?); got ")


def describe_errors(exc: ValidationError, root: type) -> list[str]:
    """One line per problem of validating ``root`` (the scene type); the entries of one
    array that break the same rule are one line (the first, and how many more), not one
    line per entry."""
    lines: list[str] = []
    more: dict[tuple[str, str], int] = {}
    first: dict[tuple[str, str], int] = {}
    for err in exc.errors():
        line = _describe(err, root)
        entry = _ENTRY.match(line)
        if entry is not None:
            rule = (entry["array"], entry["problem"])
            if rule in first:
                more[rule] = more.get(rule, 0) + 1
                continue
            first[rule] = len(lines)
        if line not in lines:
            lines.append(line)
    for rule, count in more.items():
        lines[first[rule]] += f" (and {count} more entries)"
    return lines


def _describe(err: Any, root: type) -> str:
    kind, loc, value = err["type"], tuple(err["loc"]), err.get("input")
    where = _locate(root, loc)
    got = f"; got {_show(value)}"
    if kind == "missing" and loc and isinstance(loc[-1], int):
        # a too-short array is reported per missing element: report it on the array
        where = _locate(root, loc[:-1])
        return f"{where.path}: must be {_expected(where)}{got}"
    if kind == "missing":
        return f"{where.path}: required key is missing (expected {_expected(where)})"
    if kind == "unexpected_keyword_argument":
        parent = where.parent
        valid = ", ".join(f.name for f in dataclasses.fields(parent)) if parent else ""
        return f"{where.path}: unknown key; valid keys here: {valid}"
    if kind == "union_tag_invalid":
        tags = ", ".join(repr(t) for t in union_tags(where.tp))
        tag = value.get("type") if isinstance(value, dict) else value
        return f"{where.path}.type: must be one of {tags}; got {_show(tag)}"
    if kind == "union_tag_not_found":
        if not isinstance(value, dict):
            return f"{where.path}: must be a table{got}"
        tags = ", ".join(repr(t) for t in union_tags(where.tp))
        return f"{where.path}.type: required key is missing (expected one of {tags})"
    if kind == "value_error":
        message = str(err["msg"]).removeprefix("Value error, ")
        return f"{where.path}: {message}{got}"
    if kind == "finite_number":
        return f"{where.path}: must be a finite number{_units(where.unit)}{got}"
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        return f"{where.path}: must be {_range(where.meta)}{_units(where.unit)}{got}"
    if kind == "string_too_short":
        return f"{where.path}: must be a non-empty string{got}"
    known = (
        "float_type float_parsing int_type int_parsing int_from_float bool_type bool_parsing "
        "string_type literal_error tuple_type too_long too_short dict_type dataclass_type "
        "dataclass_exact_type"
    ).split()
    if kind in known:
        return f"{where.path}: must be {_expected(where)}{got}"
    return f"{where.path}: {err['msg']}{got}"

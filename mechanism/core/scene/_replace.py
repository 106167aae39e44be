"""Dotted-key assignment into the plain-data form of a scene (``"joints.C.clearance"``),
with the valid keys at each level taken from the scene's dataclasses."""

from __future__ import annotations

import dataclasses
import typing
from typing import Any

from pydantic import Discriminator

from ._messages import SceneError, type_hints, union_tags, unwrap_type

__all__ = ["assign_dotted"]


def assign_dotted(data: dict[str, Any], parts: list[str], value: Any, root: type) -> None:
    """Set ``data[parts[0]][parts[1]]... = value``; the valid keys at each level come from
    the dataclass fields of ``root`` (the scene type) and below or, for named tables such as
    ``bodies``, the names present."""
    key = ".".join(parts)
    node: Any = data
    tp: Any = root
    for depth, part in enumerate(parts):
        level = ".".join(parts[:depth])
        if node is None:
            raise SceneError(f"{key}: '{level}' is not set; assign '{level}' as a whole")
        base, meta = unwrap_type(tp)
        tags = union_tags(base)
        if tags and isinstance(node, dict):
            pick = next(m.discriminator for m in meta if isinstance(m, Discriminator))
            tag = pick(node) if callable(pick) else None
            base = tags.get(tag) if isinstance(tag, str) else None
        if not isinstance(node, dict) or not (
            typing.get_origin(base) is dict or dataclasses.is_dataclass(base)
        ):
            if isinstance(node, dict):  # a table of unknown type: take the keys present
                valid = list(node)
                child_tp = None
            else:
                raise SceneError(f"{key}: '{level}' is a value, not a table; assign it as a whole")
        elif typing.get_origin(base) is dict:
            valid, child_tp = list(node), typing.get_args(base)[1]
        else:
            hints = type_hints(base)
            valid, child_tp = list(hints), hints.get(part)
        if part not in valid:
            raise SceneError(
                f"{key}: unknown key {part!r} in {level or 'the top level'}; "
                f"valid keys there: {', '.join(valid) or '(none)'}"
            )
        if depth == len(parts) - 1:
            node[part] = value
            return
        if part not in node:  # a table given partially earlier; pydantic fills the defaults
            node[part] = {}
        node, tp = node[part], child_tp

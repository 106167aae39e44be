"""The :class:`~mechanism.Scene`, its loading and storage: TOML/JSON → a validated
:class:`~mechanism.Scene`, dotted-key replacement, and a small TOML emitter so that a saved
scene loads back identical.

Validation has two stages. Field validation (pydantic ``TypeAdapter`` over the frozen
dataclasses of ``_model.py``) checks types, ranges and unknown keys; every error is
reported with its key path, the accepted range and the unit, e.g.
``joints.C.clearance: must be > 0 (m); got -0.001``. Cross-checks then check what one
field cannot know: bodies and points named by joints exist, a clearance is smaller than
its bearing radius, the drive acts on an ideal revolute joint, and so on.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import json
import math
import re
import tomllib
import types
import typing
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Annotated, Any

import annotated_types as at
import numpy as np
from pydantic import Discriminator, Tag, TypeAdapter, ValidationError, with_config

from chaoskit.contract import atomic_write

from ._model import (
    GROUND,
    INERTIA_RANGE,
    MASS_RANGE,
    MODEL_CONFIG,
    Acceleration,
    AncfBeam,
    AngleProfileDrive,
    Body,
    ClearanceRevolute,
    Drive,
    Effects,
    FixedJoint,
    Joint,
    Name,
    Outputs,
    Point,
    PrismaticJoint,
    RevoluteJoint,
    RigidBody,
    SolverSettings,
    Text,
    Unit,
)

__all__ = [
    "Scene",
    "SceneError",
    "list_scenes",
    "load_scene",
    "replace_scene",
    "save_scene",
    "scene_from_dict",
    "scene_from_json",
    "scene_from_toml",
    "scene_to_dict",
    "scene_to_json",
    "scene_to_toml",
    "validate_scene",
]

_NAME = re.compile(r"^[A-Za-z0-9_-]+$")
_BEAM_LENGTH_RTOL = 1e-3  # |end − start| vs length: catches unit slips, allows rounded input
#: the radius of gyration of a rigid body that can rotate lies within this factor of its
#: farthest point: the constraint matrix then keeps its entries 1/m and r²/J within eight
#: decades, half the digits of double precision (docs/scenes.md, "Accepted ranges")
GYRATION_RATIO = 1e4
_AXIS_TOL = 1e-6


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class Scene:
    """A planar mechanism as data: bodies, joints, drive, effects and solver settings.

    Load one with :func:`mechanism.load_scene` (built-in name or TOML path), change it with
    :meth:`replace`, store it with :func:`mechanism.save_scene` or :meth:`to_json`.

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("slider-crank")
    >>> faster = scene.replace({"drive.speed_rpm": 6000.0})
    >>> faster.drive.speed_rpm, scene.drive.speed_rpm
    (6000.0, 5000.0)
    """

    name: Name
    description: Text = ""
    effects: Effects = field(default_factory=Effects)
    gravity: Annotated[tuple[Acceleration, Acceleration], Unit("m s-2")] = (0.0, -9.81)
    ground_points: Annotated[dict[str, Point], Unit("m")] = field(default_factory=dict)
    bodies: dict[str, Body] = field(default_factory=dict)
    joints: dict[str, Joint] = field(default_factory=dict)
    drive: Drive | None = None
    solver: SolverSettings = field(default_factory=SolverSettings)
    outputs: Outputs = field(default_factory=Outputs)

    def replace(self, changes: Mapping[str, Any]) -> Scene:
        """A new validated scene with dotted keys replaced, e.g. ``{"joints.C.clearance": 2e-4}``.

        A table value (a dict) replaces the whole table. Unknown keys raise
        :class:`~mechanism.SceneError` listing the valid keys at that level.
        """
        return replace_scene(self, changes)

    def to_dict(self) -> dict[str, Any]:
        """Plain nested dicts and lists (unset optional fields as ``None``)."""
        return scene_to_dict(self)

    def to_json(self) -> str:
        """The resolved scene as JSON text (read back with ``scene_from_json``)."""
        return scene_to_json(self)

    def to_toml(self) -> str:
        """The resolved scene as TOML text (what ``save_scene`` writes)."""
        return scene_to_toml(self)

    def save(self, path: str | Path) -> None:
        """Write the scene as TOML to ``path`` (same as ``mechanism.save_scene``)."""
        save_scene(self, path)


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


# ---------------------------------------------------------------------------------------
# Public functions


def load_scene(name_or_path: str | Path | Scene) -> Scene:
    """Load and validate a scene: a built-in name (see :func:`list_scenes`) or a TOML file.

    Parameters
    ----------
    name_or_path : str, pathlib.Path or Scene
        A built-in scene name (``"paper"``, ``"slider-crank"``, ...), or the path of a
        TOML scene file (``docs/scenes.md`` describes the keys). A built-in name wins over
        a file of the same name in the working directory; write ``./name`` for the file.
        A :class:`~mechanism.Scene` is returned unchanged.

    Returns
    -------
    Scene
        The validated, frozen scene.

    Raises
    ------
    SceneError
        (a ``ValueError``) naming the key path, the accepted range and the unit of every
        invalid entry, or the reason the file could not be read.

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("slider-crank-clearance")
    >>> scene.joints["B"].clearance
    0.0005
    """
    if isinstance(name_or_path, Scene):
        return name_or_path
    if isinstance(name_or_path, str) and name_or_path in _builtin_names():
        text = _builtin_file(name_or_path).read_text(encoding="utf-8")
        return scene_from_toml(text, source=f"built-in scene {name_or_path!r}")
    path = Path(name_or_path)
    if not path.is_file():
        raise SceneError(
            f"no built-in scene or file named {str(name_or_path)!r}; "
            f"built-in scenes: {', '.join(_builtin_names())}"
        )
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"cannot read scene file: {exc}", source=str(path)) from exc
    return scene_from_toml(text, source=str(path))


def save_scene(scene: Scene, path: str | Path) -> Path:
    """Validate ``scene`` and write it as TOML; :func:`load_scene` reads it back identical.

    Unset optional keys (``None``) are omitted, since TOML has no null; they load back
    as ``None``. Floats are written with the shortest repr that round-trips exactly. The
    file is written atomically (temporary file, then rename): if writing fails, e.g. on a
    full disk, an existing file at ``path`` is left as it was.

    Examples
    --------
    >>> import tempfile, pathlib, mechanism
    >>> scene = mechanism.load_scene("slider-crank")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "sc.toml"
    >>> mechanism.load_scene(mechanism.save_scene(scene, path)) == scene
    True
    """
    validate_scene(scene)
    path = Path(path)
    header = (
        f"# mechanism scene {scene.name!r}, written by mechanism.save_scene.\n"
        "# Keys, units and accepted ranges: docs/scenes.md\n\n"
    )
    text = header + scene_to_toml(scene)
    # atomic: a failed write (a full disk) leaves the old scene file, never half a TOML
    atomic_write(path, lambda p: p.write_text(text, encoding="utf-8"), nbytes=len(text))
    return path


def list_scenes() -> dict[str, str]:
    """Built-in scene names with their one-line descriptions.

    Examples
    --------
    >>> import mechanism
    >>> "paper" in mechanism.list_scenes()
    True
    """
    out = {}
    for name in _builtin_names():
        data = tomllib.loads(_builtin_file(name).read_text(encoding="utf-8"))
        lines = str(data.get("description", "")).strip().splitlines()
        out[name] = lines[0] if lines else ""
    return out


def scene_from_toml(text: str, *, source: str | None = None) -> Scene:
    """Parse TOML text and validate it into a :class:`~mechanism.Scene`."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"not valid TOML: {exc}", source=source) from exc
    return scene_from_dict(data, source=source)


def scene_from_json(text: str) -> Scene:
    """Validate the JSON form written by :meth:`Scene.to_json` (e.g. from a Dataset's attrs).

    Examples
    --------
    >>> import mechanism
    >>> from mechanism.core.scene import scene_from_json
    >>> scene = mechanism.load_scene("paper")
    >>> scene_from_json(scene.to_json()) == scene
    True
    """
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise SceneError(f"not valid JSON: {exc}", source="JSON") from exc
    return scene_from_dict(data, source="JSON")


def scene_from_dict(data: Mapping[str, Any], *, source: str | None = None) -> Scene:
    """Validate nested mappings (TOML/JSON layout, keys = field names) into a
    :class:`~mechanism.Scene`."""
    if not isinstance(data, Mapping):
        raise SceneError(
            f"a scene must be a table of keys; got {type(data).__name__}", source=source
        )
    try:
        scene = _adapter().validate_python(_plain(dict(data)))
    except ValidationError as exc:
        raise SceneError(_describe_errors(exc), source=source) from None
    problems = _cross_check(scene)
    if problems:
        raise SceneError(problems, source=source)
    return _resolve_inertias(scene)


def validate_scene(scene: Scene) -> Scene:
    """Validate a scene built in Python (the dataclasses do not check themselves)."""
    return scene_from_dict(scene_to_dict(scene), source=f"scene {scene.name!r}")


def scene_to_dict(scene: Scene) -> dict[str, Any]:
    """Nested dicts/lists of plain Python values; unset optional fields are ``None``."""
    out = _plain(scene)
    assert isinstance(out, dict)
    return out


def scene_to_json(scene: Scene) -> str:
    """JSON text of :func:`scene_to_dict` (floats exact, unset optionals as ``null``)."""
    return json.dumps(scene_to_dict(scene), allow_nan=False)


def scene_to_toml(scene: Scene) -> str:
    """TOML text of the scene in the layout of ``docs/scenes.md``."""
    return _toml_document(scene_to_dict(scene))


def replace_scene(scene: Scene, changes: Mapping[str, Any]) -> Scene:
    """A new validated scene with the dotted keys of ``changes`` replaced.

    Keys are applied in order; a dict value replaces the whole table at that key. Numpy
    scalars and arrays are accepted (as Python numbers and lists).

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("paper")
    >>> worn = scene.replace({"joints.C.clearance": 5e-4, "effects.friction": False})
    >>> worn.joints["C"].clearance, worn.effects.friction
    (0.0005, False)
    """
    if not isinstance(changes, Mapping):
        raise TypeError(f"changes must be a mapping of dotted keys; got {type(changes).__name__}")
    data = scene_to_dict(scene)
    for key, value in changes.items():
        parts = key.split(".") if isinstance(key, str) else []
        if not parts or not all(parts):
            raise SceneError(f"{key!r}: not a dotted key such as 'joints.C.clearance'")
        _assign(data, parts, _plain(value))
    return scene_from_dict(data, source=f"scene {scene.name!r} after replace")


def _assign(data: dict[str, Any], parts: list[str], value: Any) -> None:
    """Set ``data[parts[0]][parts[1]]... = value``; the valid keys at each level come from
    the model (dataclass fields) or, for named tables such as ``bodies``, the names present."""
    key = ".".join(parts)
    node: Any = data
    tp: Any = Scene
    for depth, part in enumerate(parts):
        level = ".".join(parts[:depth])
        if node is None:
            raise SceneError(f"{key}: '{level}' is not set; assign '{level}' as a whole")
        base, meta = _unwrap(tp)
        tags = _tags(base)
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
            hints = _hints(base)
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


# ---------------------------------------------------------------------------------------
# Built-in scenes


def _builtin_dir() -> Any:
    return resources.files(__package__).joinpath("builtin")


@functools.cache
def _builtin_names() -> tuple[str, ...]:
    names = [
        entry.name.removesuffix(".toml")
        for entry in _builtin_dir().iterdir()
        if entry.name.endswith(".toml")
    ]
    return tuple(sorted(names))


def _builtin_file(name: str) -> Any:
    return _builtin_dir().joinpath(f"{name}.toml")


# ---------------------------------------------------------------------------------------
# Plain data


def _plain(obj: Any) -> Any:
    """Dataclasses → dicts, tuples/arrays → lists, numpy scalars → Python scalars."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, Mapping):
        return {key: _plain(value) for key, value in obj.items()}
    if isinstance(obj, list | tuple):
        return [_plain(value) for value in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


@functools.cache
def _adapter() -> TypeAdapter[Scene]:
    return TypeAdapter(Scene)


# ---------------------------------------------------------------------------------------
# Error messages: walk the dataclass annotations along pydantic's error location


@functools.cache
def _hints(cls: type) -> dict[str, Any]:
    return typing.get_type_hints(cls, include_extras=True)


def _unwrap(tp: Any) -> tuple[Any, list[Any]]:
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


def _tags(tp: Any) -> dict[str, Any]:
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


def _locate(loc: Sequence[int | str]) -> _Location:
    tp: Any = Scene
    parent: Any = None
    unit: str | None = None
    meta: list[Any] = []
    parts: list[str] = []
    for item in loc:
        tp, meta = _unwrap(tp)
        unit = _unit(meta, unit)
        tags = _tags(tp)
        if tags:
            if item in tags:  # pydantic puts the union tag into the location
                tp = tags[item]
                continue
        parent = tp
        if dataclasses.is_dataclass(tp) and isinstance(tp, type):
            parts.append(f".{item}")
            tp = _hints(tp).get(str(item))
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
    tp, meta = _unwrap(tp)
    unit = _unit(meta, unit)
    return _Location("".join(parts).lstrip("."), tp, meta, unit, parent)


def _unit(meta: Iterable[Any], default: str | None) -> str | None:
    for item in meta:
        if isinstance(item, Unit):
            default = item.symbol
    return default


def _fmt(x: Any) -> str:
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
        return f"in {lo[0]}{_fmt(lo[1])}, {_fmt(hi[1])}{hi[0]}"
    if lo:
        return f"{'>' if lo[0] == '(' else '>='} {_fmt(lo[1])}"
    if hi:
        return f"{'<' if hi[0] == ')' else '<='} {_fmt(hi[1])}"
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
        elem, _ = _unwrap(args[0])
        kind = "numbers" if elem is float else "names" if elem is str else "values"
        if len(args) == 2 and args[1] is Ellipsis:
            return f"an array of {kind}{_units(where.unit)}"
        return f"an array of {len(args)} {kind}{_units(where.unit)}"
    if typing.get_origin(tp) is dict or dataclasses.is_dataclass(tp) or _tags(tp):
        return "a table"
    return "a valid value"


_ENTRY = re.compile(r"^(?P<array>.*)\[(?P<index>\d+)\]: (?P<problem>.*?); got ")


def _describe_errors(exc: ValidationError) -> list[str]:
    """One line per problem; the entries of one array that break the same rule are one
    line (the first, and how many more), not one line per entry."""
    lines: list[str] = []
    more: dict[tuple[str, str], int] = {}
    first: dict[tuple[str, str], int] = {}
    for err in exc.errors():
        line = _describe(err)
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


def _describe(err: Any) -> str:
    kind, loc, value = err["type"], tuple(err["loc"]), err.get("input")
    where = _locate(loc)
    got = f"; got {_show(value)}"
    if kind == "missing" and loc and isinstance(loc[-1], int):
        # a too-short array is reported per missing element: report it on the array
        where = _locate(loc[:-1])
        return f"{where.path}: must be {_expected(where)}{got}"
    if kind == "missing":
        return f"{where.path}: required key is missing (expected {_expected(where)})"
    if kind == "unexpected_keyword_argument":
        parent = where.parent
        valid = ", ".join(f.name for f in dataclasses.fields(parent)) if parent else ""
        return f"{where.path}: unknown key; valid keys here: {valid}"
    if kind == "union_tag_invalid":
        tags = ", ".join(repr(t) for t in _tags(where.tp))
        tag = value.get("type") if isinstance(value, dict) else value
        return f"{where.path}.type: must be one of {tags}; got {_show(tag)}"
    if kind == "union_tag_not_found":
        if not isinstance(value, dict):
            return f"{where.path}: must be a table{got}"
        tags = ", ".join(repr(t) for t in _tags(where.tp))
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


# ---------------------------------------------------------------------------------------
# Cross-checks (after field validation)


def _cross_check(scene: Scene) -> list[str]:
    problems: list[str] = []
    add = problems.append

    def names(table: str, mapping: Mapping[str, Any]) -> None:
        for name in mapping:
            if not _NAME.match(name):
                add(
                    f"{table}.{name}: a name may use only letters, digits, '_' and '-' "
                    "(so that dotted keys stay unambiguous)"
                )

    names("ground_points", scene.ground_points)
    names("bodies", scene.bodies)
    names("joints", scene.joints)
    if GROUND in scene.bodies:
        add(f"bodies.{GROUND}: {GROUND!r} is the frame; use [ground_points] for its points")

    def check_gyration(body_name: str, body: RigidBody) -> None:
        # the constraint matrix Φq M⁻¹ Φqᵀ holds 1/m and r²/J side by side: their ratio,
        # (r/k)² with k = sqrt(J/m), must leave double precision digits to spare
        reach = max((math.hypot(*p) for p in body.points.values()), default=0.0)
        if reach == 0.0 or body.inertia is None:
            return
        ratio = math.sqrt(body.inertia / body.mass) / reach
        if not 1.0 / GYRATION_RATIO <= ratio <= GYRATION_RATIO:
            add(
                f"bodies.{body_name}.inertia: the radius of gyration sqrt(inertia / mass) = "
                f"{_fmt(ratio * reach)} m must be within a factor {GYRATION_RATIO:g} of the "
                f"farthest point from the centre of mass ({_fmt(reach)} m); got inertia "
                f"{_fmt(body.inertia)} (kg m2) with mass {_fmt(body.mass)} (kg)"
            )

    held = _held_bodies(scene)
    for body_name, body in scene.bodies.items():
        if isinstance(body, RigidBody):
            names(f"bodies.{body_name}.points", body.points)
            if body.inertia is None and body_name not in held:
                low, high = INERTIA_RANGE
                add(
                    f"bodies.{body_name}.inertia: required key is missing (expected a number "
                    f"in [{low:g}, {high:g}] (kg m2)); only a body held to the ground by a "
                    "prismatic or fixed joint, which cannot rotate, may leave it out"
                )
            elif body.inertia is not None and body_name not in held:
                check_gyration(body_name, body)
        elif isinstance(body, AncfBeam):
            low, high = MASS_RANGE
            if body.mass is None and not low <= body.total_mass <= high:
                add(
                    f"bodies.{body_name}.mass: density × area × length = "
                    f"{_fmt(body.total_mass)} kg is outside [{low:g}, {high:g}] (kg); "
                    "change them or give mass"
                )
            chord = math.dist(body.start, body.end)
            if abs(chord - body.length) > _BEAM_LENGTH_RTOL * body.length:
                add(
                    f"bodies.{body_name}.length: {_fmt(body.length)} m differs from "
                    f"|end − start| = {_fmt(chord)} m by more than "
                    f"{_BEAM_LENGTH_RTOL:.1%}"
                )

    def body_points(body_name: str) -> tuple[str, ...] | None:
        if body_name == GROUND:
            return tuple(scene.ground_points)
        body = scene.bodies.get(body_name)
        return None if body is None else body.point_names

    def check_end(path: str, point_path: str, body_name: str, point: str) -> None:
        points = body_points(body_name)
        if points is None:
            known = ", ".join([GROUND, *scene.bodies])
            add(f"{path}: no body {body_name!r}; bodies: {known}")
        elif point not in points:
            add(
                f"{point_path}: body {body_name!r} has no point {point!r}; "
                f"its points: {', '.join(points) or '(none)'}"
            )

    for joint_name, joint in scene.joints.items():
        base = f"joints.{joint_name}"
        if isinstance(joint, ClearanceRevolute):
            ends = [(f"{base}.bearing", joint.bearing), (f"{base}.journal", joint.journal)]
            for path, (body_name, point) in ends:
                check_end(f"{path}[0]", f"{path}[1]", body_name, point)
            if joint.bearing[0] == joint.journal[0]:
                add(f"{base}.journal[0]: bearing and journal must be on different bodies")
            if joint.clearance >= joint.bearing_radius:
                add(
                    f"{base}.clearance: must be < bearing_radius = "
                    f"{_fmt(joint.bearing_radius)} (m); got {_fmt(joint.clearance)}"
                )
            ecc = math.hypot(*joint.initial_eccentricity)
            if ecc > joint.clearance:
                add(
                    f"{base}.initial_eccentricity: |e| must be <= clearance = "
                    f"{_fmt(joint.clearance)} (m); got |e| = {_fmt(ecc)}"
                )
            friction = joint.friction
            if friction.law == "ambrosio" and friction.v1 <= friction.v0:
                add(
                    f"{base}.friction.v1: must be > v0 = {_fmt(friction.v0)} "
                    f"(m s-1); got {_fmt(friction.v1)}"
                )
            wear = joint.wear
            for part in ("bearing_profile", "journal_profile"):
                n = len(getattr(wear, part))
                if n not in (0, wear.regions):
                    add(
                        f"{base}.wear.{part}: must be empty or hold one depth per region "
                        f"({wear.regions}) (m); got {n} values"
                    )
            if wear.smoothing_regions > wear.regions // 2:
                # the smoothing window spans at most half the circumference
                add(
                    f"{base}.wear.smoothing_regions: must be <= regions // 2 "
                    f"({wear.regions // 2}); got {wear.smoothing_regions}"
                )
            journal_radius = joint.bearing_radius - joint.clearance
            deepest = max(wear.journal_profile, default=0.0)
            if wear.journal_profile and 0.0 < journal_radius <= deepest:
                add(
                    f"{base}.wear.journal_profile: every depth must be < the journal radius "
                    f"(bearing_radius - clearance = {_fmt(journal_radius)} m); got "
                    f"{_fmt(deepest)}"
                )
            continue
        for i in (0, 1):
            check_end(
                f"{base}.bodies[{i}]", f"{base}.points[{i}]", joint.bodies[i], joint.points[i]
            )
        if joint.bodies[0] == joint.bodies[1]:
            add(f"{base}.bodies: a joint needs two different bodies; got {list(joint.bodies)}")
        if isinstance(joint, PrismaticJoint):
            norm = math.hypot(*joint.axis)
            if abs(norm - 1.0) > _AXIS_TOL:
                add(f"{base}.axis: must be a unit vector; got length {_fmt(norm)}")

    def check_joint_ref(path: str, joint_name: str, kinds: tuple[type, ...]) -> None:
        joint = scene.joints.get(joint_name)
        if joint is None:
            add(f"{path}: no joint {joint_name!r}; joints: {', '.join(scene.joints) or '(none)'}")
        elif not isinstance(joint, kinds):
            wanted = " or ".join(repr(_joint_type(kind)) for kind in kinds)
            add(f"{path}: joint {joint_name!r} is {joint.type!r}; it must be a {wanted} joint")

    drive = scene.drive
    if drive is not None:
        check_joint_ref("drive.joint", drive.joint, (RevoluteJoint,))
        if isinstance(drive, AngleProfileDrive):
            t, a = drive.time, drive.angle
            if len(t) < 2 or len(t) != len(a):
                add(
                    f"drive.time: needs at least 2 samples and one angle per time; "
                    f"got {len(t)} times and {len(a)} angles"
                )
            elif any(t1 <= t0 for t0, t1 in itertools.pairwise(t)):
                add("drive.time: must be strictly increasing")
            elif t[-1] - t[0] > drive.period:
                add(
                    f"drive.time: the samples must span at most one period "
                    f"({_fmt(drive.period)} s); got {_fmt(t[-1] - t[0])} s"
                )
    outputs = scene.outputs
    if outputs.slider_joint is not None:
        check_joint_ref("outputs.slider_joint", outputs.slider_joint, (PrismaticJoint,))
    if outputs.crank_joint is not None:
        kinds = (RevoluteJoint, ClearanceRevolute)
        check_joint_ref("outputs.crank_joint", outputs.crank_joint, kinds)
    return problems


def _held_bodies(scene: Scene) -> set[str]:
    """Bodies that cannot rotate: held to the ground by a prismatic or fixed joint."""
    held = set()
    for joint in scene.joints.values():
        if isinstance(joint, PrismaticJoint | FixedJoint) and GROUND in joint.bodies:
            held.update(name for name in joint.bodies if name != GROUND)
    return held


def _resolve_inertias(scene: Scene) -> Scene:
    """Give every rigid body that left out its inertia (it cannot rotate) mass × (1 m)².

    The value does not change the motion: the joint that holds the body keeps its angle
    constant whatever the inertia. It gives the rotation row of the constraint matrix
    Φq M⁻¹ Φqᵀ (1/J) the scale of the translation rows (1/m), so that matrix stays as
    well conditioned as the rest of the mechanism makes it.
    """
    bodies = {
        name: dataclasses.replace(body, inertia=body.mass * 1.0)
        if isinstance(body, RigidBody) and body.inertia is None
        else body
        for name, body in scene.bodies.items()
    }
    if bodies == scene.bodies:
        return scene
    return dataclasses.replace(scene, bodies=bodies)


def _joint_type(cls: type) -> str:
    return str(next(f.default for f in dataclasses.fields(cls) if f.name == "type"))


# ---------------------------------------------------------------------------------------
# TOML emitter (tomllib only reads); covers what a scene holds: tables, strings, numbers,
# booleans and arrays of those.

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


def _toml_document(data: dict[str, Any]) -> str:
    lines: list[str] = []
    _emit_table(lines, [], data)
    return "\n".join(lines).lstrip("\n") + "\n"


def _emit_table(lines: list[str], path: list[str], table: dict[str, Any]) -> None:
    simple, subtables = [], []
    for key, value in table.items():
        if value is None:
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

"""Loading scenes: the built-in scenes of the package and TOML scene files, and the JSON
form stored with results, each validated into a :class:`~mechanism.Scene`."""

from __future__ import annotations

import functools
import json
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from ._messages import SceneError
from ._scene import Scene, scene_from_dict

__all__ = ["list_scenes", "load_scene", "scene_from_json", "scene_from_toml"]


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
        text = builtin_file(name_or_path).read_text(encoding="utf-8")
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
        data = tomllib.loads(builtin_file(name).read_text(encoding="utf-8"))
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


def builtin_file(name: str) -> Any:
    """The packaged TOML file of the built-in scene ``name`` (an importlib resource)."""
    return _builtin_dir().joinpath(f"{name}.toml")

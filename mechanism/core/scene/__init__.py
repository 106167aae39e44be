"""Scenes: mechanisms described as data (TOML), validated into frozen dataclasses.

Load a built-in scene or a TOML file with :func:`~mechanism.load_scene`, change it with
:meth:`~mechanism.Scene.replace` (dotted keys such as ``"joints.C.clearance"``), store it
with :func:`~mechanism.save_scene` or :meth:`~mechanism.Scene.to_json`. ``docs/scenes.md``
lists every key with its unit and accepted range.
"""

from ._load import list_scenes, load_scene, scene_from_json, scene_from_toml
from ._messages import SceneError
from ._model import *  # noqa: F403
from ._model import __all__ as _model_all
from ._scene import Scene, save_scene, scene_from_dict, validate_scene

__all__ = [
    *_model_all,
    "Scene",
    "SceneError",
    "list_scenes",
    "load_scene",
    "save_scene",
    "scene_from_dict",
    "scene_from_json",
    "scene_from_toml",
    "validate_scene",
]

"""Scenes: mechanisms described as data (TOML), validated into frozen dataclasses."""

from ._model import *  # noqa: F403
from ._model import __all__ as _model_all

__all__ = list(_model_all)

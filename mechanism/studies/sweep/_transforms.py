"""Special grid keys of a sweep: values the scene has no key for, applied by a function.

The registry is built here, once, from the built-in keys (``"wear"``: before/after a
wear prediction; ``"samples_per_revolution"``: the output step T/n at the point's speed);
:func:`register_grid_transform` adds a user's key. Importing another module registers
nothing.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from .._wear_prediction import predict_wear
from ._revolution import revolution_time


@dataclass(frozen=True, kw_only=True)
class GridTransform:
    """A special grid key: ``apply(scene, value) -> scene`` for values the scene has no key for.

    ``apply`` runs on the worker (it may be expensive, e.g. a wear prediction) and must be a
    module-level function so it pickles. ``values``, when given, lists the accepted values
    (checked before anything runs).
    """

    name: str
    apply: Callable[[Any, Any], Any]
    values: tuple[Any, ...] | None = None
    long_name: str = ""
    units: str = "1"


def register_grid_transform(
    name: str,
    apply: Callable[[Any, Any], Any],
    *,
    values: Sequence[Any] | None = None,
    long_name: str | None = None,
    units: str = "1",
    overwrite: bool = False,
) -> GridTransform:
    """Register a special grid key handled by ``apply(scene, value) -> scene``.

    Special keys are applied after the dotted scene keys of the same point, in grid order.

    Examples
    --------
    >>> import mechanism
    >>> def frictionless(scene, value):
    ...     return scene.replace({"joints.C.friction.law": "none"}) if value else scene
    >>> t = mechanism.register_grid_transform(
    ...     "frictionless", frictionless, values=[False, True], overwrite=True)
    >>> "frictionless" in mechanism.grid_transforms()
    True
    """
    if not isinstance(name, str) or not name or "." in name:
        raise ValueError(
            f"a special grid key must be a non-empty name without dots (dotted keys are scene "
            f"keys); got {name!r}."
        )
    if name in _GRID_TRANSFORMS and not overwrite:
        raise ValueError(f"grid key {name!r} is already registered; pass overwrite=True.")
    if not callable(apply):
        raise TypeError(f"apply must be callable(scene, value) -> scene; got {apply!r}.")
    transform = GridTransform(
        name=name,
        apply=apply,
        values=None if values is None else tuple(values),
        long_name=long_name or name,
        units=units,
    )
    _GRID_TRANSFORMS[name] = transform
    return transform


def grid_transforms() -> Mapping[str, GridTransform]:
    """The registered special grid keys (read-only view)."""
    return MappingProxyType(_GRID_TRANSFORMS)


#: predict_wear settings of the grid value wear = "after" (see docs/wear.md): the paper
#: scene reaches the paper's peak-contact-force ratio near this amount of wear.
WEAR_AFTER_SETTINGS: dict[str, float] = {
    "updates": 4,
    "cycles_per_update": 1000.0,
    "max_depth_increment": 0.25,
    "settle_revolutions": 1.0,
}


def wear_transform(scene: Any, value: Any, **settings: Any) -> Any:
    """``"before"``: the scene as is; ``"after"``: the worn scene of
    :func:`mechanism.predict_wear` with :data:`WEAR_AFTER_SETTINGS` (overridden by
    ``settings``; register ``functools.partial(wear_transform, ...)`` to change them)."""
    if value == "before":
        return scene
    options = {**WEAR_AFTER_SETTINGS, **settings}
    return predict_wear(
        scene,
        updates=int(options["updates"]),
        cycles_per_update=float(options["cycles_per_update"]),
        max_depth_increment=float(options["max_depth_increment"]),
        settle_revolutions=float(options["settle_revolutions"]),
    ).worn_scene


def _output_step_transform(scene: Any, samples: Any) -> Any:
    """``samples_per_revolution``: output step T/samples at the point's own crank speed
    (T the drive period, or 2π/ω₀ at a motor's no-load speed ω₀)."""
    period = revolution_time(scene)
    if period is None:
        raise ValueError(
            "samples_per_revolution needs a periodic drive or a motor drive (a revolution "
            "to divide); set solver.output_step instead."
        )
    return scene.replace({"solver.output_step": period / int(samples)})


def _built_in() -> dict[str, GridTransform]:
    """The special grid keys every sweep knows, before any user registration."""
    return {
        "wear": GridTransform(
            name="wear",
            apply=wear_transform,
            values=("before", "after"),
            long_name="wear state of the clearance joints",
            units="1",
        ),
        "samples_per_revolution": GridTransform(
            name="samples_per_revolution",
            apply=_output_step_transform,
            long_name="output samples per crank revolution",
            units="1",
        ),
    }


# The registry: the built-in keys, then whatever register_grid_transform adds.
_GRID_TRANSFORMS: dict[str, GridTransform] = _built_in()

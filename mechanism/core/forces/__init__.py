"""Force elements of a scene: translational spring–damper–actuators, torsional
spring–dampers at revolute joints and applied loads with time and joint-coordinate
profiles (``docs/force-elements.md``). Scenes describe them as data (``[forces.NAME]``);
the model adds their compiled forces to each right-hand side when a scene has any."""

# compiled kernels and their table layouts, for the model; not public API
from ._initial import motor_speed_row
from ._kernels import (
    FO_COLUMNS,
    FO_COORD,
    FO_FORCE,
    FO_RATE,
    force_elements_add,
    force_elements_potential,
)
from ._tables import ForceTables, force_tables

__all__: list[str] = []

"""Bodies of a mechanism: rigid bodies (reference-point coordinates) and, with
flexible ANCF beams. Assembly uses their layouts; users describe bodies in scenes."""

from ._rigid import RigidLayout, rigid_bar_from_beam

__all__ = ["RigidLayout", "rigid_bar_from_beam"]

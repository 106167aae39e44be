"""The compiled model: a scene assembled once into flat tables the time loop evaluates."""

from ._assemble import KernelModel, Model, Workspace, assemble, initial_state

__all__ = ["KernelModel", "Model", "Workspace", "assemble", "initial_state"]

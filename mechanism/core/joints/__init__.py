"""Joints of a mechanism: ideal revolute, prismatic and fixed joints and drivers as
constraint rows, and the kinematics of revolute clearance joints (journal in a bearing).
The compiled kernels live in ``_kernels.py``; scenes describe joints as data."""

__all__: list[str] = []

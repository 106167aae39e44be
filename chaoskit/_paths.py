"""Names that become file names: one sanitiser for every place that does it.

A variable, figure or grid-point name comes from user data (a CSV header, a netCDF
variable, a sweep key) and may hold ``/``, ``..``, a drive letter or control characters.
Joined to a folder unchecked, it writes outside that folder; these helpers make it a
single, harmless path component.
"""

from __future__ import annotations

import hashlib
import re
import tempfile
from pathlib import Path

__all__ = ["folder_problem", "safe_filename", "unique_filename"]

_UNSAFE = re.compile(r"(?:[^A-Za-z0-9._+-]|\.{2,})+")


def safe_filename(name: str, *, replacement: str = "_", max_length: int = 80) -> str:
    """``name`` as one path component: runs of characters outside ``[A-Za-z0-9._+-]`` or of
    two or more dots become ``replacement``, and so does a leading dot (no hidden files, no
    ``..``); at most ``max_length`` characters; never empty.

    Examples
    --------
    >>> safe_filename("../../etc/passwd")
    '_etc_passwd'
    >>> safe_filename("eccentricity_x[joint=C]")
    'eccentricity_x_joint_C_'
    """
    if not isinstance(name, str):
        name = str(name)
    out = _UNSAFE.sub(replacement, name)
    stripped = out.lstrip(".")
    if stripped != out:
        out = replacement + stripped
    return out[:max_length] or replacement


def unique_filename(name: str, *, max_length: int = 80) -> str:
    """:func:`safe_filename`, plus 8 hex digits of the name's SHA-1 when sanitising changed
    it, so that two names that sanitise alike (``a/b`` and ``a_b``) keep apart.

    Examples
    --------
    >>> unique_filename("x")
    'x'
    >>> unique_filename("a/b")
    'a_b-3ec69c85'
    """
    safe = safe_filename(name, max_length=max_length)
    if safe == name:
        return safe
    return f"{safe}-{hashlib.sha1(str(name).encode('utf-8')).hexdigest()[:8]}"


def folder_problem(folder: str | Path, what: str) -> str | None:
    """Why no file can be written in ``folder`` (or made under its nearest existing
    parent), as one line starting with ``what``; None when one can.

    A temporary file is created and removed there, since permission bits do not tell: root
    passes every ``os.access`` test, yet can create nothing in ``/proc``. Nothing is left
    behind.
    """
    existing = Path(folder)
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        return f"{what}: {existing} is not a folder."
    try:
        with tempfile.TemporaryFile(dir=existing):
            pass
    except OSError as exc:
        return f"{what}: {existing} is not writable ({exc.strerror or exc})."
    return None

"""Compiled-kernel caches that always match the source they were compiled from.

numba's on-disk cache (``cache=True``) is keyed on the source file of the function it
compiled, not on the modules that function calls: when a kernel module changes, the cached
machine code of a loop in another module that inlined the old kernel is still loaded, and
silently runs the old code. :func:`refresh_jit_cache` closes that hole for a whole package:
it fingerprints every Python source of the package and, when the fingerprint differs from
the one recorded beside the caches, deletes the package's cached kernels (``*.nbi``,
``*.nbc`` in its ``__pycache__`` folders) before anything is compiled or loaded. The next
call of each kernel compiles it again from the current source.

Only standard-library imports here: the packages call it before importing any kernel.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path

__all__ = ["refresh_jit_cache"]

#: File beside a package's top-level caches that records the fingerprint of its sources.
STAMP = "jit-sources.sha256"


def _fingerprint(root: Path) -> str:
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(b"\0")
        digest.update(path.read_bytes())
        digest.update(b"\0")
    return digest.hexdigest()


def refresh_jit_cache(package: str | os.PathLike[str]) -> bool:
    """Delete a package's cached compiled kernels if any of its sources changed.

    Parameters
    ----------
    package
        The package folder, or any file in it (a package's ``__file__``).

    Returns
    -------
    bool
        True when caches were found stale and deleted (or none had been recorded yet),
        False when they match the sources or the folder cannot be written (an install
        without write access keeps numba's own cache location and rules).
    """
    root = Path(package)
    if root.is_file():
        root = root.parent
    cache = root / "__pycache__"
    stamp = cache / STAMP
    try:
        current = _fingerprint(root)
        if stamp.is_file() and stamp.read_text(encoding="ascii").strip() == current:
            return False
        for pattern in ("*.nbi", "*.nbc"):
            for path in root.rglob(pattern):
                if "__pycache__" in path.parts:
                    path.unlink(missing_ok=True)
        cache.mkdir(exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=cache, prefix=".jit-", suffix=".tmp")
        with os.fdopen(fd, "w", encoding="ascii") as fh:
            fh.write(current + "\n")
        os.replace(tmp, stamp)
    except OSError:
        return False
    return True

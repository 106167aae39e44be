"""Compiled-kernel caches: always in a folder that can be written, always matching the
source they were compiled from. :func:`refresh_jit_cache` does both for a package, before
any of its kernels is compiled or loaded.

**Where.** numba caches a kernel (``cache=True``) in ``NUMBA_CACHE_DIR`` when set, else in
the ``__pycache__`` folder beside its source, else in a user-wide folder
(``~/.cache/numba``); when none can be written — a read-only install with a read-only home
— numba refuses to decorate the kernel and the import fails. The package then has numba
cache in a private folder of the user (``$XDG_CACHE_HOME/chaoskit-numba``, else
``chaoskit-numba-<uid>`` in the system's temporary folder), by setting
``NUMBA_CACHE_DIR`` for this process and the processes it starts. The folder must be a
directory of the user's own that nobody else can write: numba's caches are pickled code,
and a shared temporary folder could hold anyone's. Where no folder can be had, the
package's kernels are compiled without a cache at every start, after one warning.

**Fresh.** numba's cache is keyed on the source file of the function it compiled, not on
the modules that function calls: when a kernel module changes, the cached machine code of
a loop in another module that inlined the old kernel is still loaded, and silently runs
the old code. :func:`refresh_jit_cache` fingerprints every Python source of the package
and, when the fingerprint differs from the one recorded beside the caches (wherever they
are), deletes the package's cached kernels (``*.nbi``, ``*.nbc``) before anything is
compiled or loaded. The next call of each kernel compiles it again from the current
source.

Nothing here compiles a kernel: the packages call it before importing any.
"""

from __future__ import annotations

import hashlib
import inspect
import os
import stat
import tempfile
import warnings
from pathlib import Path

from numba.core import config as numba_config
from numba.core.dispatcher import Dispatcher
from numba.misc.appdirs import AppDirs

__all__ = ["refresh_jit_cache"]

#: File beside a package's top-level caches that records the fingerprint of its sources.
STAMP = "jit-sources.sha256"
#: Name of the private cache folder in ``$XDG_CACHE_HOME`` or the temporary folder.
FALLBACK_NAME = "chaoskit-numba"

#: package folders whose kernels compile without a cache when numba finds no folder
_ROOTS: list[str] = []
#: whether the warning that kernels are not cached has been given (once per process)
_WARNED: list[bool] = [False]
_numba_enable_caching = Dispatcher.enable_caching


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


def _writable(folder: Path) -> bool:
    """Whether ``folder`` exists or can be made, and a file can be created in it (the
    test numba applies; it holds for root too, unlike permission bits)."""
    try:
        os.makedirs(folder, exist_ok=True)
        tempfile.TemporaryFile(dir=folder).close()
    except OSError:
        return False
    return True


def _private(folder: Path) -> bool:
    """Whether ``folder`` is, or could be made, a directory of this user's own that
    nobody else can write, and a file can be created in it."""
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        info = os.lstat(folder)
    except OSError:
        return False
    if not stat.S_ISDIR(info.st_mode):  # a symbolic link or a file
        return False
    if hasattr(os, "getuid") and (info.st_uid != os.getuid() or info.st_mode & 0o022):
        return False
    return _writable(folder)


def _fallback_folders() -> list[Path]:
    folders = []
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    if os.path.isabs(xdg):
        folders.append(Path(xdg) / FALLBACK_NAME)
    try:
        user = str(os.getuid()) if hasattr(os, "getuid") else os.getlogin()
        folders.append(Path(tempfile.gettempdir()) / f"{FALLBACK_NAME}-{user}")
    except OSError:  # no temporary folder can be written, or no user name
        pass
    return folders


def _numba_folder(folder: str) -> Path:
    """numba's cache subfolder for the sources in ``folder`` under an external cache
    folder (its ``_CacheLocator.get_suitable_cache_subpath``)."""
    path = os.path.abspath(folder)
    return Path(f"{os.path.basename(path)}_{hashlib.sha1(path.encode()).hexdigest()}")


def _cache_folder(root: Path) -> Path | None:
    """The folder numba caches the kernels of the package in ``root`` under, made
    writable if need be.

    Returns
    -------
    pathlib.Path or None
        The package folder itself when its ``__pycache__`` folders hold the caches;
        the external cache folder (``NUMBA_CACHE_DIR``, numba's user-wide folder, or
        the private fallback, which is then set as ``NUMBA_CACHE_DIR``) otherwise;
        None when no folder can be written (the kernels compile without a cache).
    """
    numba_config.reload_config()  # an environment changed since numba was imported
    given = getattr(numba_config, "CACHE_DIR", "")  # set from the environment
    if given and _writable(Path(given)):
        return Path(given)
    if _writable(root / "__pycache__"):
        return root
    user_wide = Path(AppDirs(appname="numba", appauthor=False).user_cache_dir)
    if _writable(user_wide):
        return user_wide
    for folder in _fallback_folders():
        if _private(folder):
            if given:
                warnings.warn(
                    f"NUMBA_CACHE_DIR={given} cannot be written; compiled kernels are "
                    f"cached in {folder} instead.",
                    RuntimeWarning,
                    stacklevel=3,
                )
            os.environ["NUMBA_CACHE_DIR"] = str(folder)
            numba_config.reload_config()
            return folder
    return None


def _cached_kernels(root: Path, base: Path) -> list[Path]:
    """The cache files (``*.nbi``, ``*.nbc``) of the package in ``root`` under ``base``."""
    if base == root:
        folders = {p.parent for p in root.rglob("*.py") if "__pycache__" not in p.parts}
        folders = {folder / "__pycache__" for folder in folders}
    else:
        sources = {str(p.parent) for p in root.rglob("*.py") if "__pycache__" not in p.parts}
        folders = {base / _numba_folder(folder) for folder in sources}
    return [path for folder in sorted(folders) for pattern in ("*.nbi", "*.nbc")
            for path in folder.glob(pattern)]  # fmt: skip


def _warn_uncached() -> None:
    if _WARNED[0]:
        return
    _WARNED[0] = True
    warnings.warn(
        "no writable folder for compiled-kernel caches (the package folder, numba's "
        "user cache, $XDG_CACHE_HOME, the temporary folder): kernels are compiled again "
        "at every start; set NUMBA_CACHE_DIR to a writable folder to keep them.",
        RuntimeWarning,
        stacklevel=4,
    )


def _enable_caching(self: Dispatcher) -> None:
    """numba's ``Dispatcher.enable_caching``, except that a kernel of a registered
    package for which numba finds no cache folder is compiled without a cache (one
    warning) rather than failing its module's import."""
    try:
        _numba_enable_caching(self)
    except RuntimeError:
        source = os.path.abspath(inspect.getfile(self.py_func))
        if not any(source.startswith(root) for root in _ROOTS):
            raise
        _warn_uncached()


def _register(root: Path) -> None:
    prefix = os.path.join(os.path.abspath(root), "")
    if prefix not in _ROOTS:
        _ROOTS.append(prefix)
    Dispatcher.enable_caching = _enable_caching  # type: ignore[method-assign]


def refresh_jit_cache(package: str | os.PathLike[str]) -> bool:
    """Give a package's compiled kernels a cache folder, and delete its cached kernels if
    any of its sources changed.

    Parameters
    ----------
    package
        The package folder, or any file in it (a package's ``__file__``).

    Returns
    -------
    bool
        True when caches were found stale and deleted (or none had been recorded yet),
        False when they match the sources or no cache folder can be written (the
        package's kernels are then compiled at every start, after one warning).
    """
    root = Path(package)
    if root.is_file():
        root = root.parent
    _register(root)
    base = _cache_folder(root)
    if base is None:
        _warn_uncached()
        return False
    if base == root:
        stamp = root / "__pycache__" / STAMP
    else:
        stamp = base / _numba_folder(str(root)) / STAMP
    try:
        current = _fingerprint(root)
        if stamp.is_file() and stamp.read_text(encoding="ascii").strip() == current:
            return False
        for path in _cached_kernels(root, base):
            path.unlink(missing_ok=True)
        stamp.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=stamp.parent, prefix=".jit-", suffix=".tmp")
        with os.fdopen(fd, "w", encoding="ascii") as fh:
            fh.write(current + "\n")
        os.replace(tmp, stamp)
    except OSError:
        return False
    return True

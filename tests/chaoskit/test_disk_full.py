"""A full disk: a clear OSError(ENOSPC), the old file kept, no temporary file, no crash.

Before the fix, writing a 6 MB trajectory to a full disk raised a RuntimeError from HDF5 and
the interpreter then died with a segmentation fault (exit 139) when h5netcdf flushed.
"""

from __future__ import annotations

import errno
import os
import shutil
import subprocess
import sys
import textwrap
from collections import namedtuple
from pathlib import Path

import numpy as np
import pytest

import chaoskit
from chaoskit import _io
from tests.conftest import REPO

BIG = chaoskit.load_trajectory(np.random.default_rng(0).standard_normal((200_000, 3)), dt=0.01)
SMALL = chaoskit.load_trajectory(np.sin(np.arange(100) * 0.1), dt=0.1)
_Usage = namedtuple("_Usage", "total used free")


def _only(path: Path) -> list[str]:
    return sorted(p.name for p in path.iterdir())


@pytest.mark.parametrize("suffix", [".nc", ".csv", ".npz"])
def test_too_little_free_space_is_refused_before_writing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, suffix: str
) -> None:
    target = chaoskit.save_trajectory(SMALL, tmp_path / f"run{suffix}")
    before = target.read_bytes()
    monkeypatch.setattr(_io.shutil, "disk_usage", lambda p: _Usage(10**7, 10**7 - 10**5, 10**5))
    with pytest.raises(OSError, match="not enough free space") as err:
        chaoskit.save_trajectory(BIG, target)
    assert err.value.errno == errno.ENOSPC and "\n" not in str(err.value)
    assert target.read_bytes() == before and _only(tmp_path) == [target.name]


def test_a_write_that_fails_midway_leaves_the_old_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = chaoskit.save_trajectory(SMALL, tmp_path / "run.nc")
    before = target.read_bytes()

    def full(self: Path, data: bytes) -> int:
        with self.open("wb") as fh:
            fh.write(data[:1000])
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Path, "write_bytes", full)
    with pytest.raises(OSError, match="No space left"):
        chaoskit.save_trajectory(BIG, target)
    monkeypatch.undo()
    assert target.read_bytes() == before and _only(tmp_path) == [target.name]


def test_a_real_full_disk_gives_an_error_not_a_segfault(tmp_path: Path) -> None:
    """On a 1 MB tmpfs (needs root to mount; skipped otherwise)."""
    disk = tmp_path / "full"
    disk.mkdir()
    if os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("mounting a tmpfs needs root")
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(disk)], capture_output=True
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {mounted.stderr.decode().strip()}")
    try:
        script = textwrap.dedent(
            f"""
            import gc, numpy as np, chaoskit
            from chaoskit import _io
            ds = chaoskit.load_trajectory(np.zeros((200_000, 3)) + np.arange(3), dt=0.01)
            for check in (True, False):
                if not check:  # the space check passes (e.g. a race): the write itself fails
                    _io.check_free_space = lambda folder, nbytes: None
                try:
                    chaoskit.save_trajectory(ds, {str(disk / "x.nc")!r})
                except OSError as exc:
                    print("OSError", exc.errno)
            gc.collect()
            print("alive")
            """
        )
        env = {**os.environ, "PYTHONPATH": str(REPO)}
        proc = subprocess.run(
            [sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=300
        )
        assert proc.returncode == 0, (proc.returncode, proc.stderr[-2000:])
        assert proc.stdout.split() == ["OSError", "28", "OSError", "28", "alive"]
        assert list(disk.iterdir()) == []
    finally:
        subprocess.run(["umount", str(disk)], capture_output=True)

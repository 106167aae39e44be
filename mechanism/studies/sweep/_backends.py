"""Where the points of a sweep run: in this process (``"serial"``) or on
dask.distributed."""

from __future__ import annotations

import contextlib
import logging
import os
import uuid
from collections.abc import Iterator, Sequence
from typing import Any

from ._point import PointTask, record_lost_point, run_point


def _progress_bar(total: int, enabled: bool) -> Any:
    from tqdm.auto import tqdm

    return tqdm(total=total, desc="sweep", unit="point", disable=not enabled)


def run_serial(tasks: Sequence[PointTask], progress: bool) -> list[tuple[str, str]]:
    """Run the points one after the other in this process; ``(point_id, status)`` each."""
    done = []
    with _progress_bar(len(tasks), progress) as bar:
        for task in tasks:
            done.append(run_point(task))
            bar.update(1)
    return done


@contextlib.contextmanager
def dask_client(client: Any, n_workers: int | None, n_tasks: int) -> Iterator[Any]:
    """The dask ``Client`` a sweep runs on, as a context manager.

    ``client`` None starts a ``LocalCluster`` of ``n_workers`` single-threaded processes
    (default: CPU count, at most ``n_tasks``) and closes it on exit; an address connects to
    that scheduler (closing leaves it running); a ``Client`` is yielded unchanged. Studies
    that run several sweeps open one backend here and pass it as ``client=``.
    """
    from distributed import Client, LocalCluster

    if client is None:
        n = n_workers if n_workers is not None else min(os.cpu_count() or 1, n_tasks)
        with (
            LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address="127.0.0.1:0",  # any free local port: no clash on 8787
                silence_logs=logging.ERROR,
            ) as cluster,
            Client(cluster) as owned,
        ):
            yield owned
    elif isinstance(client, str):
        with Client(client) as connected:  # closing it leaves the remote scheduler running
            yield connected
    else:
        yield client


def run_dask(
    tasks: Sequence[PointTask], client: Any, n_workers: int | None, progress: bool
) -> list[tuple[str, str]]:
    """Run the points on dask (:func:`dask_client`); a task that never returns is
    recorded as a failed point. ``(point_id, status)`` each, in completion order."""
    from distributed import as_completed

    done = []
    with dask_client(client, n_workers, len(tasks)) as c:
        run = uuid.uuid4().hex[:8]
        futures = {
            c.submit(run_point, task, key=f"sweep-{task.point_id}-{run}", pure=False): task
            for task in tasks
        }
        with _progress_bar(len(tasks), progress) as bar:
            for future in as_completed(futures):
                try:
                    done.append(future.result())
                except Exception as exc:  # KilledWorker, a store that cannot be written, ...
                    done.append(record_lost_point(futures[future], exc))
                bar.update(1)
                future.release()
    return done

"""Progress of long analyses: a stage bar that the estimators advance when one is active.

Library calls stay silent: :func:`stage` does nothing unless a caller (``analyze`` or
``classify_variables`` with ``progress=True``) opened :func:`stage_bar`. The bar appears only
when the work lasts longer than ``PROGRESS_DELAY`` seconds, and names the variable and the
estimator running, so a long analysis never looks hung.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

__all__ = ["PROGRESS_DELAY", "STAGES", "finish_item", "stage", "stage_bar"]

#: Seconds of work before the bar is shown.
PROGRESS_DELAY = 2.0
#: The estimators of one classification, in the order ``classify`` runs them.
STAGES = ("delay", "dimension", "rosenstein", "wolf", "zero-one", "surrogates")

_BAR: ContextVar[Any] = ContextVar("chaoskit_progress_bar", default=None)


@contextmanager
def stage_bar(n_items: int, *, desc: str) -> Iterator[Any]:
    """A tqdm bar over ``n_items × len(STAGES)`` stages, active for :func:`stage` inside."""
    from tqdm.auto import tqdm

    bar = tqdm(total=n_items * len(STAGES), desc=desc, unit="stage", delay=PROGRESS_DELAY)
    token = _BAR.set(bar)
    try:
        yield bar
    finally:
        _BAR.reset(token)
        bar.close()


def stage(name: str) -> None:
    """Advance the active bar by one stage and show ``name`` (no-op without a bar)."""
    bar = _BAR.get()
    if bar is not None:
        bar.set_postfix_str(name, refresh=False)
        bar.update(1)


def finish_item(bar: Any, done_items: int, label: str) -> None:
    """Put the bar at the end of item ``done_items`` whatever stages it skipped."""
    bar.n = min(done_items * len(STAGES), bar.total)
    bar.set_description(label, refresh=False)
    bar.refresh()

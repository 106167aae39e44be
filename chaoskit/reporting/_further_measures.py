"""The "Further measures" section of a report: D2, RQA, spectrum, SampEn, DFA, Hurst."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import pandas as pd

from .._measure_registry import (
    LABELS,
    RQA_MAX_SAMPLES,
    measure_figures,
    measures_for_verdicts,
    measures_row,
)
from ._content import ReportTable

SECTION = "Further measures"


def measure_items(
    states: Sequence[Any],
    specs: Sequence[Any],
    names: Sequence[str],
    put: Callable[..., None],
    draw: Callable[..., Any],
    *,
    rng: int = 0,
) -> None:
    """Compute the measures for every state and variable; add one table and the figures."""
    results = {
        st.label: measures_for_verdicts(st.view, st.verdicts, names, rng=rng) for st in states
    }
    rows = {
        (alias, label): measures_row(res[alias]) for label, res in results.items() for alias in res
    }
    if not rows:
        return
    frame = pd.DataFrame(rows).T
    frame.index = frame.index.set_names(["variable", "state"])
    failures = [
        f"{alias} ({label}) {measure}: {value}"
        for label, res in results.items()
        for alias, per in res.items()
        for measure, value in per.items()
        if isinstance(value, str)
    ]
    put(
        ReportTable(
            caption=(
                "Further measures per variable and state: correlation dimension D2 with the "
                "range of its local slopes over the scaling region, recurrence quantification "
                f"(RR = 5 %, the verdict's embedding, at most the last {RQA_MAX_SAMPLES} "
                "samples), the two largest exponents and the sum of the Lyapunov spectrum "
                "(per unit of the sampling interval's units) with the number of exponents "
                "the embedding check does not confirm, sample entropy, DFA α and Hurst H."
            ),
            data=frame,
            intervals={"d2": ("d2_low", "d2_high")} if "d2" in frame else {},
            labels=LABELS,
            layout="long" if frame.shape[1] > 8 else "wide",
            notes="; ".join(failures),
            section=SECTION,
        )
    )
    for spec in specs:
        alias = spec.alias
        per_state = [(st.label, results[st.label].get(alias, {})) for st in states]
        kinds: dict[str, str] = {}
        for _, res in per_state:
            for kind, caption, _ in measure_figures(res):
                kinds.setdefault(kind, caption)
        for kind, caption in kinds.items():
            n = len(per_state)
            ncols = min(n, 3)

            def panels(
                axes: Any, kind: str = kind, per_state: list = per_state, alias: str = alias
            ) -> None:
                for k, ax in enumerate(axes.flat):
                    if k >= len(per_state):
                        ax.set_visible(False)
                        continue
                    label, res = per_state[k]
                    found = {kd: fn for kd, _, fn in measure_figures(res)}
                    if kind in found:
                        found[kind](ax)
                    ax.set_title(f"{alias}: {label}", fontsize=9)

            put(
                draw(
                    panels,
                    nrows=math.ceil(n / ncols),
                    ncols=ncols,
                    section=SECTION,
                    name=f"{kind.replace('_', '-')}-{alias}",
                    caption=f"{caption[0].upper()}{caption[1:]} of {alias} ({spec.spec}).",
                )
            )

"""The shape of the reporting API: option objects of ``report``, parameter counts, layering.

``report`` groups what a caller adds (:class:`ReportExtras`) and its finer settings
(:class:`ReportOptions`) into two frozen objects; their fields are still accepted as
keywords, and both spellings make the same report. The reporting modules form no import
cycle, not even through ``TYPE_CHECKING`` imports, and ``chaoskit.plot`` (the lower layer)
never imports ``chaoskit.reporting``.
"""

from __future__ import annotations

import inspect
import re

import numpy as np
import pandas as pd
import pytest

import chaoskit
from chaoskit import plot, reporting
from chaoskit.reporting import ReportExtras, ReportOptions, ReportTable
from tests.conftest import REPO
from tests.test_layout import cycles, imports, source_files

_STAMP = re.compile(r"\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}\+00:00")


def _table() -> ReportTable:
    return ReportTable(
        caption="Response metrics.",
        data=pd.DataFrame({"peak force": [9500.0, 21000.0]}, index=["before", "after"]),
        section="Response metrics",
    )


def _page(rep: chaoskit.Report) -> str:
    return _STAMP.sub("TIME", rep.to_markdown(figures="embed"))


def test_no_public_reporting_or_plot_function_takes_more_than_12_parameters() -> None:
    for module in (reporting, plot):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isfunction(obj):
                n = len(inspect.signature(obj).parameters)
                assert n <= 12, f"{module.__name__}.{name} takes {n} parameters"
    assert len(inspect.signature(chaoskit.report).parameters) == 12


def test_fields_as_keywords_or_in_the_objects_make_the_same_report() -> None:
    settings = {"revolutions": 10}
    by_keyword = chaoskit.report(
        tables=[_table()], parameters=settings, command="study", rng=3, title="demo"
    )
    by_object = chaoskit.report(
        title="demo",
        extras=ReportExtras(tables=[_table()], parameters=settings, command="study"),
        options=ReportOptions(rng=3),
    )
    assert _page(by_keyword) == _page(by_object)
    assert [t.caption for t in by_object.tables][:2] == [
        "Response metrics.",
        "Provenance: when and how the report was made, and the package versions.",
    ]
    assert by_object.table("Provenance").data.loc["command", "value"] == "study"


def test_a_field_given_twice_or_unknown_is_refused() -> None:
    with pytest.raises(ValueError) as err:
        chaoskit.report(tables=[_table()], extras=ReportExtras(tables=[_table()]))
    assert (
        str(err.value) == "give tables either in extras= (ReportExtras) or as keywords, not both."
    )
    with pytest.raises(ValueError) as err:
        chaoskit.report(rng=1, progress=True, options=ReportOptions())
    assert str(err.value) == (
        "give rng, progress either in options= (ReportOptions) or as keywords, not both."
    )
    with pytest.raises(ValueError) as err:
        chaoskit.report(extras={"tables": []})
    assert str(err.value) == "extras must be a ReportExtras; got dict."
    with pytest.raises(TypeError) as err:
        chaoskit.report(tabels=[_table()])
    assert str(err.value) == "report() got an unexpected keyword argument 'tabels'"


def test_option_objects_are_frozen() -> None:
    extras = ReportExtras(reference_name="paper")
    with pytest.raises(AttributeError):
        extras.reference_name = "other"  # type: ignore[misc]
    assert ReportOptions().n_surrogates == 19
    assert ReportOptions().markdown_figures == "files"


def test_reporting_and_plot_have_no_import_cycle_even_through_type_checking() -> None:
    known = set(source_files(REPO, ("chaoskit",)))
    scope = ("chaoskit.reporting", "chaoskit.plot")
    graph: dict[str, set[str]] = {m: set() for m in known if m.startswith(scope)}
    for imp in imports(REPO, ("chaoskit",)):
        if imp.local or imp.module not in graph:
            continue  # type-only imports are kept: they count here
        graph[imp.module] |= {t for t in imp.targets if t in graph and t != imp.module}
    assert cycles(graph) == []
    upward = [(m, t) for m, ts in graph.items() if m.startswith("chaoskit.plot") for t in ts]
    assert [e for e in upward if e[1].startswith("chaoskit.reporting")] == []


def test_panel_figure_blank_panel_and_label_axes() -> None:
    seen = {}

    def draw(axes: np.ndarray) -> None:
        seen["shape"] = axes.shape
        plot.blank_panel(axes[0, 0], "no data")
        plot.label_axes(axes[0, 1], "x [m]", "dx/dt [m s-1]")

    fig = plot.panel_figure(draw, nrows=1, ncols=2, panel=(4.0, 3.0))
    assert seen["shape"] == (1, 2)
    assert tuple(fig.get_size_inches()) == pytest.approx((8.0, 3.0), abs=1e-12)
    first, second = fig.axes
    assert list(first.get_xticks()) == [] and first.texts[0].get_text() == "no data"
    assert (second.get_xlabel(), second.get_ylabel()) == ("x [m]", "dx/dt [m s-1]")

"""The shape of the reporting API: option objects of ``report``, parameter counts, layering.

``report`` groups what a caller adds (:class:`ReportExtras`) and its finer settings
(:class:`ReportOptions`) into two frozen objects; their fields are still accepted as
keywords, and both spellings make the same report. The reporting modules form no import
cycle, not even through ``TYPE_CHECKING`` imports, and ``chaoskit.plot`` (the lower layer)
never imports ``chaoskit.reporting``.
"""

from __future__ import annotations

import inspect

import numpy as np
import pandas as pd
import pytest

import chaoskit
from chaoskit import plot, reporting
from chaoskit.reporting import ReportExtras, ReportOptions, ReportTable
from tests.conftest import REPO
from tests.test_layout import cycles, imports, source_files


def _table() -> ReportTable:
    return ReportTable(
        caption="Response metrics.",
        data=pd.DataFrame({"peak force": [9500.0, 21000.0]}, index=["before", "after"]),
        section="Response metrics",
    )


def test_no_public_reporting_or_plot_function_takes_more_than_12_parameters() -> None:
    for module in (reporting, plot):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isfunction(obj):
                n = len(inspect.signature(obj).parameters)
                assert n <= 12, f"{module.__name__}.{name} takes {n} parameters"
    assert len(inspect.signature(chaoskit.report).parameters) == 11


def test_the_fields_of_the_option_objects_make_the_report() -> None:
    settings = {"revolutions": 10}
    by_object = chaoskit.report(
        title="demo",
        extras=ReportExtras(tables=[_table()], parameters=settings, command="study"),
        options=ReportOptions(rng=3),
    )
    assert [t.caption for t in by_object.tables][:2] == [
        "Response metrics.",
        "Provenance: when and how the report was made, and the package versions.",
    ]
    assert by_object.table("Provenance").data.loc["command", "value"] == "study"


def test_a_field_given_as_a_keyword_names_its_object() -> None:
    """A field of the option objects is not a keyword of report: the TypeError says which
    object holds it, on one line."""
    with pytest.raises(TypeError) as err:
        chaoskit.report(tables=[_table()], extras=ReportExtras(tables=[_table()]))
    assert str(err.value) == (
        "report() got an unexpected keyword argument 'tables'; pass it in the ReportExtras "
        "object: extras=ReportExtras(tables=...)."
    )
    with pytest.raises(TypeError) as err:
        chaoskit.report(rng=1)
    assert str(err.value) == (
        "report() got an unexpected keyword argument 'rng'; pass it in the ReportOptions "
        "object: options=ReportOptions(rng=...)."
    )


def test_a_wrong_object_or_an_unknown_keyword_is_refused() -> None:
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

"""The content of a report: tables (pandas DataFrames), figures (PNG bytes), code blocks,
sections, and the number format every table uses.

Every table and figure carries a caption. A table keeps its numbers in ``data``; the text
that both renderers print comes from :meth:`ReportTable.display`, so the HTML page and the
Markdown twin show the same strings.
"""

from __future__ import annotations

import io
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import pandas as pd

__all__ = [
    "ReportCode",
    "ReportFigure",
    "ReportSection",
    "ReportTable",
    "format_number",
]

MISSING = "—"


def format_number(value: Any, digits: int = 4) -> str:
    """A number with ``digits`` significant digits, without exponent between 1e-3 and 1e7.

    NaN and None print as an em dash, booleans as yes/no, text as it is.

    Examples
    --------
    >>> format_number(23330.0), format_number(0.0042), format_number(float("nan"))
    ('23330', '0.0042', '—')
    """
    if value is None:
        return MISSING
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        v = float(value)
        if not math.isfinite(v):
            return MISSING if math.isnan(v) else ("∞" if v > 0 else "−∞")
        if v == 0.0:
            return "0"
        mag = abs(v)
        if 1e-3 <= mag < 1e7:
            decimals = max(digits - 1 - math.floor(math.log10(mag)), 0)
            text = f"{v:.{decimals}f}"
            if "." in text:
                text = text.rstrip("0").rstrip(".")
            return "0" if text in ("-0", "") else text
        return f"{v:.{digits}g}"
    if isinstance(value, float) and math.isnan(value):
        return MISSING
    text = str(value)
    return MISSING if text in ("", "nan", "None", "<NA>") else text


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )


def _difference(ours: Any, theirs: Any) -> str:
    """100 (|ours| − |theirs|)/|theirs| for numbers; same/differs for text.

    Magnitudes are compared, so a torque of −184.6 against −478.5 reads −61.4 (ours is
    smaller), not +61.4; when the signs differ the text says so.
    """
    if _is_number(ours) and _is_number(theirs):
        a, b = float(ours), float(theirs)
        if not (math.isfinite(a) and math.isfinite(b)) or b == 0.0:
            return MISSING
        text = f"{100.0 * (abs(a) - abs(b)) / abs(b):+.1f}"
        return text if a * b >= 0.0 else f"{text}, opposite sign"
    if theirs is None or (isinstance(theirs, float) and math.isnan(theirs)):
        return MISSING
    if ours is None or (isinstance(ours, float) and math.isnan(ours)):
        return MISSING
    return "same" if str(ours).strip().lower() == str(theirs).strip().lower() else "differs"


def _slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")[:48] or "item"


@dataclass(frozen=True, kw_only=True, eq=False)
class ReportTable:
    """A captioned table, optionally beside reference values (e.g. a paper's).

    Parameters
    ----------
    caption
        What the table shows, units included where the column labels do not say.
    data
        Our values; rows and columns labelled (a MultiIndex on rows is allowed).
    reference
        Values to compare with, labelled like ``data`` (same row and column labels; rows
        or columns it lacks show a dash). Each compared column is shown as
        "ours | <reference_name> | difference (%)", the difference of magnitudes
        :math:`100\\,(|x_\\text{ours}| - |x_\\text{ref}|)/|x_\\text{ref}|` ("opposite sign"
        added when the signs differ; for text: same or differs).
    reference_name
        Header of the reference values, e.g. ``"paper"`` or ``"reference"``.
    ratio
        ``(numerator_row, denominator_row)``: add a row with their ratio (for ours and the
        reference), e.g. ``("after wear", "before wear")``. Needs a single-level row index.
    intervals
        ``{column: (low_column, high_column)}``: printed as ``value [low, high]``; the
        low and high columns are not shown on their own.
    labels
        Display labels of the columns (e.g. with units); default: the column names.
    layout
        ``"wide"`` (one row per data row, compared columns in groups of three) or
        ``"long"`` (one row per data row and column: handy for many columns).
    digits
        Significant digits of our numbers (reference values print with up to 6).
    formats
        ``{column: format spec}`` for columns that need a fixed format instead of
        ``digits``, e.g. ``{"confidence": ".2f"}`` (interval bounds follow their column).
    marks
        ``{(row label, column): marker}``: a footnote marker (e.g. ``"†"``) appended to
        that cell; say what it means in ``notes``.
    notes
        Text shown under the table (e.g. why a value differs from the paper).
    section
        Heading of the report section that holds the table.
    number
        Table number, set when the report is assembled.
    """

    caption: str
    data: pd.DataFrame
    reference: pd.DataFrame | None = None
    reference_name: str = "reference"
    ratio: tuple[str, str] | None = None
    intervals: Mapping[str, tuple[str, str]] = field(default_factory=dict)
    labels: Mapping[str, str] = field(default_factory=dict)
    layout: Literal["wide", "long"] = "wide"
    digits: int = 4
    formats: Mapping[str, str] = field(default_factory=dict)
    marks: Mapping[tuple[Any, str], str] = field(default_factory=dict)
    notes: str = ""
    section: str = "Response metrics"
    number: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.caption, str) or not self.caption.strip():
            raise ValueError("caption must be a non-empty string.")
        if not isinstance(self.data, pd.DataFrame):
            raise ValueError(f"data must be a pandas DataFrame; got {type(self.data).__name__}.")
        if self.data.columns.nlevels != 1:
            raise ValueError("data must have one level of column labels (flatten them first).")
        if self.reference is not None and not isinstance(self.reference, pd.DataFrame):
            raise ValueError(
                f"reference must be a pandas DataFrame; got {type(self.reference).__name__}."
            )
        if self.layout not in ("wide", "long"):
            raise ValueError(f"layout must be 'wide' or 'long'; got {self.layout!r}.")
        if not isinstance(self.digits, int) or not 1 <= self.digits <= 15:
            raise ValueError(f"digits must be an integer in [1, 15]; got {self.digits!r}.")
        for col, pair in self.intervals.items():
            missing = [c for c in (col, *pair) if c not in self.data.columns]
            if missing:
                raise ValueError(f"intervals name columns {missing} that data does not have.")
        if self.ratio is not None:
            if self.data.index.nlevels != 1:
                raise ValueError("ratio= needs a single-level row index.")
            missing = [r for r in self.ratio if r not in self.data.index]
            if len(self.ratio) != 2 or missing:
                raise ValueError(
                    f"ratio must name two rows of data; missing {missing} "
                    f"(rows: {list(self.data.index)})."
                )
        for col, spec in self.formats.items():
            if col not in self.data.columns:
                raise ValueError(f"formats names the column {col!r} that data does not have.")
            try:
                format(0.5, spec)
            except (TypeError, ValueError):
                raise ValueError(
                    f"formats[{col!r}] = {spec!r} is not a format spec for numbers (e.g. '.2f')."
                ) from None
        for key, mark in self.marks.items():
            if not (isinstance(key, tuple) and len(key) == 2):
                raise ValueError(f"marks keys must be (row label, column) pairs; got {key!r}.")
            row, col = key
            if col not in self.data.columns or row not in self.data.index:
                raise ValueError(f"marks names the cell {key!r} that data does not have.")
            if not isinstance(mark, str) or not mark.strip():
                raise ValueError(f"marks[{key!r}] must be a non-empty string; got {mark!r}.")
        # Our own copies: the report is frozen, so its tables must not change under it.
        object.__setattr__(self, "data", self.data.copy())
        if self.reference is not None:
            object.__setattr__(self, "reference", self.reference.copy())
        object.__setattr__(self, "intervals", dict(self.intervals))
        object.__setattr__(self, "labels", dict(self.labels))
        object.__setattr__(self, "formats", dict(self.formats))
        object.__setattr__(self, "marks", dict(self.marks))

    # ------------------------------------------------------------------ display
    def _frames(self) -> tuple[pd.DataFrame, pd.DataFrame | None]:
        data = self.data
        ref = None
        if self.reference is not None:
            ref = self.reference.reindex(index=data.index)
        if self.ratio is not None:
            top, bottom = self.ratio
            name = f"ratio {top} / {bottom}"

            def ratio_row(frame: pd.DataFrame) -> pd.DataFrame:
                row = {}
                for col in frame.columns:
                    a, b = frame.at[top, col], frame.at[bottom, col]
                    row[col] = (
                        float(a) / float(b)
                        if _is_number(a) and _is_number(b) and float(b) != 0.0
                        else float("nan")
                    )
                return pd.DataFrame([row], index=pd.Index([name], name=frame.index.name))

            data = pd.concat([data.astype(object), ratio_row(data).astype(object)])
            if ref is not None:
                ref = pd.concat([ref.astype(object), ratio_row(ref).astype(object)])
        return data, ref

    def shown_columns(self) -> list[str]:
        """Columns of ``data`` shown as columns (interval bounds are folded into values)."""
        hidden = {c for pair in self.intervals.values() for c in pair}
        return [c for c in self.data.columns if c not in hidden]

    def _number(self, value: Any, col: str) -> str:
        spec = self.formats.get(col)
        if spec is not None and _is_number(value) and math.isfinite(float(value)):
            return format(float(value), spec)
        return format_number(value, self.digits)

    def _cell(self, frame: pd.DataFrame, row: Any, col: str) -> str:
        value = frame.at[row, col]
        text = self._number(value, col)
        if col in self.intervals and text != MISSING:
            lo, hi = (self._number(frame.at[row, c], col) for c in self.intervals[col])
            if lo != MISSING or hi != MISSING:
                text = f"{text} [{lo}, {hi}]"
        mark = self.marks.get((row, col))
        return f"{text} {mark}" if mark else text

    def display(self) -> pd.DataFrame:
        """The table as printed: strings, two header levels (column, ours/reference/diff).

        The row index is kept (as strings); the second column level is ``""`` for columns
        without a reference value.
        """
        data, ref = self._frames()
        compared = {c for c in self.shown_columns() if ref is not None and c in ref.columns}
        label = {c: str(self.labels.get(c, c)) for c in self.shown_columns()}
        index = pd.MultiIndex.from_tuples(
            [tuple(str(v) for v in (r if isinstance(r, tuple) else (r,))) for r in data.index],
            names=[str(n) if n is not None else "" for n in data.index.names],
        )
        if index.nlevels == 1:
            index = index.get_level_values(0)
        ref_name = self.reference_name
        if self.layout == "long":
            rows, keys = [], []
            for r, key in zip(data.index, index, strict=True):
                for c in self.shown_columns():
                    key_t = key if isinstance(key, tuple) else (key,)
                    keys.append((*key_t, label[c]))
                    cells = [self._cell(data, r, c)]
                    if ref is not None:
                        theirs = ref.at[r, c] if c in compared else None
                        cells += [
                            format_number(theirs, 6),
                            _difference(data.at[r, c], theirs) if c in compared else MISSING,
                        ]
                    rows.append(cells)
            names = [*list(index.names), "quantity"]
            cols = ["ours", ref_name, "difference (%)"] if ref is not None else ["value"]
            return pd.DataFrame(
                rows,
                index=pd.MultiIndex.from_tuples(keys, names=names),
                columns=pd.MultiIndex.from_tuples([(c, "") for c in cols]),
            )
        columns: list[tuple[str, str]] = []
        for c in self.shown_columns():
            if c in compared:
                columns += [(label[c], "ours"), (label[c], ref_name), (label[c], "difference (%)")]
            else:
                columns.append((label[c], ""))
        rows = []
        for r in data.index:
            row: list[str] = []
            for c in self.shown_columns():
                row.append(self._cell(data, r, c))
                if c in compared:
                    assert ref is not None
                    theirs = ref.at[r, c]
                    row += [format_number(theirs, 6), _difference(data.at[r, c], theirs)]
            rows.append(row)
        return pd.DataFrame(rows, index=index, columns=pd.MultiIndex.from_tuples(columns))


@dataclass(frozen=True, kw_only=True)
class ReportFigure:
    """A captioned figure stored as PNG bytes.

    Parameters
    ----------
    caption
        What the figure shows.
    png
        The image, PNG-encoded.
    name
        File stem used when the Markdown twin writes the image next to it.
    section
        Heading of the report section that holds the figure.
    number
        Figure number, set when the report is assembled.
    """

    caption: str
    png: bytes
    name: str = "figure"
    section: str = "Figures"
    number: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.caption, str) or not self.caption.strip():
            raise ValueError("caption must be a non-empty string.")
        if not isinstance(self.png, (bytes, bytearray)) or not bytes(self.png).startswith(
            b"\x89PNG\r\n\x1a\n"
        ):
            raise ValueError("png must be the bytes of a PNG image.")
        object.__setattr__(self, "png", bytes(self.png))
        object.__setattr__(self, "name", _slug(self.name))

    @classmethod
    def from_matplotlib(
        cls,
        figure: Any,
        *,
        caption: str,
        name: str = "figure",
        section: str = "Figures",
        dpi: int = 100,
    ) -> ReportFigure:
        """Render a matplotlib Figure to PNG (the figure is not closed)."""
        buffer = io.BytesIO()
        figure.savefig(buffer, format="png", dpi=dpi, metadata={"Software": None})
        return cls(caption=caption, png=buffer.getvalue(), name=name, section=section)


@dataclass(frozen=True, kw_only=True)
class ReportCode:
    """A captioned block of preformatted text (e.g. the scene as JSON)."""

    caption: str
    text: str
    language: str = ""
    section: str = "Parameters and provenance"


@dataclass(frozen=True, kw_only=True, eq=False)
class ReportSection:
    """A heading, an optional paragraph and its tables, figures and code blocks in order.

    ``text`` is printed under the heading, before the items (keep it to what the reader
    needs first); ``footer`` after the items (settings, costs and other notes).
    """

    title: str
    items: tuple[ReportTable | ReportFigure | ReportCode, ...] = ()
    text: str = ""
    footer: str = ""

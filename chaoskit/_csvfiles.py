"""Reading CSV and other delimited text files (``.csv``, ``.txt``, ``.tsv``) into Datasets.

The delimiter is detected (``,``, tab, ``;``, ``|`` or blanks); title lines are skipped with
``skip_rows`` and a decimal comma is read with ``decimal=","``, and the error messages say
which of the two a file needs. A ``# chaoskit-attrs: {...}`` line above the header (as
:func:`chaoskit.save_trajectory` writes it) restores the attributes. The table is then
indexed by :func:`chaoskit._tables.from_table`.
"""

from __future__ import annotations

import io
import json
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from ._contract import ParameterError
from ._tables import MISSING_WORDS, Origin, from_table, one_line

__all__ = ["ATTRS_LINE", "apply_payload", "read_csv"]


ATTRS_LINE = "# chaoskit-attrs: "
_DELIMITERS = (",", "\t", ";", "|")
_DELIMITER_NAMES = {",": "','", "\t": "tab", ";": "';'", "|": "'|'", r"\s+": "blank"}
_LOAD = "load_trajectory"
_lit = ParameterError.literal


def apply_payload(ds: xr.Dataset, payload: dict[str, Any]) -> xr.Dataset:
    ds.attrs.update(payload.get("global", {}))
    for name, attrs in payload.get("variables", {}).items():
        if name in ds.variables:
            ds[name].attrs.update(attrs)
    return ds


def _looks_like_header(frame: pd.DataFrame) -> bool:
    """True if the first row holds words only and some later row a number (a header below
    a title line that has as many fields as the header)."""
    if len(frame) < 2 or frame.shape[1] < 2:
        return False
    first = frame.iloc[0].astype(str).str.strip()
    if first.str.lower().isin(MISSING_WORDS).any():
        return False
    words = pd.to_numeric(first, errors="coerce").isna().all()
    later = pd.to_numeric(frame.iloc[1].astype(str).str.strip(), errors="coerce").notna().any()
    return bool(words and later)


def _consistent(lines: list[str], seps: Sequence[str]) -> str | None:
    """The delimiter every line holds equally often (> 0), else blanks if every line splits
    into the same number (> 1) of fields, else None."""
    for sep in seps:
        counts = {line.count(sep) for line in lines}
        if len(counts) == 1 and counts.pop() > 0:
            return sep
    fields = {len(line.split()) for line in lines}
    if len(fields) == 1 and fields.pop() > 1:
        return r"\s+"
    return None


def _fields(line: str, sep: str) -> int:
    return len(line.split()) if sep == r"\s+" else line.count(sep) + 1


def _delimiter(
    lines: list[str], *, what: str, decimal: str, first_line: int, skip_rows: int
) -> str:
    """The column delimiter of a header and its first data lines; "," for one column.

    A delimiter counts if every line has the same, non-zero number of it; failing all,
    whitespace if every line splits into the same number (> 1) of fields. When only the
    lines below the first agree, the first is taken for a title and the error says so.
    """
    seps = [s for s in _DELIMITERS if not (decimal == "," and s == ",")]
    sep = _consistent(lines, seps)
    if sep is not None:
        return sep
    if decimal == "," and _consistent(lines, [","]) == ",":
        raise ParameterError(
            f"{_lit(what)} is comma-separated, so its decimal mark cannot be a comma; leave "
            "out {decimal=,}.",
            function=_LOAD,
        )
    if all(len(line.split()) <= 1 and not any(d in line for d in _DELIMITERS) for line in lines):
        return ","  # one column
    for k in range(1, min(4, len(lines) - 1)):
        below = _consistent(lines[k:], seps)
        if below is not None:
            n_first, n_below = _fields(lines[0], below), _fields(lines[k], below)
            title = "line is a title" if k == 1 else f"{k} lines are a title"
            raise ParameterError(
                f"cannot tell the column delimiter of {_lit(what)}: its first line (line "
                f"{first_line}) has {n_first} field(s) where the lines below have {n_below} "
                f"({_DELIMITER_NAMES[below]}-separated); if the first {title}, skip "
                f"{'it' if k == 1 else 'them'} with {{skip_rows={skip_rows + k}}}{{to}}.",
                function=_LOAD,
            )
    raise ValueError(
        f"cannot tell the column delimiter of {what}: its first lines do not all hold the "
        "same number of ',', tab, ';', '|' or blanks; write one column per variable, "
        "comma-separated, with one header line."
    )


def _scan_text(path: Path, skip_rows: int) -> tuple[Any, int, str | None, list[str], list[int]]:
    """The attributes line's payload, the header's line number and text, the data lines and
    their line numbers (1-based; blank lines left out)."""
    payload, header, header_no = None, None, 0
    rows: list[str] = []
    numbers: list[int] = []
    try:
        with path.open("r", encoding="utf-8-sig") as fh:  # -sig: drop a byte-order mark
            for no, line in enumerate(fh, start=1):
                if no <= skip_rows:
                    continue
                text = line.rstrip("\r\n")
                if header is None:
                    if text.startswith(ATTRS_LINE):
                        payload = json.loads(text[len(ATTRS_LINE) :])
                    elif text.strip() and not text.startswith("#"):
                        header, header_no = text, no
                elif text.strip():
                    rows.append(text)
                    numbers.append(no)
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path} is not a UTF-8 text file ({exc.reason}).") from None
    except json.JSONDecodeError:
        raise ValueError(f"{path} has a damaged {ATTRS_LINE.strip()} line.") from None
    return payload, header_no, header, rows, numbers


def _parse_table(text: str, *, sep: str, decimal: str, path: Path, numbers: list[int]) -> Any:
    try:
        return pd.read_csv(io.StringIO(text), sep=sep, decimal=decimal, engine="c")
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        first = one_line(exc)
        match = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", first)
        if match and 0 <= int(match[2]) - 2 < len(numbers):
            line = numbers[int(match[2]) - 2]
            first = f"line {line} has {match[3]} fields where the header has {match[1]}"
        raise ValueError(f"cannot read {path} as a table: {first}") from None


def read_csv(
    path: Path,
    *,
    time: str | None,
    dt: float | None,
    step: str | None,
    keep: Sequence[str] | None,
    skip_rows: int,
    decimal: str,
) -> tuple[xr.Dataset, Origin]:
    payload, header_no, header, rows, numbers = _scan_text(path, skip_rows)
    skipped = f" after skipping {skip_rows} line(s)" if skip_rows else ""
    if header is None:
        raise ValueError(f"{path} is empty{skipped}: no header line and no data.")
    if not rows:
        raise ValueError(f"{path} has a header but no data rows.")
    if path.suffix.lower() == ".tsv":
        sep = "\t"
    else:
        sep = _delimiter(
            [header, *rows[:5]],
            what=str(path),
            decimal=decimal,
            first_line=header_no,
            skip_rows=skip_rows,
        )
    names = [c.strip() for c in (header.split() if sep == r"\s+" else header.split(sep))]
    duplicated = sorted({c for c in names if names.count(c) > 1})
    if duplicated:
        raise ValueError(f"{path} has duplicate column names {duplicated}; rename them.")
    frame = _parse_table(
        "\n".join([header, *rows]), sep=sep, decimal=decimal, path=path, numbers=numbers
    )
    if payload is None and _looks_like_header(frame):
        raise ParameterError(
            f"line {numbers[0]} of {_lit(path)} holds words where numbers belong, below the "
            f"header on line {header_no} ({_lit(header.strip())!r}); if that line is a title, "
            f"skip it with {{skip_rows={header_no}}}{{to}}; units belong in the header, as in "
            "'time (s)'.",
            function=_LOAD,
        )
    origin = Origin(str(path), lines=np.asarray(numbers), sep=sep, decimal=decimal)
    ds = from_table(
        frame,
        time=time,
        dt=dt,
        step=step,
        origin=origin,
        keep=keep,
        parse_header=payload is None,
    )
    return (apply_payload(ds, payload) if payload else ds), origin

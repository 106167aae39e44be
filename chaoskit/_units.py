"""Units as people write them: in column headers, and of time.

:func:`split_header` takes a header such as ``acc y [m/s^2]`` apart, :func:`cf_units`
rewrites a unit in the CF (UDUNITS) spelling and :func:`seconds_per` converts a time unit to
seconds. Used by every reader of tables (:mod:`chaoskit._tables`).
"""

from __future__ import annotations

import re
from typing import Any

__all__ = ["cf_units", "seconds_per", "split_header"]


#: Units a time column or variable may carry, in seconds (after :func:`cf_units`).
_TIME_UNITS = {
    "s": 1.0,
    "second": 1.0,
    "seconds": 1.0,
    "ms": 1e-3,
    "us": 1e-6,
    "ns": 1e-9,
    "min": 60.0,
    "h": 3600.0,
    "hr": 3600.0,
    "d": 86400.0,
    "day": 86400.0,
    "days": 86400.0,
}


_HEADER_UNITS = (
    re.compile(r"(?P<name>.*?\S)\s*\((?P<units>[^()]*)\)"),
    re.compile(r"(?P<name>.*?\S)\s*\[(?P<units>[^\[\]]*)\]"),
    re.compile(r"(?P<name>.*?\S)\s+/\s+(?P<units>\S.*)"),
)
_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")
_UNIT_FACTOR = re.compile(r"([A-Za-z%°Ω]+)\^?([+-]?\d+)?")
_UNIT_WORDS = {"%": "percent", "°": "degree", "deg": "degree", "°C": "degC", "sec": "s"}


def split_header(text: Any) -> tuple[str, str | None]:
    """A column header as its name and its units, as written (``None`` without units).

    Understood: ``name (units)``, ``name [units]`` and ``name / units`` (blanks around the
    slash).

    Examples
    --------
    >>> split_header("acc y [m/s^2]"), split_header("x / mm"), split_header("time")
    (('acc y', 'm/s^2'), ('x', 'mm'), ('time', None))
    """
    text = str(text).strip()
    for pattern in _HEADER_UNITS:
        match = pattern.fullmatch(text)
        if match:
            return match["name"].strip(), (match["units"].strip() or None)
    return text, None


def cf_units(text: str) -> str:
    """A unit as people write it, in the CF (UDUNITS) spelling: ``m/s^2`` → ``m s-2``.

    Products (blank, ``*``, ``·``), quotients (``/``) and powers (``^2``, ``**2``, ``²``,
    ``-1``) of unit symbols are rewritten; ``µ`` becomes ``u``, ``%`` ``percent`` and ``-``
    ``1``. Anything else is returned as written.

    Examples
    --------
    >>> cf_units("m/s^2"), cf_units("1/s"), cf_units("N*m"), cf_units("µm")
    ('m s-2', 's-1', 'N m', 'um')
    """
    raw = str(text).strip()
    s = raw.translate(_SUPERSCRIPTS).replace("**", "^").replace("µ", "u").replace("μ", "u")
    s = s.replace("·", " ").replace("⋅", " ").replace("*", " ")
    if s in ("", "-", "1"):
        return "1"
    powers: dict[str, int] = {}
    for k, part in enumerate(s.split("/")):
        factors = part.split()
        if not factors:
            return raw
        for factor in factors:
            if factor == "1":
                continue
            match = _UNIT_FACTOR.fullmatch(factor)
            if match is None:
                return raw
            base = _UNIT_WORDS.get(match[1], match[1])
            power = int(match[2] or 1)
            powers[base] = powers.get(base, 0) + (power if k == 0 else -power)
    terms = [base if p == 1 else f"{base}{p}" for base, p in powers.items() if p != 0]
    return " ".join(terms) or "1"


def seconds_per(units: str | None, *, what: str) -> float:
    """Seconds per unit of a time given in ``units`` (1 without units)."""
    if units is None:
        return 1.0
    factor = _TIME_UNITS.get(cf_units(units))
    if factor is None:
        raise ValueError(
            f"the time of {what} is in {units!r}; chaoskit reads time in {', '.join(_TIME_UNITS)}."
        )
    return factor

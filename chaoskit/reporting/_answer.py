"""The answer in a few words: which evidence decided a verdict, and one row per state.

:func:`decided_by` says in one line which pieces of evidence carried a verdict and which it
set aside; :func:`answer_table` gives one row per state (verdict, confidence, largest
exponent with its 95 % interval and where it comes from), the table the command lines print
and the reports open with. :data:`CONFIDENCE_NOTE` says what the confidence is.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import pandas as pd

from ._content import MISSING, format_number

__all__ = [
    "CONFIDENCE_FORMAT",
    "CONFIDENCE_NOTE",
    "answer_table",
    "decided_by",
    "format_confidence",
    "plural",
]

#: Format spec of every confidence a report or a console prints.
CONFIDENCE_FORMAT = ".2f"

#: One sentence on what the confidence of a verdict is: its scale and its calibration.
CONFIDENCE_NOTE = (
    "Confidence, from 0 to 1, is the fraction of the pieces of evidence that could have "
    "decided and agree with the verdict (the votes in the appendix); it is a vote count, not "
    "a probability: on the corpus of systems of known motion, verdicts at confidence ≥ 0.9 "
    "were right 98 % of the time where the motion was decidable (docs/verdict.md)."
)


def format_confidence(value: Any) -> str:
    """A confidence with two decimals (``"0.67"``); a dash when it is missing or NaN."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        return MISSING
    return format(v, CONFIDENCE_FORMAT) if math.isfinite(v) else MISSING


def plural(count: float, word: str, words: str | None = None) -> str:
    """``"1 update"``, ``"2 updates"``, ``"0.5 revolutions"``: a count with its noun.

    Examples
    --------
    >>> plural(1, "update"), plural(3, "update"), plural(0.5, "revolution")
    ('1 update', '3 updates', '0.5 revolutions')
    """
    many = words if words is not None else f"{word}s"
    return f"{count:,g} {word if count == 1 else many}"


def _section_words(structure: Any) -> str:
    kind = getattr(structure, "kind", "none")
    if kind == "clusters":
        return plural(int(structure.n_clusters), "tight cluster")
    if kind == "closed-curve":
        return "a closed curve"
    if kind == "too-few-points":
        return f"too few points ({structure.n_points})"
    return str(kind)


def _clear(flag: bool | None) -> str:
    return "clearly positive" if flag else "not clearly positive"


def _motion_pieces(mv: Any) -> dict[str, str]:
    """What each vote of a motion verdict stands for, in words."""
    say = getattr(mv, "equations_say", None)
    pieces = {
        "equations": "the exponent from the equations ("
        + ("interval above zero" if say == "chaotic" else "interval not above zero")
        + ")",
        "section": f"the joint section ({_section_words(getattr(mv, 'structure', None))})",
        "exponent": "the joint exponent of the data estimators ("
        + _clear(getattr(mv, "exponent_positive", None))
        + ")",
    }
    for name, v in getattr(mv, "variables", {}).items():
        pieces[f"variable {name}"] = f"{name} ({v.label})"
    return pieces


def _variable_pieces(v: Any) -> dict[str, str]:
    """What each vote of a per-variable verdict stands for, in words."""
    lines = getattr(v, "lines", None)
    zero_one = getattr(v, "zero_one", None)
    surrogates = getattr(v, "surrogates", None)
    return {
        "lines": f"the line spectrum ({getattr(lines, 'kind', 'none')})",
        "section": f"the section ({_section_words(getattr(v, 'structure', None))})",
        "rosenstein": f"Rosenstein's exponent ({_clear(getattr(v, 'rosenstein_positive', None))})",
        "wolf": f"Wolf's exponent ({_clear(getattr(v, 'wolf_positive', None))})",
        "kantz": f"Kantz's exponent ({_clear(getattr(v, 'kantz_positive', None))})",
        "zero_one": "the 0-1 test"
        + ("" if zero_one is None else f" (K = {format(float(zero_one.k), '.2f')})"),
        "surrogates": "the surrogate test ("
        + ("rejects" if getattr(surrogates, "rejected", False) else "does not reject")
        + " linear noise)",
    }


def _join(parts: list[str]) -> str:
    if len(parts) <= 1:
        return "".join(parts)
    return ", ".join(parts[:-1]) + " and " + parts[-1]


def decided_by(verdict: Any) -> str:
    """Which evidence decided a verdict, in one line.

    ``verdict`` is a :class:`chaoskit.MotionVerdict` or a :class:`chaoskit.Verdict`. The
    pieces that voted for the label "decide over" those that voted against it (e.g. "the
    exponent from the equations (interval above zero) decides over the joint exponent of
    the data estimators (not clearly positive)"); when nothing voted against, they
    "agree". An undetermined verdict gives its reason with what would decide it.
    """
    reason = " ".join(str(getattr(verdict, "reason", "")).split())
    if getattr(verdict, "label", "undetermined") == "undetermined":
        return reason
    votes: Mapping[str, str] = getattr(verdict, "votes", {}) or {}
    motion = hasattr(verdict, "voting")
    pieces = _motion_pieces(verdict) if motion else _variable_pieces(verdict)
    order = [k for k in pieces if k in votes] + [k for k in votes if k not in pieces]

    def words(side: str) -> list[str]:
        chosen = [k for k in order if votes.get(k) == side]
        variables = [k for k in chosen if k.startswith("variable ")]
        out = [pieces.get(k, k) for k in chosen if not k.startswith("variable ")]
        if variables:
            names = ", ".join(k.removeprefix("variable ") for k in variables)
            per = getattr(verdict, "variables", {})
            labels = {
                str(getattr(per.get(k.removeprefix("variable ")), "label", "?")) for k in variables
            }
            noun = "variable" if len(variables) == 1 else "variables"
            out.append(f"the {noun} {names} ({'/'.join(sorted(labels))})")
        return out

    supports, opposes = words("supports"), words("opposes")
    if not supports:
        return reason
    if not opposes:
        return f"{_join(supports)} agree" if len(supports) > 1 else f"{supports[0]} decides"
    verb = "decides" if len(supports) == 1 else "decide"
    return f"{_join(supports)} {verb} over {_join(opposes)}"


def _exponent_of(verdict: Any) -> tuple[tuple[float, float, float] | None, str]:
    """(λ₁, low, high) the answer quotes and where it comes from."""
    equations = getattr(verdict, "equations", None)
    if equations is not None:
        value = getattr(equations, "exponent", getattr(equations, "mle", None))
        ci = getattr(equations, "ci", getattr(equations, "interval", None))
        try:
            low, high = (float(c) for c in ci)  # type: ignore[union-attr]
            triple = (float(value), low, high)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            triple = None
        if triple is not None and all(math.isfinite(x) for x in triple):
            return triple, "equations of motion"
    if hasattr(verdict, "voting"):
        res, source = getattr(verdict, "exponent", None), "data, joint embedding (Rosenstein)"
    else:
        res, source = getattr(verdict, "rosenstein", None), "data (Rosenstein)"
    if res is None:
        return None, MISSING
    return (float(res.mle), float(res.ci[0]), float(res.ci[1])), source


def answer_table(verdicts: Mapping[str, Any]) -> pd.DataFrame:
    """One row per state: verdict, confidence, λ₁ [95 % interval] and its source.

    Parameters
    ----------
    verdicts
        ``{state: MotionVerdict or Verdict}`` (e.g. :attr:`chaoskit.Report.motions`).

    Returns
    -------
    pandas.DataFrame
        Strings, indexed by ``state``: ``verdict`` (with the period k of a period-k
        motion), ``confidence`` (two decimals), ``λ₁ [95 %]`` (in 1/s, or 1/iteration for a
        map; from the equations of motion when given, else from the data) and ``λ₁ from``.
        ``print(frame.to_string())`` gives the console table.
    """
    rows = []
    for v in verdicts.values():
        period = getattr(v, "period", None)
        label = str(v.label) if period is None else f"{v.label} (period {period})"
        triple, source = _exponent_of(v)
        unit = "1/iteration" if getattr(v, "kind", "") == "map" else "1/s"
        if triple is None:
            exponent = MISSING
        else:
            value, low, high = (format_number(x, 3) for x in triple)
            exponent = f"{value} [{low}, {high}] {unit}"
        rows.append(
            {
                "verdict": label,
                "confidence": format_confidence(getattr(v, "confidence", math.nan)),
                "λ₁ [95 %]": exponent,
                "λ₁ from": source,
            }
        )
    columns = ["verdict", "confidence", "λ₁ [95 %]", "λ₁ from"]
    return pd.DataFrame(
        rows, index=pd.Index([str(s) for s in verdicts], name="state"), columns=columns
    )

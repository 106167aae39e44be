"""Write a report: its HTML page and Markdown twin (Jinja2 templates), and the files.

Both renderers take their cell text from :meth:`ReportTable.display`, so the page and its
Markdown twin print the same strings. The templates ship as package data in
``chaoskit/reporting/templates/``. Every string of the report (titles, labels, captions,
cells, notes) is text, never markup: the HTML template escapes it (Jinja2 autoescape) and
the Markdown twin passes it through :func:`markdown_text`, so a variable name such as
``<script>`` or ``a|b`` prints as itself in any viewer.

The writer needs only a report's title, time of assembly and sections (:class:`Page`), so
it sits below the :class:`~chaoskit.Report` type, whose output methods call it.
"""

from __future__ import annotations

import base64
import os
import re
from collections.abc import Sequence
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, Protocol

from .._paths import safe_filename
from ..contract import atomic_write
from ._content import MISSING, ReportCode, ReportFigure, ReportSection, ReportTable

if TYPE_CHECKING:
    from jinja2 import Environment

__all__ = [
    "Page",
    "figure_filename",
    "markdown_text",
    "render_html",
    "render_markdown",
    "table_cells",
    "write_report",
]


class Page(Protocol):
    """What the writer reads of a report (a :class:`~chaoskit.Report` is one)."""

    @property
    def title(self) -> str: ...

    @property
    def created(self) -> str: ...

    @property
    def sections(self) -> Sequence[ReportSection]: ...

    @property
    def figures(self) -> Sequence[ReportFigure]: ...


#: Characters that Markdown (CommonMark, GitHub) reads as inline or table syntax: each is
#: backslash-escaped. ``<``, ``>`` and ``&`` become HTML entities, so no viewer can read
#: them as a tag or an entity.
_MD_SYNTAX = re.compile(r"([\\`*_\[\]|])")
_MD_ENTITIES = {"&": "&amp;", "<": "&lt;", ">": "&gt;"}
#: What makes a paragraph's first characters a heading, list, quote or rule.
_MD_BLOCK_START = re.compile(r"^(\d+)([.)])|^([#=+-])")


def markdown_text(text: Any, *, block: bool = False) -> str:
    """``text`` as literal Markdown text on one line: syntax escaped, HTML made inert.

    Backslash-escapes Markdown's inline and table syntax (backslash, backtick, ``*``,
    ``_``, ``[``, ``]``, ``|``), writes ``<``, ``>`` and ``&`` as HTML entities and joins
    lines with spaces, so a hostile name (``<script>``, ``a | b``, ``[x](javascript:...)``)
    renders as itself. With ``block`` (text that starts a paragraph) a leading ``#``,
    ``-``, ``+``, ``=`` or ``1.`` is escaped too, so it cannot open a heading or a list.

    Examples
    --------
    >>> markdown_text("<b>x|y</b> [a](b)")
    '&lt;b&gt;x\\\\|y&lt;/b&gt; \\\\[a\\\\](b)'
    """
    one_line = " ".join(str(text).split())
    escaped = _MD_SYNTAX.sub(r"\\\1", one_line)
    if block:
        escaped = _MD_BLOCK_START.sub(
            lambda m: f"{m[1]}\\{m[2]}" if m[1] else f"\\{m[3]}", escaped, count=1
        )
    return "".join(_MD_ENTITIES.get(c, c) for c in escaped)


def _markdown_block(text: Any) -> str:
    return markdown_text(text, block=True)


@cache
def _environment() -> Environment:
    from jinja2 import Environment, PackageLoader, StrictUndefined, select_autoescape

    env = Environment(
        loader=PackageLoader("chaoskit.reporting", "templates"),
        autoescape=select_autoescape(["html", "html.j2"]),
        undefined=StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )
    env.filters["md"] = markdown_text
    env.filters["md_block"] = _markdown_block
    return env


def _anchor(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-") or "section"


def table_cells(table: ReportTable) -> tuple[list[list[dict[str, Any]]], list[list[str]]]:
    """Header rows (cells with text, colspan, rowspan) and body rows (strings) of a table.

    The body rows start with the row labels (one cell per index level).
    """
    shown = table.display()
    names = [str(n) for n in shown.index.names]
    cols = list(shown.columns)
    two_levels = any(sub for _, sub in cols)
    top: list[dict[str, Any]] = [
        {"text": n, "colspan": 1, "rowspan": 2 if two_levels else 1, "row_label": True}
        for n in names
    ]
    second: list[dict[str, Any]] = []
    i = 0
    while i < len(cols):
        label, sub = cols[i]
        if not sub:
            top.append({"text": label, "colspan": 1, "rowspan": 2 if two_levels else 1})
            i += 1
            continue
        j = i
        while j < len(cols) and cols[j][0] == label and cols[j][1]:
            second.append({"text": cols[j][1], "colspan": 1, "rowspan": 1})
            j += 1
        top.append({"text": label, "colspan": j - i, "rowspan": 1})
        i = j
    header = [top, second] if two_levels else [top]
    body = []
    for key, row in zip(shown.index, shown.itertuples(index=False), strict=True):
        keys = list(key) if isinstance(key, tuple) else [key]
        body.append([str(k) for k in keys] + [str(c) for c in row])
    return header, body


#: A number, optionally with its interval and a footnote marker (``1.2 [0.5, 2] †``).
_NUMERIC = re.compile(r"^[-+−]?(\d[\d.]*([eE][-+]?\d+)?|∞)( \[.*\])?( [†‡§¶*]+)?$")


def _numeric_columns(body: list[list[str]], n_labels: int) -> list[bool]:
    """Per cell position: True when every non-missing cell of that column is a number."""
    width = len(body[0]) if body else 0
    out = []
    for j in range(width):
        cells = [row[j] for row in body if row[j] != MISSING]
        out.append(j >= n_labels and bool(cells) and all(_NUMERIC.match(c) for c in cells))
    return out


def _flat_header(table: ReportTable) -> list[str]:
    shown = table.display()
    names = [str(n) for n in shown.index.names]
    return names + [f"{a}: {b}" if b else str(a) for a, b in shown.columns]


def _context(report: Page, *, figure_src: Any) -> dict[str, Any]:
    sections = []
    for section in report.sections:
        items = []
        for item in section.items:
            if isinstance(item, ReportTable):
                header, body = table_cells(item)
                n_labels = item.display().index.nlevels
                items.append(
                    {
                        "kind": "table",
                        "number": item.number,
                        "caption": item.caption,
                        "header": header,
                        "flat_header": _flat_header(item),
                        "body": body,
                        "n_row_labels": n_labels,
                        "numeric": _numeric_columns(body, n_labels),
                        "notes": item.notes,
                    }
                )
            elif isinstance(item, ReportFigure):
                items.append(
                    {
                        "kind": "figure",
                        "number": item.number,
                        "caption": item.caption,
                        "src": figure_src(item),
                        "name": item.name,
                    }
                )
            elif isinstance(item, ReportCode):
                items.append(
                    {
                        "kind": "code",
                        "caption": item.caption,
                        "text": item.text,
                        "language": re.sub(r"[^A-Za-z0-9_+-]", "", str(item.language)),
                    }
                )
        sections.append(
            {
                "title": section.title,
                "anchor": _anchor(section.title),
                "text": section.text,
                "footer": section.footer,
                "entries": items,
            }
        )
    return {"title": report.title, "created": report.created, "sections": sections}


def _data_uri(figure: ReportFigure) -> str:
    return "data:image/png;base64," + base64.b64encode(figure.png).decode("ascii")


def render_html(report: Page) -> str:
    """The self-contained page: inline CSS, figures as base64 PNG data URIs."""
    template = _environment().get_template("report.html.j2")
    return template.render(**_context(report, figure_src=_data_uri))


def _md_cell(text: str) -> str:
    return markdown_text(text)


def _md_code_fence(text: str) -> str:
    longest = max((len(m) for m in re.findall(r"`+", text)), default=0)
    return "`" * max(3, longest + 1)


def render_markdown(
    report: Page,
    *,
    figures: Literal["files", "embed"] = "files",
    figure_dir: str = "figures",
) -> str:
    """The Markdown twin: pipe tables, figures linked as files or embedded as data URIs."""
    if figures not in ("files", "embed"):
        raise ValueError(f"figures must be 'files' or 'embed'; got {figures!r}.")

    def src(fig: ReportFigure) -> str:
        if figures == "embed":
            return _data_uri(fig)
        return f"{figure_dir.rstrip('/')}/{figure_filename(fig)}"

    context = _context(report, figure_src=src)
    for section in context["sections"]:
        for item in section["entries"]:
            if item["kind"] == "table":
                item["md_lines"] = _md_table(item)
    template = _environment().get_template("report.md.j2")
    return template.render(**context, fence=_md_code_fence)


def _md_table(item: dict[str, Any]) -> list[str]:
    def line(cells: list[str]) -> str:
        return "| " + " | ".join(_md_cell(c) for c in cells) + " |"

    numeric = item["numeric"] or [False] * len(item["flat_header"])
    rule = "| " + " | ".join("--:" if num else ":--" for num in numeric) + " |"
    return [line(item["flat_header"]), rule, *(line(row) for row in item["body"])]


def figure_filename(figure: ReportFigure) -> str:
    """File name of a figure next to the Markdown twin."""
    return safe_filename(f"figure-{figure.number:02d}-{figure.name}") + ".png"


def write_report(
    report: Page,
    path: str | os.PathLike[str],
    *,
    markdown: bool = True,
    markdown_figures: Literal["files", "embed"] = "files",
) -> dict[str, Any]:
    """Write ``path`` (HTML) and its Markdown twin; see :meth:`chaoskit.Report.write`."""
    if markdown_figures not in ("files", "embed"):
        raise ValueError(f"markdown_figures must be 'files' or 'embed'; got {markdown_figures!r}.")
    path = Path(path)
    html_path = path if path.suffix.lower() in (".html", ".htm") else path.with_suffix(".html")
    written: dict[str, Any] = {"html": html_path, "markdown": None, "figures": []}
    html = render_html(report)
    atomic_write(html_path, lambda p: p.write_text(html, encoding="utf-8"))
    if markdown:
        md_path = html_path.with_suffix(".md")
        folder = f"{html_path.stem}_figures"
        text = render_markdown(report, figures=markdown_figures, figure_dir=folder)
        if markdown_figures == "files":
            for fig in report.figures:
                target = html_path.parent / folder / figure_filename(fig)
                atomic_write(target, lambda p, b=fig.png: p.write_bytes(b))
                written["figures"].append(target)
        atomic_write(md_path, lambda p: p.write_text(text, encoding="utf-8"))
        written["markdown"] = md_path
    return written

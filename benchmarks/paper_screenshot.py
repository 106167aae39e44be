"""The paper study's report as a reader first sees it: a headless-Chromium screenshot.

The report must answer its question on the first screen: per state the verdict with its
confidence, the exponent from the equations beside Wolf's and Rosenstein's with their
intervals, the paper's values and claims beside ours, and the headline figures. This
script renders ``report.html`` of a finished study (``mechanism paper --quick -o
results/``) in headless Chromium at a laptop-sized window and writes one PNG of the first
screen and one of the full page, so a person (or a review) can look at what the page
shows without a browser session.

Run::

    apt-get install -y chromium          # once; any Chromium or Chrome binary works
    python benchmarks/paper_screenshot.py results/report.html --out results/

which writes ``results/first-screen.png`` (1280 × 1000) and ``results/page.png``
(1280 × 6000: the summary, the headline figures and the first tables). The options
``--width``, ``--height`` and ``--page-height`` change the sizes; ``--browser`` names the
binary when it is not on PATH. Exit status 2 when the report or the browser is missing.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
from pathlib import Path

#: Switches that keep a headless browser from touching the network or a profile.
QUIET = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--hide-scrollbars",
)


def find_browser(name: str | None = None) -> str | None:
    """Path of a Chromium or Chrome binary (``name`` if given), or None."""
    candidates = (name,) if name else ("chromium", "chromium-browser", "google-chrome")
    for candidate in candidates:
        found = shutil.which(candidate) if candidate else None
        if found:
            return found
    return None


def screenshot(
    html: Path, png: Path, *, width: int = 1280, height: int = 1000, browser: str | None = None
) -> Path:
    """Render ``html`` in headless Chromium at ``width`` × ``height`` px into ``png``.

    Raises
    ------
    FileNotFoundError
        When ``html`` does not exist or no browser is found.
    RuntimeError
        When the browser fails (its last output in the message).
    """
    html = Path(html).resolve()
    if not html.is_file():
        raise FileNotFoundError(f"report not found: {html}")
    binary = find_browser(browser)
    if binary is None:
        raise FileNotFoundError("no chromium binary on PATH (apt-get install -y chromium)")
    if width < 200 or height < 200:
        raise ValueError(f"width and height must be >= 200 px; got {width} × {height}.")
    png = Path(png).resolve()
    png.parent.mkdir(parents=True, exist_ok=True)
    done = subprocess.run(
        [binary, *QUIET, f"--screenshot={png}", f"--window-size={width},{height}", html.as_uri()],
        capture_output=True,
        text=True,
        timeout=180,
        check=False,
    )
    if done.returncode != 0 or not png.is_file():
        raise RuntimeError(f"{binary} failed ({done.returncode}): {done.stderr[-1000:]}")
    return png


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("report", type=Path, help="report.html of a finished study")
    parser.add_argument("--out", type=Path, default=None, help="folder of the PNGs")
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=1000)
    parser.add_argument("--page-height", type=int, default=6000)
    parser.add_argument("--browser", default=None, help="Chromium binary (default: on PATH)")
    args = parser.parse_args(argv)
    out = args.out or args.report.resolve().parent
    try:
        first = screenshot(
            args.report, out / "first-screen.png", width=args.width, height=args.height,
            browser=args.browser,
        )  # fmt: skip
        page = screenshot(
            args.report, out / "page.png", width=args.width, height=args.page_height,
            browser=args.browser,
        )  # fmt: skip
    except (FileNotFoundError, ValueError) as exc:
        print(f"Error: {exc}", file=sys.stderr)
        return 2
    print(f"wrote {first} and {page}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The ``mechanism`` Typer application: the command group, Ctrl-C handling and ``--version``.

The command modules of this package register their commands on :data:`app`.
"""

from __future__ import annotations

import signal
from typing import Any

import typer
from typer.core import TyperGroup

from chaoskit.contract import __version__
from mechanism.core.integrate import interrupt_integrations

#: exit status of a command stopped by Ctrl-C (128 + SIGINT, as a shell reports it)
EXIT_INTERRUPTED = 130
#: the order ``mechanism --help`` lists the commands in, whatever order their modules were
#: imported in (a command not named here comes after these, in the order it was registered)
COMMAND_ORDER = (
    "scenes",
    "show",
    "simulate",
    "wear",
    "wear-life",
    "convergence",
    "sweep",
    "bifurcation",
    "paper",
    "lyapunov",
    "continuation",
)


def _on_sigint(signum: int, frame: Any) -> None:
    # integrations in other threads (a run's ideal companion) stop with the main thread,
    # also while it is only waiting for them
    interrupt_integrations()
    raise KeyboardInterrupt


class _Commands(TyperGroup):
    """The command group: Ctrl-C ends any command with one line and exit status 130."""

    def list_commands(self, ctx: Any) -> list[str]:
        rank = {name: i for i, name in enumerate(COMMAND_ORDER)}
        return sorted(super().list_commands(ctx), key=lambda name: rank.get(name, len(rank)))

    def format_commands(self, ctx: Any, formatter: Any) -> None:
        # click cuts a command's summary with "..." to fit beside the longest command name;
        # the summaries wrap under their own column instead, so none is cut
        rows = []
        for name in self.list_commands(ctx):
            command = self.get_command(ctx, name)
            if command is not None and not command.hidden:
                rows.append((name, command.get_short_help_str(limit=1000)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)

    def invoke(self, ctx: Any) -> Any:
        previous = signal.getsignal(signal.SIGINT)
        if previous is signal.default_int_handler:
            signal.signal(signal.SIGINT, _on_sigint)
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            # files a command already wrote (sweep points, bifurcation values) are whole:
            # each is written atomically, and a re-run with the same --store resumes
            typer.echo("interrupted", err=True)
            raise typer.Exit(code=EXIT_INTERRUPTED) from None
        finally:
            if previous is signal.default_int_handler:
                signal.signal(signal.SIGINT, previous)


app = typer.Typer(
    name="mechanism",
    help="Simulate planar rigid-flexible mechanisms with clearance joints and wear.",
    no_args_is_help=True,
    add_completion=False,
    cls=_Commands,
    # plain (click) help at a fixed 100 columns: long option names, help texts and command
    # summaries wrap instead of being cut at the terminal's width as in the rich panels,
    # and flags show no value type
    rich_markup_mode=None,
    context_settings={"terminal_width": 100, "max_content_width": 100},
)


def _version_callback(value: bool) -> None:
    if value:
        typer.echo(f"mechanism (chaoskit {__version__})")
        raise typer.Exit()


@app.callback()
def main(
    version: bool = typer.Option(
        False, "--version", callback=_version_callback, is_eager=True, help="Print the version."
    ),
) -> None:
    """mechanism command line."""

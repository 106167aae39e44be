"""``python -m mechanism.cli``: the ``mechanism`` command."""

from mechanism.cli import app

app()

"""The sample trajectories shipped with the package (see ``data/README.md`` in the repository)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

__all__ = ["SAMPLES", "sample_path"]

#: Every sample file, as shipped in ``chaoskit/data`` (installed) or ``data/`` (a checkout).
SAMPLES = (
    "lorenz.nc",
    "measured-journal.csv",
    "paper-150rpm-after.nc",
    "paper-150rpm-before.nc",
    "slider-crank-clearance.nc",
)


def sample_path(name: str) -> Path:
    """Path of a sample trajectory shipped with chaoskit, wherever the package is installed.

    Parameters
    ----------
    name
        One of ``"lorenz.nc"`` (Lorenz x, y, z; the file of ``chaoskit demo``),
        ``"measured-journal.csv"`` (synthetic probe signals), ``"paper-150rpm-before.nc"``,
        ``"paper-150rpm-after.nc"`` (the six-bar press before and after wear) and
        ``"slider-crank-clearance.nc"``.

    Returns
    -------
    pathlib.Path
        The file inside the installed package (``chaoskit/data``), or in ``data/`` of a
        source checkout installed in editable mode.

    Raises
    ------
    ValueError
        If ``name`` is not a sample, or the file is missing from this installation.

    Examples
    --------
    >>> import chaoskit
    >>> ds = chaoskit.load_trajectory(chaoskit.sample_path("lorenz.nc"))
    >>> sorted(ds.data_vars)
    ['x', 'y', 'z']
    """
    if name not in SAMPLES:
        raise ValueError(f"no sample named {name!r}; the samples are {', '.join(SAMPLES)}.")
    installed = resources.files(__package__).joinpath("data", name)
    if installed.is_file():
        return Path(str(installed))
    checkout = Path(__file__).resolve().parents[1] / "data" / name
    if checkout.is_file():
        return checkout
    raise ValueError(
        f"sample {name!r} is missing from this installation (looked in {installed} and "
        f"{checkout}); reinstall chaoskit, or run python data/make_samples.py in a checkout."
    )

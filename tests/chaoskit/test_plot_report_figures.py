"""The report figures (chaos map) draw exactly the data they are given."""

from __future__ import annotations

import matplotlib.pyplot as plt  # tests/conftest.py selects the Agg backend
import numpy as np
import pytest
import xarray as xr

from chaoskit import plot


def _rendered(ax) -> bool:
    ax.figure.canvas.draw()
    pixels = np.asarray(ax.figure.canvas.buffer_rgba())
    plt.close(ax.figure)
    return pixels.std() > 0


def _map() -> xr.Dataset:
    mle = np.array([[-2.0, 0.5, np.nan], [1.0, 4.0, -0.5]])
    verdict = np.array(
        [["periodic", "chaotic", ""], ["chaotic", "chaotic", "quasi-periodic"]], dtype=object
    )
    return xr.Dataset(
        {
            "mle": (("clearance", "speed"), mle, {"units": "s-1", "long_name": "MLE"}),
            "verdict": (("clearance", "speed"), verdict),
        },
        coords={
            "clearance": ("clearance", [1e-4, 2e-4], {"units": "m"}),
            "speed": ("speed", [30, 90, 150], {"units": "rpm"}),
        },
    )


def test_chaos_map_colours_the_exponents_and_writes_the_verdicts() -> None:
    ds = _map()
    ax = plot.chaos_map(ds)
    mesh = ax.collections[0]
    drawn = np.ma.masked_invalid(mesh.get_array()).reshape(2, 3)
    np.testing.assert_array_equal(drawn.mask, np.isnan(ds["mle"].values))
    np.testing.assert_allclose(drawn.filled(np.nan), ds["mle"].values)
    assert mesh.norm.vmin == -4.0 and mesh.norm.vmax == 4.0  # centred on 0
    texts = {(t.get_position(), t.get_text()) for t in ax.texts}
    assert texts == {
        ((0, 0), "periodic"),
        ((1, 0), "chaotic"),
        ((0, 1), "chaotic"),
        ((1, 1), "chaotic"),
        ((2, 1), "quasi-\nperiodic"),
    }
    assert [t.get_text() for t in ax.get_xticklabels()] == ["30", "90", "150"]
    assert [t.get_text() for t in ax.get_yticklabels()] == ["0.0001", "0.0002"]
    assert ax.get_xlabel() == "speed [rpm]" and ax.get_ylabel() == "clearance [m]"
    assert _rendered(ax)


def test_chaos_map_axes_can_be_swapped_and_a_dataarray_drawn() -> None:
    ds = _map()
    ax = plot.chaos_map(ds, x="clearance", y="speed")
    drawn = np.ma.masked_invalid(ax.collections[0].get_array()).reshape(3, 2)
    np.testing.assert_allclose(drawn.filled(np.nan), ds["mle"].values.T)
    plt.close(ax.figure)
    _, given = plt.subplots()
    assert plot.chaos_map(ds["mle"], ax=given) is given
    assert not given.texts  # no verdicts given
    assert _rendered(given)


def test_chaos_map_refuses_bad_input() -> None:
    with pytest.raises(ValueError, match="2-D exponent"):
        plot.chaos_map(xr.Dataset({"mle": ("x", np.ones(3))}))
    with pytest.raises(ValueError, match="dimensions"):
        plot.chaos_map(_map(), x="wear")
    with pytest.raises(ValueError, match="verdict variable"):
        plot.chaos_map(_map(), verdict="label")
    with pytest.raises(ValueError, match="Dataset"):
        plot.chaos_map(np.ones((2, 2)))

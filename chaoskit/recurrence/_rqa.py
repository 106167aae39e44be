"""Recurrence plots and recurrence quantification analysis (Zbilut & Webber 1992;
Marwan et al. 2007), built from a sparse recurrence matrix."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import xarray as xr
from scipy import sparse
from scipy.spatial import cKDTree

from .._validate import as_series, check_choice, check_int, check_positive, check_probability
from ..embedding import embed, min_length

__all__ = ["RecurrenceResult", "recurrence_analysis"]

Norm = Literal["chebyshev", "euclidean"]
_NORMS: tuple[str, ...] = ("chebyshev", "euclidean")
_P = {"chebyshev": np.inf, "euclidean": 2.0}
DEFAULT_RATE = 0.05
_RATE_SAMPLE = 1_000_000  # random pairs whose distance quantile sets a fixed-rate threshold
_MAX_PAIRS = 200_000_000  # recurrences held at once (≈ 1.6 GB of indices): a clear error above


@dataclass(frozen=True, kw_only=True)
class RecurrenceResult:
    r"""Recurrence quantification of one series, with the recurrence matrix it came from.

    Pairs closer in time than the Theiler window (:math:`|i - j| \le w`, always the main
    diagonal) are not recurrences. Both triangles of the symmetric matrix are counted, as
    pyunicorn does.

    Attributes
    ----------
    threshold
        Recurrence threshold ε, units of the input series.
    recurrence_rate
        RR: fraction of admissible pairs that recur.
    determinism
        DET: fraction of recurrence points on diagonal lines of at least ``min_line``.
    laminarity
        LAM: fraction of recurrence points on vertical lines of at least ``min_line``.
    mean_diagonal, max_diagonal
        L (mean length of diagonal lines ≥ ``min_line``) and L_max, samples.
    entropy
        ENTR: Shannon entropy (nats) of the diagonal line-length distribution (≥ ``min_line``).
    trapping_time, max_vertical
        TT (mean length of vertical lines ≥ ``min_line``) and V_max, samples.
    diagonal_lengths, vertical_lengths
        Number of lines of each length ``1 … N`` (index 0 is length 1).
    tau_recurrence
        Recurrence rate of the diagonal at each offset τ = 0 … N − 1 (zero inside the
        Theiler window): peaks are at the periods of the signal.
    matrix
        The recurrence matrix as a boolean :class:`scipy.sparse.csr_array` (N × N).
    embedding_dim, lag, theiler_window, min_line
        Embedding and line parameters used (samples).
    norm
        ``"chebyshev"`` or ``"euclidean"``.
    threshold_rule
        ``"given"`` or how ε was chosen from the requested recurrence rate.
    n_points
        Embedded points (the side of the matrix).
    units
        Units of the input series (those of ``threshold``).
    """

    threshold: float
    recurrence_rate: float
    determinism: float
    laminarity: float
    mean_diagonal: float
    max_diagonal: int
    entropy: float
    trapping_time: float
    max_vertical: int
    diagonal_lengths: np.ndarray
    vertical_lengths: np.ndarray
    tau_recurrence: np.ndarray
    matrix: Any
    embedding_dim: int
    lag: int
    theiler_window: int
    min_line: int
    norm: str
    threshold_rule: str
    n_points: int
    units: str

    def measures(self) -> dict[str, float]:
        """The RQA measures by their usual symbols (RR, DET, LAM, L, L_max, ENTR, TT, V_max)."""
        return {
            "RR": self.recurrence_rate,
            "DET": self.determinism,
            "LAM": self.laminarity,
            "L": self.mean_diagonal,
            "L_max": float(self.max_diagonal),
            "ENTR": self.entropy,
            "TT": self.trapping_time,
            "V_max": float(self.max_vertical),
        }

    def to_dataset(self) -> xr.Dataset:
        """Line-length distributions and τ-recurrence rate; measures in the attributes."""
        length = np.arange(1, self.n_points + 1)
        attrs: dict[str, Any] = {
            "threshold": self.threshold,
            "threshold_units": self.units,
            "threshold_rule": self.threshold_rule,
            "recurrence_rate": self.recurrence_rate,
            "determinism": self.determinism,
            "laminarity": self.laminarity,
            "mean_diagonal": self.mean_diagonal,
            "max_diagonal": self.max_diagonal,
            "entropy": self.entropy,
            "trapping_time": self.trapping_time,
            "max_vertical": self.max_vertical,
            "embedding_dim": self.embedding_dim,
            "lag": self.lag,
            "theiler_window": self.theiler_window,
            "min_line": self.min_line,
            "norm": self.norm,
            "n_points": self.n_points,
        }
        return xr.Dataset(
            {
                "diagonal_lines": (
                    "line_length",
                    self.diagonal_lengths,
                    {"units": "1", "long_name": "number of diagonal lines of each length"},
                ),
                "vertical_lines": (
                    "line_length",
                    self.vertical_lengths,
                    {"units": "1", "long_name": "number of vertical lines of each length"},
                ),
                "tau_recurrence": (
                    "offset",
                    self.tau_recurrence,
                    {"units": "1", "long_name": "recurrence rate of the diagonal at offset tau"},
                ),
            },
            coords={
                "line_length": (
                    "line_length",
                    length,
                    {"units": "1", "long_name": "line length in samples"},
                ),
                "offset": (
                    "offset",
                    np.arange(self.n_points),
                    {"units": "1", "long_name": "diagonal offset tau in samples"},
                ),
            },
            attrs=attrs,
        )


def _run_lengths(keys: np.ndarray, n: int) -> np.ndarray:
    """Histogram (index l − 1) of runs of consecutive integers in sorted ``keys``."""
    if keys.size == 0:
        return np.zeros(n, dtype=np.int64)
    starts = np.flatnonzero(np.diff(keys) != 1) + 1
    lengths = np.diff(np.concatenate(([0], starts, [keys.size])))
    return np.bincount(lengths - 1, minlength=n).astype(np.int64)


def _line_measures(hist: np.ndarray, min_line: int) -> tuple[float, float, int, float]:
    """(fraction of points in lines ≥ min_line, mean such length, longest, entropy)."""
    length = np.arange(1, hist.size + 1)
    points = float(length @ hist)
    long = hist[min_line - 1 :]
    long_len = length[min_line - 1 :]
    in_long = float(long_len @ long)
    n_long = float(long.sum())
    nonzero = np.flatnonzero(hist)
    longest = int(nonzero[-1] + 1) if nonzero.size else 0
    frac = in_long / points if points > 0 else float("nan")
    mean = in_long / n_long if n_long > 0 else float("nan")
    p = long[long > 0] / n_long if n_long > 0 else np.array([])
    entropy = float(-(p * np.log(p)).sum()) if p.size else float("nan")
    return frac, mean, longest, entropy


def _rate_threshold(
    pts: np.ndarray, rate: float, w: int, p: float, gen: np.random.Generator
) -> float:
    """The ``rate`` quantile of the distances of random admissible pairs."""
    n = pts.shape[0]
    i = gen.integers(0, n, _RATE_SAMPLE)
    j = gen.integers(0, n, _RATE_SAMPLE)
    keep = np.abs(i - j) > w
    d = np.linalg.norm(pts[i[keep]] - pts[j[keep]], ord=p, axis=1)
    return float(np.quantile(d, rate))


def recurrence_analysis(
    x: Any,
    *,
    embedding_dim: int = 1,
    lag: int = 1,
    threshold: float | None = None,
    recurrence_rate: float | None = None,
    theiler_window: int = 0,
    min_line: int = 2,
    norm: Norm = "euclidean",
    rng: Any = 0,
    units: str = "1",
) -> RecurrenceResult:
    r"""Recurrence matrix and recurrence quantification analysis (RQA) of a scalar series.

    .. math:: R_{ij} = \Theta(\varepsilon - \lVert \mathbf y_i - \mathbf y_j \rVert),
              \quad |i - j| > w

    The recurrences are found with a KD-tree (:meth:`scipy.spatial.cKDTree.query_pairs`)
    and kept as a sparse matrix, so memory grows with the number of recurrences
    (RR·N²), not with N²: N = 20 000 at RR = 5 % holds 2·10⁷ recurrences. Diagonal and
    vertical lines are runs of consecutive recurrences along the diagonals and columns.

    Parameters
    ----------
    x
        Scalar series (units ``units``).
    embedding_dim, lag
        Delay embedding (default: the series itself, m = 1).
    threshold
        ε in units of ``x``. Give this or ``recurrence_rate``.
    recurrence_rate
        Fix the recurrence rate instead (0 < RR < 1; default 0.05 when neither is given):
        ε is the RR-quantile of the distances of 10⁶ random admissible pairs, and the RR
        achieved is reported (within about 1 %).
    theiler_window
        Pairs with :math:`|i - j| \le w` are excluded (0: only the main diagonal).
    min_line
        Shortest diagonal or vertical line counted in DET, L, ENTR, LAM and TT (≥ 1).
    norm
        ``"euclidean"`` or ``"chebyshev"`` (maximum norm).
    rng
        Seed or generator for the random pairs of a fixed recurrence rate.
    units
        Units of ``x``.

    Returns
    -------
    RecurrenceResult

    Raises
    ------
    ValueError
        On bad parameters, both or an invalid ``threshold``/``recurrence_rate``, or more
        than 2·10⁸ recurrences (lower the threshold or subsample).

    References
    ----------
    N. Marwan, M. C. Romano, M. Thiel and J. Kurths, "Recurrence plots for the analysis of
    complex systems", Physics Reports 438 (2007) 237–329. J. P. Zbilut and C. L. Webber,
    "Embeddings and delays as derived from quantification of recurrence plots", Phys.
    Lett. A 171 (1992) 199.

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import recurrence_analysis
    >>> x = np.sin(2 * np.pi * np.arange(1000) / 50)
    >>> res = recurrence_analysis(x, embedding_dim=2, lag=12, threshold=0.1)
    >>> round(res.determinism, 3)
    1.0
    """
    embedding_dim = check_int(embedding_dim, name="embedding_dim", minimum=1, maximum=64)
    lag = check_int(lag, name="lag", minimum=1)
    w = check_int(theiler_window, name="theiler_window", minimum=0)
    min_line = check_int(min_line, name="min_line", minimum=1)
    norm = check_choice(norm, name="norm", choices=_NORMS)  # type: ignore[assignment]
    if threshold is not None and recurrence_rate is not None:
        raise ValueError("give threshold or recurrence_rate, not both.")
    arr = as_series(x, min_length=min_length(embedding_dim, lag, 2 * w + 2))
    pts = embed(arr, embedding_dim, lag)
    n = pts.shape[0]
    p = _P[norm]
    if threshold is not None:
        eps = check_positive(threshold, name="threshold")
        rule = "given"
    else:
        rate = DEFAULT_RATE if recurrence_rate is None else recurrence_rate
        rate = check_probability(rate, name="recurrence_rate")
        gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
        eps = _rate_threshold(pts, rate, w, p, gen)
        rule = f"recurrence rate {rate:g}: quantile of random pair distances"
    tree = cKDTree(pts, leafsize=16, balanced_tree=False, compact_nodes=False)
    upper = tree.query_pairs(eps, p=p, output_type="ndarray")  # i < j
    if upper.shape[0] > _MAX_PAIRS:
        raise ValueError(
            f"threshold={eps:.4g} gives {2 * upper.shape[0]} recurrences, more than "
            f"{2 * _MAX_PAIRS} held at once; lower the threshold or recurrence_rate or "
            "subsample the series."
        )
    i = upper[:, 0].astype(np.int64)
    j = upper[:, 1].astype(np.int64)
    del upper
    keep = (j - i) > w
    i, j = i[keep], j[keep]
    offset = j - i
    admissible = (n - w - 1) * (n - w)  # ordered pairs with |i − j| > w
    rr = 2.0 * i.size / admissible if admissible > 0 else float("nan")
    tau = np.bincount(offset, minlength=n).astype(np.float64)
    tau[1:] /= n - np.arange(1, n)
    tau[: w + 1] = 0.0
    # runs of consecutive keys are lines; the stride n + 1 keeps neighbouring diagonals
    # (and rows) from touching. Diagonal lines in one triangle, counted for both.
    diag = 2 * _run_lengths(np.sort(offset * (n + 1) + i), n)
    del offset
    cells = np.sort(np.concatenate([i * (n + 1) + j, j * (n + 1) + i]))  # row-major order
    del i, j
    vert = _run_lengths(cells, n)  # runs along a row = along a column (symmetric)
    rows, cols = np.divmod(cells, n + 1)
    del cells
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=n), out=indptr[1:])
    matrix = sparse.csr_array(
        (np.ones(cols.size, dtype=bool), cols.astype(np.int32), indptr), shape=(n, n)
    )
    det, mean_l, max_l, entr = _line_measures(diag, min_line)
    lam, tt, max_v, _ = _line_measures(vert, min_line)
    return RecurrenceResult(
        threshold=float(eps),
        recurrence_rate=float(rr),
        determinism=det,
        laminarity=lam,
        mean_diagonal=mean_l,
        max_diagonal=max_l,
        entropy=entr,
        trapping_time=tt,
        max_vertical=max_v,
        diagonal_lengths=diag,
        vertical_lengths=vert,
        tau_recurrence=tau,
        matrix=matrix,
        embedding_dim=embedding_dim,
        lag=lag,
        theiler_window=w,
        min_line=min_line,
        norm=norm,
        threshold_rule=rule,
        n_points=n,
        units=str(units),
    )

"""Chebyshev collocation on an interval (NumPy): the Chebyshev–Lobatto nodes, barycentric
interpolation and the differentiation matrix (Trefethen, *Spectral Methods in MATLAB*, SIAM 2000,
ch. 6; Berrut and Trefethen, SIAM Review 46 (2004) 501)."""

from __future__ import annotations

import numpy as np

from particles.validation import (
    InvalidArgumentError,
    check_count,
    check_positive,
    check_real_array,
)

__all__ = ["chebyshev_nodes", "barycentric_weights", "barycentric_matrix",
           "differentiation_matrix"]


def chebyshev_nodes(n: int, length: float) -> np.ndarray:
    """Chebyshev–Lobatto points q_j = Q (1 − cos(jπ/n)) / 2, j = 0..n, increasing from 0 to Q.

    Parameters
    ----------
    n : int
        Polynomial degree (n + 1 points, n ≥ 1).
    length : float
        Length Q of the interval [0, Q].

    Returns
    -------
    numpy.ndarray
        The n + 1 nodes, shape (n + 1,), with the end points set exactly to 0 and Q.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``n`` is not an integer >= 1 or ``length`` not a finite number > 0.
    """
    n = check_count(n, "n", 1)
    length = check_positive(length, "length")
    j = np.arange(n + 1)
    q = 0.5 * length * (1.0 - np.cos(np.pi * j / n))
    q[0], q[-1] = 0.0, float(length)
    return q


def barycentric_weights(n: int) -> np.ndarray:
    """Barycentric weights of the n + 1 Chebyshev–Lobatto points: (−1)ʲ, halved at both ends.

    Parameters
    ----------
    n : int
        Polynomial degree.

    Returns
    -------
    numpy.ndarray
        Shape (n + 1,).  Any common factor cancels in the barycentric formula.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``n`` is not an integer >= 1.
    """
    n = check_count(n, "n", 1)
    w = (-1.0) ** np.arange(n + 1)
    w[0] *= 0.5
    w[-1] *= 0.5
    return w


def barycentric_matrix(nodes: np.ndarray, targets) -> np.ndarray:
    """Matrix B with (B @ values)[i] = interpolant through (nodes, values) at targets[i].

    ``nodes`` are Chebyshev–Lobatto points (any affine image); the barycentric formula of the
    second kind is used, and a target that coincides with a node copies that node's value.

    Parameters
    ----------
    nodes : numpy.ndarray
        The n + 1 Chebyshev–Lobatto nodes (as from :func:`chebyshev_nodes`).
    targets : array_like
        Points at which to interpolate (a scalar is taken as one point).

    Returns
    -------
    numpy.ndarray
        B, shape (len(targets), len(nodes)).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``nodes`` are not at least two distinct finite reals or ``targets`` are not finite
        reals.
    """
    nodes = _check_nodes(nodes)
    targets = np.atleast_1d(check_real_array(targets, "targets"))
    w = barycentric_weights(len(nodes) - 1)
    diff = targets[:, None] - nodes[None, :]
    exact = diff == 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        c = w[None, :] / diff
        B = c / c.sum(axis=1, keepdims=True)
    rows = exact.any(axis=1)
    B[rows] = exact[rows].astype(float)
    return B


def differentiation_matrix(nodes: np.ndarray) -> np.ndarray:
    """Chebyshev differentiation matrix on the given Lobatto nodes (negative-sum trick).

    Off-diagonal entries D_ij = (w_j / w_i) / (x_i − x_j) from the barycentric weights; each
    diagonal entry is minus the sum of its row, so that D annihilates constants exactly.

    Parameters
    ----------
    nodes : numpy.ndarray
        The n + 1 Chebyshev–Lobatto nodes (any affine image of them).

    Returns
    -------
    numpy.ndarray
        D, shape (n + 1, n + 1): (D @ values) is the derivative of the interpolant at the nodes.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``nodes`` are not at least two distinct finite reals.
    """
    nodes = _check_nodes(nodes)
    n = len(nodes) - 1
    w = barycentric_weights(n)
    dx = nodes[:, None] - nodes[None, :]
    np.fill_diagonal(dx, 1.0)
    D = (w[None, :] / w[:, None]) / dx
    np.fill_diagonal(D, 0.0)
    np.fill_diagonal(D, -D.sum(axis=1))
    return D


def _check_nodes(nodes) -> np.ndarray:
    nodes = check_real_array(nodes, "nodes", ndim=1, min_size=2)
    if np.unique(nodes).size != nodes.size:
        raise InvalidArgumentError("nodes", nodes.tolist()[:40], "distinct nodes")
    return nodes

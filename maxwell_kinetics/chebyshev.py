"""Chebyshev collocation on an interval (NumPy): the Chebyshev–Lobatto nodes, barycentric
interpolation and the differentiation matrix (Trefethen, *Spectral Methods in MATLAB*, SIAM 2000,
ch. 6; Berrut and Trefethen, SIAM Review 46 (2004) 501)."""

from __future__ import annotations

import numpy as np

__all__ = ["chebyshev_nodes", "barycentric_weights", "barycentric_matrix",
           "differentiation_matrix"]


def chebyshev_nodes(n: int, length: float) -> np.ndarray:
    """Chebyshev–Lobatto points q_j = Q (1 − cos(jπ/n)) / 2, j = 0..n, increasing from 0 to Q.

    Parameters
    ----------
    n : int
        The degree (n + 1 points).
    length : float
        Q.

    Returns
    -------
    numpy.ndarray
    """
    j = np.arange(n + 1)
    q = 0.5 * length * (1.0 - np.cos(np.pi * j / n))
    q[0], q[-1] = 0.0, float(length)
    return q


def barycentric_weights(n: int) -> np.ndarray:
    """Barycentric weights of the n + 1 Chebyshev–Lobatto points: (−1)ʲ, halved at both ends.

    Parameters
    ----------
    n : int
        The degree.

    Returns
    -------
    numpy.ndarray
    """
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
        Chebyshev–Lobatto points.
    targets : array_like
        Where to interpolate.

    Returns
    -------
    numpy.ndarray
        (len(targets), len(nodes)).
    """
    nodes = np.asarray(nodes, dtype=float)
    targets = np.atleast_1d(np.asarray(targets, dtype=float))
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

    Parameters
    ----------
    nodes : numpy.ndarray
        Chebyshev–Lobatto points.

    Returns
    -------
    numpy.ndarray
    """
    n = len(nodes) - 1
    w = barycentric_weights(n)
    dx = nodes[:, None] - nodes[None, :]
    np.fill_diagonal(dx, 1.0)
    D = (w[None, :] / w[:, None]) / dx
    np.fill_diagonal(D, 0.0)
    np.fill_diagonal(D, -D.sum(axis=1))
    return D

"""The velocity grids of the spectral hard-sphere solver (:mod:`maxwell_kinetics.sphere_spectral`):
:class:`SphereGrid` (N modes per axis on the box [−L, L)^d of the scaled velocity, the kernel's
cutoff R and the quadrature sizes), the named grids :data:`GRIDS` and :func:`sphere_grid`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from particles.validation import InvalidArgumentError, check_count, check_positive

__all__ = ["SphereGrid", "GRIDS", "sphere_grid"]


@dataclass(frozen=True)
class SphereGrid:
    """The discretisation of the scaled velocity c (unit variance per component).

    Attributes
    ----------
    points : int
        N, Fourier modes (and nodes) per axis, even, ≥ 8.
    half_width : float
        L: the box is [−L, L)^d.
    cutoff : float
        R: the kernel is truncated to |g·n| ≤ R, |g⊥| ≤ R; R < L.
    sphere_order : int
        The Lebedev degree (d = 3; one of SciPy's) or the number of angles (d = 2).
    radial_nodes : int
        Gauss–Legendre nodes in s ∈ [0, R].

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming the field that is out of range.
    """

    points: int
    half_width: float
    cutoff: float
    sphere_order: int
    radial_nodes: int

    def __post_init__(self):
        points = check_count(self.points, "points", 8)
        if points % 2:
            raise InvalidArgumentError("points", self.points, "an even number >= 8")
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "half_width", check_positive(self.half_width, "half_width"))
        cutoff = check_positive(self.cutoff, "cutoff")
        if cutoff >= self.half_width:
            raise InvalidArgumentError("cutoff", self.cutoff, f"a cutoff R below the half "
                                       f"width L = {self.half_width:g} (L >= 1.4 R keeps the "
                                       f"periodic images apart)")
        object.__setattr__(self, "cutoff", cutoff)
        object.__setattr__(self, "sphere_order", check_count(self.sphere_order,
                                                             "sphere_order", 3))
        object.__setattr__(self, "radial_nodes", check_count(self.radial_nodes,
                                                             "radial_nodes", 2))

    @property
    def spacing(self) -> float:
        """h = 2L/N."""
        return 2.0 * self.half_width / self.points

    def nodes(self) -> np.ndarray:
        """c_j = −L + j h, j = 0 … N − 1 (one axis).

        Returns
        -------
        numpy.ndarray
        """
        return -self.half_width + self.spacing * np.arange(self.points)

    def to_dict(self) -> dict:
        """The fields as a JSON-able dict.

        Returns
        -------
        dict
        """
        return {"points": self.points, "half_width": self.half_width, "cutoff": self.cutoff,
                "sphere_order": self.sphere_order, "radial_nodes": self.radial_nodes}


#: The named grids by dimension: "coarse" (the tests), "default", "fine" (benchmarks/README.md,
#: "Spectral hard spheres", measures their accuracy).
GRIDS: dict[int, dict[str, SphereGrid]] = {
    3: {"coarse": SphereGrid(20, 8.0, 6.0, 11, 10),
        "default": SphereGrid(24, 9.0, 7.0, 11, 12),
        "fine": SphereGrid(32, 10.0, 7.5, 17, 14)},
    2: {"coarse": SphereGrid(32, 10.0, 7.0, 32, 12),
        "default": SphereGrid(48, 11.0, 7.5, 48, 16),
        "fine": SphereGrid(64, 12.0, 8.0, 64, 20)},
}


def sphere_grid(grid, dimension: int) -> SphereGrid:
    """A :class:`SphereGrid` from a name of :data:`GRIDS` (or None: "default") or a grid.

    Parameters
    ----------
    grid : str or SphereGrid or None
        The grid.
    dimension : int
        d, 2 or 3.

    Returns
    -------
    SphereGrid

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``dimension`` (not 2 or 3) or ``grid`` (an unknown name, or a value that is no
        grid).
    """
    if dimension not in (2, 3) or isinstance(dimension, bool):
        raise InvalidArgumentError("dimension", dimension, "2 or 3")
    if grid is None:
        grid = "default"
    if isinstance(grid, str):
        if grid not in GRIDS[dimension]:
            raise InvalidArgumentError("grid", grid, f"one of {sorted(GRIDS[dimension])}")
        return GRIDS[dimension][grid]
    if not isinstance(grid, SphereGrid):
        raise InvalidArgumentError("grid", grid, "a SphereGrid or the name of one")
    return grid

"""Accuracy and cost of the spectral hard-sphere solver (:mod:`maxwell_kinetics.sphere_spectral`):
convergence in the modes per axis N and in the quadratures of the sphere and of s, and the wall
time from the Maxwellian to the homogeneous cooling state (HCS).  Results in benchmarks/README.md
("Spectral hard spheres").

    python benchmarks/hard_sphere_spectral.py convergence    # N, sphere rule, s rule (d = 2, 3)
    python benchmarks/hard_sphere_spectral.py hcs --dimension 3 --grid default

Measures (one JSON line each):

* ``elastic``: max |Q(M)| / max Q⁻(M) for the Maxwellian at α = 1 (exactly 0 for the equation);
* ``zeta``: the cooling rate ζ(0) of the Maxwellian at α = 0.5 from Q, relative to the exact rate
  of the kernel truncated at the same R (a one-dimensional quadrature, independent of the grid),
  so that N and the quadratures are measured apart from the truncation;
* ``hcs``: a₂, a₃, the cooling rate and the residual max |dF/dτ| / max F along the march to the
  HCS, with the wall time.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time

import numpy as np
from scipy.integrate import quad
from scipy.special import gammaln

from maxwell_kinetics.sphere_grid import SphereGrid
from maxwell_kinetics.sphere_spectral import SphereOperator, cooling_state
from particles.sphere_kernels import HardSpheres


def truncated_zeta(dimension: int, cutoff: float, alpha: float = 0.5) -> float:
    """ζ(0) = (1 − α²)/(4d) ⟨V(|g|)⟩ of the Maxwellian of T = 1, V(r) = ∫dn |g·n|³ over the n
    whose cylinder (half-size R) holds g."""
    def weight(r):
        hi = min(1.0, cutoff / r) if r > 0 else 1.0
        lo = math.sqrt(max(0.0, 1 - hi * hi))
        if dimension == 3:
            return math.pi * r**3 * (hi**4 - lo**4)
        s_lo, s_hi = math.sqrt(1 - lo * lo), math.sqrt(1 - hi * hi)
        return 4 * r**3 * ((s_lo - s_lo**3 / 3) - (s_hi - s_hi**3 / 3))

    def law(r):
        x = r / math.sqrt(2)
        return math.exp((dimension - 1) * math.log(x) - x * x / 2 - (dimension / 2 - 1)
                        * math.log(2) - gammaln(dimension / 2)) / math.sqrt(2)

    mean = quad(lambda r: weight(r) * law(r), 0, 40, points=[cutoff, cutoff * math.sqrt(2)],
                limit=400)[0]
    return (1 - alpha**2) / (4 * dimension) * mean


def measure(dimension: int, grid: SphereGrid) -> dict:
    """The ``elastic`` and ``zeta`` errors of one grid, with the seconds of one evaluation."""
    row = {"dimension": dimension, **grid.to_dict()}
    elastic = SphereOperator(HardSpheres(1.0), dimension, grid)
    M = elastic.initial("gaussian")[0]
    gain, loss = elastic.collision(M)
    row["elastic"] = float(np.max(np.abs(gain - loss)) / np.max(loss))
    cooling = SphereOperator(HardSpheres(0.5), dimension, grid)
    cooling.scaled_rhs(M)  # compiled
    start = time.perf_counter()
    _, sigma = cooling.scaled_rhs(M)
    row["rhs_seconds"] = time.perf_counter() - start
    row["zeta"] = float(-2 * sigma / truncated_zeta(dimension, grid.cutoff) - 1)
    return row


def convergence() -> None:
    series = [
        (3, "N", [SphereGrid(n, 9.0, 7.0, 17, 14) for n in (12, 16, 20, 24, 32)]),
        (3, "sphere", [SphereGrid(24, 9.0, 7.0, o, 14) for o in (5, 7, 11, 17, 23)]),
        (3, "s", [SphereGrid(24, 9.0, 7.0, 17, m) for m in (4, 6, 8, 10, 12, 16)]),
        (2, "N", [SphereGrid(n, 10.0, 7.0, 64, 20) for n in (16, 24, 32, 48, 64)]),
        (2, "sphere", [SphereGrid(48, 10.0, 7.0, o, 20) for o in (8, 16, 24, 32, 48)]),
        (2, "s", [SphereGrid(48, 10.0, 7.0, 64, m) for m in (4, 6, 8, 12, 16, 20)]),
    ]
    for dimension, varied, grids in series:
        for grid in grids:
            print(json.dumps({"varied": varied, **measure(dimension, grid)}), flush=True)


def hcs(dimension: int, grid: str, tolerance: float) -> None:
    start = time.perf_counter()
    state = cooling_state(HardSpheres(0.5), dimension=dimension, grid=grid, tolerance=tolerance)
    for tau, a2, a3, residual in state.history:
        print(json.dumps({"tau": tau, "a2": a2, "a3": a3, "residual": residual}), flush=True)
    print(json.dumps({"dimension": dimension, "grid": grid, **state.grid.to_dict(),
                      "a2": state.a2, "a3": state.a3, "cooling_rate": state.cooling_rate,
                      "residual": state.residual, "tau": state.tau, "steps": state.steps,
                      "seconds": time.perf_counter() - start,
                      "loadavg": os.getloadavg()}), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("part", choices=("convergence", "hcs"))
    parser.add_argument("--dimension", type=int, default=3)
    parser.add_argument("--grid", default="default")
    parser.add_argument("--tolerance", type=float, default=1e-6)
    args = parser.parse_args()
    if args.part == "convergence":
        convergence()
    else:
        hcs(args.dimension, args.grid, args.tolerance)


if __name__ == "__main__":
    main()

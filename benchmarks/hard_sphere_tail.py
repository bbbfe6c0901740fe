"""The overpopulated tail of the hard-sphere (d = 3) and hard-disk (d = 2) homogeneous cooling
state on wide spectral grids: the fitted rate A of ln F = a + μ ln c − A c
(:func:`maxwell_kinetics.sphere_tail.measure_tail`) against the prediction A = 2K/ζ*
(:func:`maxwell_kinetics.sphere_tail.tail_rate`), per grid and window.  Results in
benchmarks/README.md ("Hard-sphere HCS tail").

    python benchmarks/hard_sphere_tail.py state --dimension 2 --alpha 0.5 \\
        --grid 64 14 10 64 20 --out /tmp/hs_tail/d2_R10.npz [--start /tmp/hs_tail/d2_R7.npz]
    python benchmarks/hard_sphere_tail.py fit /tmp/hs_tail/d2_R10.npz --windows 4,7 5,8

``state`` solves the cooling state by Newton–Krylov to the residual ``--tolerance`` (default
1e-12: the tail at F ~ 1e-10 max F needs max|dF/dτ| well below its own loss K c F), from the
Maxwellian after a march of τ = 0.5, or, with ``--start``, from a saved state of another grid
interpolated in |c| (ln F of its shells, extended linearly past its last resolved shell) with
no march; it saves F, the grid and the state's numbers to ``--out`` (npz) and prints them with
per unit shell of |c|: the largest |dF/dτ|/(K c F) (how far the shell is from steady,
relative to the tail's own loss rate), the mean loss/(K c F) (→ 1 at large c, the premise of the
prediction) and the mean gain/loss (→ 0).  ``fit`` prints one JSON row per window: the fit,
its window systematic (the window moved by a quarter of its width), the predicted A and the
local slopes.
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

from maxwell_kinetics.sphere_grid import SphereGrid
from maxwell_kinetics.sphere_spectral import SphereOperator, cooling_state
from maxwell_kinetics.sphere_steady import steady_state
from maxwell_kinetics.sphere_tail import fit_tail, radial_profile, tail_rate
from particles.sphere_kernels import HardSpheres, VariableHardSpheres


def _kernel(alpha: float, gamma: float | None):
    return HardSpheres(alpha) if gamma is None else VariableHardSpheres(alpha, exponent=gamma)


def _interpolated(path: str, grid: SphereGrid, dimension: int) -> np.ndarray:
    """A saved state's ln F of |c| (its shells; past its last resolved shell, the straight line
    fitted to its last four) at the nodes of ``grid``."""
    saved = np.load(path)
    old = SphereGrid(*saved["grid"].tolist())
    profile = radial_profile(saved["F"], old, floor=1e-13)
    c, y = profile.speed, profile.log_density
    slope, _ = np.polyfit(c[-4:], y[-4:], 1)
    axis = grid.nodes()
    r = np.sqrt(sum(x**2 for x in np.meshgrid(*([axis] * dimension), indexing="ij")))
    inside = np.interp(r, c, y)
    return np.exp(np.where(r <= c[-1], inside, y[-1] + slope * (r - c[-1])))


def state(args) -> None:
    grid = SphereGrid(int(args.grid[0]), *map(float, args.grid[1:3]), *map(int, args.grid[3:]))
    kernel = _kernel(args.alpha, args.gamma)
    d = args.dimension
    begin = time.perf_counter()
    operator = SphereOperator(kernel, d, grid)
    if args.start:
        start = _interpolated(args.start, grid, d)
        solved = steady_state(operator, start, tolerance=args.tolerance, max_newton=20)
        F, sigma, residual = solved.F, solved.sigma, solved.residual
        newton, products = solved.newton_steps, solved.krylov_steps
        zeta = -2.0 * sigma
    else:
        hcs = cooling_state(kernel, dimension=d, grid=grid, tolerance=args.tolerance)
        F, zeta, residual = hcs.F, hcs.cooling_rate, hcs.residual
        newton, products = hcs.newton_steps, hcs.krylov_steps
    seconds = time.perf_counter() - begin
    rhs, _ = operator.scaled_rhs(F)
    r = np.linalg.norm(operator.nodes, axis=-1)
    rate = np.asarray(kernel.rate(np.eye(d)[:1], np.zeros((1, d)), np))[0] * r**kernel.homogeneity
    gain, loss = operator.collision(F)
    balance = []  # per unit shell of |c|: steadiness, loss/(K c^γ F), gain/loss
    for k in range(int(grid.cutoff)):
        pick = (r >= k) & (r < k + 1) & (F > 0)
        if np.any(pick):
            balance.append([k, float(np.max(np.abs(rhs[pick]) / (rate[pick] * F[pick]))),
                            float(np.mean(loss[pick] / (rate[pick] * F[pick]))),
                            float(np.mean(gain[pick] / loss[pick]))])
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    np.savez(args.out, F=F, grid=np.array(list(grid.to_dict().values()), dtype=float),
             dimension=d, alpha=args.alpha, gamma=-1.0 if args.gamma is None else args.gamma,
             cooling_rate=zeta, residual=residual, seconds=seconds)
    print(json.dumps({"part": "state", "dimension": d, "alpha": args.alpha, "gamma": args.gamma,
                      "grid": grid.to_dict(), "cooling_rate": zeta, "residual": residual,
                      "newton_steps": newton, "products": products, "seconds": seconds,
                      "min_F_over_max": float(F.min() / F.max()),
                      "balance_by_shell": balance, "loadavg": os.getloadavg(),
                      "out": args.out}), flush=True)


def fit(args) -> None:
    saved = np.load(args.path)
    grid = SphereGrid(int(saved["grid"][0]), *saved["grid"][1:3], *saved["grid"][3:].astype(int))
    d, alpha, gamma = int(saved["dimension"]), float(saved["alpha"]), float(saved["gamma"])
    kernel = _kernel(alpha, None if gamma < 0 else gamma)
    zeta = float(saved["cooling_rate"])
    predicted = tail_rate(kernel, d, zeta) if kernel.homogeneity == 1.0 else None
    profile = radial_profile(saved["F"], grid, floor=args.floor, axis_gap=args.axis_gap)
    speed, slope = profile.local_slope()
    for text in args.windows:
        lo, hi = map(float, text.split(","))
        try:
            result = fit_tail(profile, (lo, hi), predicted=predicted).to_dict()
        except Exception as error:  # a window out of reach: say so and go on
            result = {"window": [lo, hi], "error": str(error)}
        print(json.dumps({"part": "fit", "path": args.path, "dimension": d, "alpha": alpha,
                          "grid": grid.to_dict(), "cooling_rate": zeta,
                          "resolved": profile.resolved, "threshold": profile.threshold,
                          "axis_gap": args.axis_gap,
                          **result}), flush=True)
    if args.slopes:
        print(json.dumps({"part": "slopes", "path": args.path,
                          "speed": np.round(speed, 3).tolist(),
                          "slope": np.round(slope, 4).tolist(),
                          "spread": np.round(profile.spread, 5).tolist()}), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="part", required=True)
    one = sub.add_parser("state")
    one.add_argument("--dimension", type=int, default=2)
    one.add_argument("--alpha", type=float, default=0.5)
    one.add_argument("--gamma", type=float, default=None,
                     help="variable hard spheres of rate |g|^gamma (default: hard spheres)")
    one.add_argument("--grid", nargs=5, required=True, help="N L R sphere_order radial_nodes")
    one.add_argument("--tolerance", type=float, default=1e-12)
    one.add_argument("--start", default=None)
    one.add_argument("--out", required=True)
    two = sub.add_parser("fit")
    two.add_argument("path")
    two.add_argument("--windows", nargs="+", default=["4,7"])
    two.add_argument("--floor", type=float, default=1e-12)
    two.add_argument("--slopes", action="store_true")
    two.add_argument("--axis-gap", type=float, default=0.0,
                     help="leave out the nodes within this angle (degrees) of an axis")
    args = parser.parse_args()
    if args.part == "state":
        state(args)
    else:
        fit(args)


if __name__ == "__main__":
    main()

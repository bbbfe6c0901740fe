"""a₂(α) and a₃(α) of the homogeneous cooling state of smooth inelastic hard disks (d = 2) and
spheres (d = 3), deterministic: the steady solve of the scaled spectral equation
(:func:`maxwell_kinetics.sphere_spectral.cooling_state`, Newton–Krylov), against the first
Sonine approximation (van Noije and Ernst, :func:`particles.sphere_observables.first_sonine_a2`)
and the exact a₂ of the inelastic Maxwell model in the same d
(:func:`particles.sphere_observables.maxwell_hcs_a2`); a few α against the
DSMC (:class:`particles.hard_sphere_dsmc.SphereDSMC`); and the wall time of each.  Results in
benchmarks/README.md ("Hard-sphere HCS sweep").

    python benchmarks/hard_sphere_hcs_sweep.py sweep --dimension 2      # α = 0.1 … 1.0
    python benchmarks/hard_sphere_hcs_sweep.py sweep --dimension 3
    python benchmarks/hard_sphere_hcs_sweep.py dsmc --alphas 0.5 0.2 --seeds 4
    python benchmarks/hard_sphere_hcs_sweep.py speed --seeds 32         # d = 3, α = 0.5
    python benchmarks/hard_sphere_hcs_sweep.py tail --alphas 0.5       # d = 2, wide grid

The sweep runs α downward: α = 1 is the steady solve (:func:`maxwell_kinetics.sphere_steady.
steady_state`) from the Maxwellian (its a₂, a₃ are the scheme's error), and each lower α starts
Newton from the previous α's state (continuation; a march of τ = 1 first if Newton fails from
there).  The DSMC's cooling-state a₂ of a seed is its mean over 10, 12, 14 and 16 collisions
per particle (Haff's clock), as in :mod:`maxwell_kinetics.app.comparisons._hard_spheres`; σ is
the standard error of the seeds' mean.  Each line of output is one JSON row.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time

import numpy as np

from maxwell_kinetics.sphere_grid import SphereGrid
from maxwell_kinetics.sphere_solution import sonine
from maxwell_kinetics.sphere_spectral import SphereOperator, cooling_state
from maxwell_kinetics.sphere_steady import SteadyStateError, steady_state
from particles.cooling_state_sample import sample_cooling_state
from particles.sphere_kernels import HardSpheres
from particles.sphere_observables import first_sonine_a2, maxwell_hcs_a2, window_times

WINDOW = (10, 12, 14, 16)


def sweep(dimension: int, grid: str, alphas) -> None:
    """One JSON row per α (downward from 1), each with its wall time."""
    previous = None
    for alpha in sorted(alphas, reverse=True):
        start = time.perf_counter()
        if alpha == 1.0:
            operator = SphereOperator(HardSpheres(1.0), dimension, grid)
            solved = steady_state(operator, operator.initial("gaussian")[0])
            F, residual = solved.F, solved.residual
            a2, a3 = sonine(F, operator.nodes, operator.weight)
            how = {"newton_steps": solved.newton_steps, "krylov_steps": solved.krylov_steps,
                   "march_tau": 0.0}
        else:
            kernel = HardSpheres(alpha)
            try:
                state = cooling_state(kernel, dimension=dimension, grid=grid, start=previous,
                                      march_tau=0.0 if previous is not None else 1.0)
            except SteadyStateError:
                state = cooling_state(kernel, dimension=dimension, grid=grid, start=previous,
                                      march_tau=1.0)
            F, residual, a2, a3 = state.F, state.residual, state.a2, state.a3
            how = {"newton_steps": state.newton_steps, "krylov_steps": state.krylov_steps,
                   "march_tau": state.tau}
        previous = F
        print(json.dumps({"part": "sweep", "dimension": dimension, "grid": grid,
                          "alpha": alpha, "a2": a2, "a3": a3, "residual": residual,
                          "first_sonine_a2": first_sonine_a2(alpha, dimension),
                          "maxwell_a2": (maxwell_hcs_a2(alpha, dimension) if alpha < 1
                                         else 0.0),
                          "seconds": time.perf_counter() - start, **how}), flush=True)


def dsmc(dimension: int, alphas, seeds: int, n: int) -> None:
    """One JSON row per α: the seeds' window means of a₂, a₃, their mean and σ, seconds."""
    for alpha in alphas:
        per_seed, seconds = _dsmc_seeds(alpha, dimension, seeds, n)
        mean = per_seed.mean(axis=0)
        sem = per_seed.std(axis=0, ddof=1) / math.sqrt(seeds)
        print(json.dumps({"part": "dsmc", "dimension": dimension, "alpha": alpha, "n": n,
                          "seeds": seeds, "a2": mean[0], "a2_sigma": sem[0], "a3": mean[1],
                          "a3_sigma": sem[1], "a2_per_seed": per_seed[:, 0].tolist(),
                          "seconds_per_seed": seconds.tolist()}), flush=True)


def _dsmc_seeds(alpha: float, dimension: int, seeds: int, n: int):
    """(per-seed window means of (a₂, a₃), shape (seeds, 2); seconds of each seed) of the
    DSMC at N = ``n``."""
    from particles.hard_sphere_dsmc import SphereDSMC
    from particles.sphere_observables import sonine_coefficients

    times = window_times(alpha, dimension, WINDOW)
    values, seconds = [], []
    for seed in range(seeds):
        start = time.perf_counter()
        engine = SphereDSMC(n, alpha, dimension=dimension)
        rng = np.random.default_rng(seed)
        state = engine.initial_state(rng)
        window = []
        for t in times:
            state = engine.advance(state, float(t), rng)
            obs = sonine_coefficients(state.velocities)
            window.append((obs["a2"], obs["a3"]))
        values.append(np.mean(window, axis=0))
        seconds.append(time.perf_counter() - start)
    return np.array(values), np.array(seconds)


def speed(grid: str, march_taus, seeds: int, n: int, target: float,
          tolerance: float | None = None, snapshots: int = 40) -> None:
    """d = 3, α = 0.5, side by side in one process: the wall time of the deterministic HCS from
    the Maxwellian for each march τ before Newton (twice each: the first call of the process
    compiles; the second is warm), and ``seeds`` DSMC runs of N = ``n`` (the window means of
    a₂, as in ``dsmc``), whose spread σ₁ of one seed sets the seeds needed for σ(a₂) =
    ``target``: (σ₁/target)², assuming σ ∝ 1/√seeds.  The ratio is that DSMC's time (the
    seeds × the mean seconds of one) over the deterministic time; the same for the DSMC in
    rescaled chunks (:func:`particles.cooling_state_sample.sample_cooling_state`, ``seeds``
    runs of ``snapshots`` snapshots), which pays for one warm-up per seed.  Newton stops at the
    residual ``tolerance`` (None: cooling_state's 1e-10).  Then how far the last a₂ and a₃ are
    from a steady state to 1e-12."""
    kernel, dimension = HardSpheres(0.5), 3
    rows = []
    for march_tau in march_taus:
        for label in ("first call", "second call"):
            start = time.perf_counter()
            state = cooling_state(kernel, dimension=dimension, grid=grid, march_tau=march_tau,
                                  tolerance=tolerance)
            seconds = time.perf_counter() - start
            rows.append({"part": "speed", "call": label, "grid": grid, "march_tau": march_tau,
                         "a2": state.a2, "a3": state.a3, "residual": state.residual,
                         "march_steps": state.steps, "newton_steps": state.newton_steps,
                         "krylov_steps": state.krylov_steps, "seconds": seconds,
                         "loadavg": os.getloadavg()})
            print(json.dumps(rows[-1]), flush=True)
    values, seconds = _dsmc_seeds(0.5, dimension, seeds, n)
    values = values[:, 0]  # a₂
    sigma1 = float(values.std(ddof=1))
    needed = (sigma1 / target) ** 2
    dsmc_seconds = needed * float(seconds.mean())
    print(json.dumps({"part": "speed", "dsmc_n": n, "seeds": seeds, "a2": float(values.mean()),
                      "a2_sigma": sigma1 / math.sqrt(seeds), "sigma_one_seed": sigma1,
                      "seconds_per_seed": float(seconds.mean()), "target": target,
                      "seeds_needed": needed, "dsmc_seconds": dsmc_seconds,
                      "loadavg": os.getloadavg()}), flush=True)
    # the DSMC in rescaled chunks: one warm-up per seed, then `snapshots` snapshots one chunk
    # apart; σ(a₂) of the seeds' mean assumed ∝ 1/√snapshots (snapshots farther apart than
    # a₂'s correlation time), so σ = target takes snapshots × (σ/target)² per seed
    sample = sample_cooling_state(n, 0.5, dimension=dimension, seeds=range(seeds),
                                  snapshots=snapshots, progress=False)
    a2, a2_sigma = sample.seed_values("a2")
    longer = snapshots * (a2_sigma / target) ** 2
    per_chunk = sample.seconds / (seeds * (sample.parameters["warmup"] + snapshots))
    sampler_seconds = seeds * (sample.parameters["warmup"] + longer) * per_chunk
    print(json.dumps({"part": "speed", "sampler_n": n, "seeds": seeds, "snapshots": snapshots,
                      "a2": a2, "a2_sigma": a2_sigma, "seconds": sample.seconds,
                      "seconds_per_chunk": per_chunk, "snapshots_needed": longer,
                      "sampler_seconds": sampler_seconds, "loadavg": os.getloadavg()}),
          flush=True)
    for row in rows:
        print(json.dumps({"part": "speed", "call": row["call"], "march_tau": row["march_tau"],
                          "ratio": dsmc_seconds / row["seconds"],
                          "sampler_ratio": sampler_seconds / row["seconds"]}), flush=True)
    operator = SphereOperator(kernel, dimension, grid)
    tight = steady_state(operator, state.F, tolerance=1e-12)
    a2, a3 = sonine(tight.F, operator.nodes, operator.weight)
    print(json.dumps({"part": "speed", "tolerance": tolerance, "a2_to_1e-12": a2,
                      "a2_change": abs(a2 - state.a2), "a3_change": abs(a3 - state.a3)}),
          flush=True)


def tail(alpha: float, grid) -> None:
    """d = 2: the local slope −d ln F/d|c| of the steady F along the c_x axis on a wide grid,
    against the large-|c| balance of loss and dilation, −d ln F/d|c| ≈ A + d/|c| with
    A = 2K/ζ* (K = ∫dn |ĝ·n| = 4 in d = 2, ζ* = −2σ′ the solver's own cooling rate; in the
    reduced c̃ = c/√2 of the Sonine convention the tail is exp(−√2 A c̃))."""
    grid = SphereGrid(*grid)
    start = time.perf_counter()
    try:
        state = cooling_state(HardSpheres(alpha), dimension=2, grid=grid, march_tau=0.0)
    except SteadyStateError:
        state = cooling_state(HardSpheres(alpha), dimension=2, grid=grid)
    operator = SphereOperator(HardSpheres(alpha), 2, grid)
    c = operator.nodes[:, grid.points // 2, 0]  # the c_x axis at c_y = 0
    line = state.F[:, grid.points // 2]
    a = 2.0 * 4.0 / state.cooling_rate
    rows = []
    for lo, hi in ((3.0, 4.0), (4.0, 5.0), (5.0, 6.0), (6.0, 7.0)):
        pick = (c >= lo) & (c <= hi) & (line > 0)
        slope = -np.polyfit(c[pick], np.log(line[pick]), 1)[0]
        rows.append({"window": [lo, hi], "slope": slope,
                     "A_plus_d_over_c": a + 2.0 / (0.5 * (lo + hi))})
    print(json.dumps({"part": "tail", "alpha": alpha, "grid": grid.to_dict(), "a2": state.a2,
                      "cooling_rate": state.cooling_rate, "A": a, "residual": state.residual,
                      "rows": rows, "seconds": time.perf_counter() - start}), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("part", choices=("sweep", "dsmc", "speed", "tail"))
    parser.add_argument("--dimension", type=int, default=3)
    parser.add_argument("--grid", default="default")
    parser.add_argument("--alphas", type=float, nargs="+",
                        default=[round(0.1 * k, 1) for k in range(1, 11)])
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--march-tau", type=float, nargs="+", default=[0.5],
                        help="speed: the march τ before Newton, each timed (default 0.5)")
    parser.add_argument("--tolerance", type=float, default=None,
                        help="speed: Newton's residual (default cooling_state's 1e-10)")
    parser.add_argument("--target", type=float, default=1e-4,
                        help="speed: the DSMC's σ(a₂) to reach")
    parser.add_argument("--snapshots", type=int, default=40,
                        help="speed: snapshots per run of the DSMC in rescaled chunks")
    args = parser.parse_args()
    if args.part == "sweep":
        sweep(args.dimension, args.grid, args.alphas)
    elif args.part == "dsmc":
        dsmc(args.dimension, args.alphas, args.seeds, args.n)
    elif args.part == "tail":
        tail(args.alphas[0], (64, 14.0, 10.0, 64, 16))
    else:
        speed(args.grid, args.march_tau, args.seeds, args.n, args.target, args.tolerance,
              args.snapshots)


if __name__ == "__main__":
    main()

"""Throughput of the hard-sphere DSMC (:class:`particles.hard_sphere_dsmc.SphereDSMC`): N
particles in d = 3 at restitution α from a Maxwellian of T = 1, to a given number of collisions
per particle (2 · pair collisions / N, the project's τ), timed segment by segment; with T/T_Haff
and the Sonine coefficients a₂, a₃ at each time (the first Sonine a₂ for comparison).  Results in
benchmarks/README.md ("Hard-sphere DSMC").

    python benchmarks/hard_sphere_dsmc.py                       # N = 1e6, α = 0.5, 30 per particle
    python benchmarks/hard_sphere_dsmc.py --n 100000 --collisions 10

Under Haff's law the pair collisions per particle to t are (ν₀/2)(2/ζ₀) ln(1 + ζ₀t/2), so
τ collisions per particle are reached at t = (2/ζ₀)(exp(ζ₀ τ/(2ν₀)) − 1).
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from particles.hard_sphere_dsmc import SphereDSMC
from particles.sphere_observables import first_sonine_a2, haff_temperature, sonine_coefficients


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--restitution", type=float, default=0.5)
    parser.add_argument("--dimension", type=int, default=3)
    parser.add_argument("--collisions", type=float, default=30.0,
                        help="collisions per particle to reach (2 pair collisions / N)")
    parser.add_argument("--segments", type=int, default=6)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    a, d = args.restitution, args.dimension
    nu0 = (8.0 if d == 3 else 4.0) * math.sqrt(math.pi)
    zeta0 = (1 - a * a) * nu0 / d
    taus = np.linspace(args.collisions / args.segments, args.collisions, args.segments)
    times = (2.0 / zeta0) * np.expm1(zeta0 * taus / (2.0 * nu0))
    engine = SphereDSMC(args.n, a, dimension=d)
    rng = np.random.default_rng(args.seed)
    state = engine.initial_state(rng)
    rows, total, done = [], 0.0, 0
    for t in times:
        start = time.perf_counter()
        state = engine.advance(state, float(t), rng)
        seconds = time.perf_counter() - start
        total += seconds
        new = state.collisions - done
        done = state.collisions
        sonine = sonine_coefficients(state.velocities)
        rows.append({"t": float(t), "collisions_per_particle": 2 * done / args.n,
                     "seconds": seconds, "collisions_per_second": new / seconds,
                     "T_over_haff": sonine["temperature"] / float(haff_temperature(t, a, d)),
                     "a2": sonine["a2"], "a3": sonine["a3"]})
        print(json.dumps(rows[-1]), flush=True)
    print(json.dumps({"n": args.n, "dimension": d, "restitution": a, "seed": args.seed,
                      "seconds": total, "pair_collisions": done,
                      "collisions_per_second": done / total,
                      "first_sonine_a2": first_sonine_a2(a, d)}))


if __name__ == "__main__":
    main()

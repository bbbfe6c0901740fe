"""The exact sticky gas against its exact late-time laws (``particles/sticky_exact.py``,
compared by ``particles/sticky_comparison.py``): χ²/dof of the mass-weighted velocity histogram and
of the cluster-mass histogram at several times, pooled over seeds, and the corrections to scaling.

    python benchmarks/sticky_exact.py                          # N = 1e7, 4 seeds
    python benchmarks/sticky_exact.py --n 1000000 --seeds 3 --times 10 100

Units: density n = 1 and ⟨v²⟩ = T₀ = 1 (the engine's draw), so w = v t^{1/3} and
μ = m / t^{2/3}.  The histograms, their bins and variance models are those of
:class:`particles.sticky_comparison.ExactLawComparison` (shared with comparison 9): the
mass-weighted
velocity histogram (24 bins of width 0.25 on w ∈ [−3, 3] plus the open bins beyond, variance
Σ m² over the clusters in a bin) and the cluster-mass histogram (about 12 bins per decade in m,
Poisson variance).  Also printed: E t^{2/3} against the exact
0.44275 and the mean cluster mass over ℓ against 1/1.32826.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from particles.sticky import StickyGas, StickyParams  # noqa: E402
from particles.sticky_comparison import ExactLawComparison  # noqa: E402
from particles.sticky_exact import exact_moments  # noqa: E402


def compare(n_particles: int, seeds: int, t: float, seed0: int = 0) -> dict:
    """χ² of the velocity and mass histograms at time t, pooled over ``seeds`` runs
    (:class:`particles.sticky_comparison.ExactLawComparison`, which states the bins and variance
    models)."""
    engine = StickyGas(StickyParams(n_particles, 1.0, "gaussian"))
    cmp = ExactLawComparison(t)
    for seed in range(seed0, seed0 + seeds):
        cmp.add(engine.advance(engine.initial_state(np.random.default_rng(seed)), t))
    vel, mass, corr = cmp.velocity(), cmp.mass(), cmp.corrections()
    return {
        "t": t,
        "chi2_velocity": vel["chi2"],
        "dof_velocity": vel["dof"],
        "chi2_mass": mass["chi2"],
        "dof_mass": mass["dof"],
        "energy": corr["energy"]["value"][0],
        "energy_se": corr["energy"]["value"][1] or 0.0,
        "clusters": corr["clusters"]["value"][0],
        "velocity_residual": (vel["observed"] - vel["expected"]) / vel["sigma"],
        "mass_residual": (mass["observed"] - mass["expected"]) / np.sqrt(mass["expected"]),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000_000)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--times", type=float, nargs="+", default=[10.0, 100.0, 1000.0, 1e4])
    args = ap.parse_args(argv)
    mom = exact_moments()
    print(f"exact: E t^(2/3) -> {mom['velocity_variance']:.6f}, clusters*ell/N -> "
          f"{mom['clusters']:.6f}")
    print(f"N = {args.n}, {args.seeds} seeds")
    print("t        chi2_v/dof    chi2_m/dof    E t^(2/3)           clusters*ell/N   wall")
    for t in args.times:
        t0 = time.perf_counter()
        r = compare(args.n, args.seeds, t)
        print(f"{t:<8g} {r['chi2_velocity']:8.1f}/{r['dof_velocity']:<4d} "
              f"{r['chi2_mass']:8.1f}/{r['dof_mass']:<4d} "
              f"{r['energy']:.5f} ± {r['energy_se']:.5f}   {r['clusters']:.5f}        "
              f"{time.perf_counter() - t0:.0f} s", flush=True)


if __name__ == "__main__":
    main()

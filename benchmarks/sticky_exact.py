"""The exact sticky gas against its exact late-time laws (``particles/sticky.py``, section
"Exact late-time laws"): χ²/dof of the mass-weighted velocity histogram and of the cluster-mass
histogram at several times, pooled over seeds, and the corrections to scaling.

    python benchmarks/sticky_exact.py                          # N = 1e7, 4 seeds
    python benchmarks/sticky_exact.py --n 1000000 --seeds 3 --times 10 100

Units: density n = 1 and ⟨v²⟩ = T₀ = 1 (the engine's draw), so w = v t^{1/3} and
μ = m / t^{2/3}.  Velocity histogram: 24 bins of width 0.25 on w ∈ [−3, 3], each particle
counted (mass-weighted); its variance per bin is Σ m² over the clusters in the bin (a cluster's
particles move together; clusters taken as independent); the outer bins are merged inwards
until each holds at least 25 clusters.  Mass histogram: the integer masses
grouped into bins [m_a, m_b] (half-integer edges), roughly log-spaced in μ from 1/ℓ to 4,
ℓ = t^{2/3}, expected count N/ℓ ∫ F dμ over the bin, Poisson variance; bins with fewer than 25
expected clusters are merged into their neighbour.  Also printed: E t^{2/3} against the exact
0.44275 and the mean cluster mass over ℓ against 1/1.32826.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from particles.sticky import (  # noqa: E402
    StickyGas,
    StickyParams,
    exact_mass_density,
    exact_moments,
    exact_velocity_density,
)

W_EDGES = np.linspace(-3.0, 3.0, 25)


def _bin_integral(density, edges, nodes=12):
    x, w = np.polynomial.legendre.leggauss(nodes)
    lo, hi = edges[:-1, None], edges[1:, None]
    pts = 0.5 * (hi - lo) * (x[None, :] + 1.0) + lo
    return (density(pts) * w[None, :]).sum(axis=1) * 0.5 * (hi - lo)[:, 0]


def mass_bins(t: float, n_particles: int, seeds: int):
    """Integer mass bins [m_a, m_b] with half-integer edges, and their expected counts."""
    ell = t ** (2.0 / 3.0)
    upper = max(2, int(4.0 * ell))
    cuts = np.unique(np.round(np.geomspace(1, upper + 1, 30)).astype(int))
    edges = cuts - 0.5
    expected = n_particles * seeds / ell * _bin_integral(exact_mass_density, edges / ell, 16)
    keep = [0]
    acc = 0.0
    for i, e in enumerate(expected):  # merge bins with fewer than 25 expected clusters
        acc += e
        if acc >= 25.0 or i == expected.size - 1:
            keep.append(i + 1)
            acc = 0.0
    edges = edges[np.array(keep)]
    expected = n_particles * seeds / ell * _bin_integral(exact_mass_density, edges / ell, 16)
    return edges, expected


def velocity_groups(clusters_per_bin, minimum: int = 25) -> np.ndarray:
    """Start indices of groups of adjacent velocity bins: the outer bins are merged inwards
    (from each end) until each group holds at least ``minimum`` clusters."""
    k = clusters_per_bin.size
    lo, acc = 0, 0.0
    while lo < k // 2 and acc + clusters_per_bin[lo] < minimum:
        acc += clusters_per_bin[lo]
        lo += 1
    hi, acc = k, 0.0
    while hi > k // 2 and acc + clusters_per_bin[hi - 1] < minimum:
        acc += clusters_per_bin[hi - 1]
        hi -= 1
    return np.concatenate([[0], np.arange(lo + 1, min(hi, k))]) if hi > lo + 1 else np.array([0])


def compare(n_particles: int, seeds: int, t: float, seed0: int = 0) -> dict:
    """χ² of the velocity and mass histograms at time t, pooled over ``seeds`` runs."""
    engine = StickyGas(StickyParams(n_particles, 1.0, "gaussian"))
    ell = t ** (2.0 / 3.0)
    v_counts = np.zeros(W_EDGES.size - 1)
    v_var = np.zeros(W_EDGES.size - 1)
    v_n = np.zeros(W_EDGES.size - 1)
    m_edges, m_expected = mass_bins(t, n_particles, seeds)
    m_counts = np.zeros(m_edges.size - 1)
    energies, clusters = [], []
    for seed in range(seed0, seed0 + seeds):
        state = engine.advance(engine.initial_state(np.random.default_rng(seed)), t)
        masses = state.masses.astype(float)
        w = state.cluster_velocities * t ** (1.0 / 3.0)
        v_counts += np.histogram(w, W_EDGES, weights=masses)[0]
        v_var += np.histogram(w, W_EDGES, weights=masses**2)[0]
        v_n += np.histogram(w, W_EDGES)[0]
        m_counts += np.histogram(masses, m_edges)[0]
        energies.append(float(np.mean(state.velocities**2)) * t ** (2.0 / 3.0))
        clusters.append(masses.size / n_particles * ell)
    v_expected = n_particles * seeds * _bin_integral(exact_velocity_density, W_EDGES)
    groups = velocity_groups(v_n)
    v_counts, v_var, v_expected = (np.add.reduceat(a, groups) for a in (v_counts, v_var,
                                                                         v_expected))
    chi_v = float(np.sum((v_counts - v_expected) ** 2 / v_var))
    chi_m = float(np.sum((m_counts - m_expected) ** 2 / m_expected))
    return {
        "t": t,
        "chi2_velocity": chi_v,
        "dof_velocity": groups.size,
        "chi2_mass": chi_m,
        "dof_mass": m_edges.size - 1,
        "energy": float(np.mean(energies)),
        "energy_se": float(np.std(energies, ddof=1) / math.sqrt(seeds)) if seeds > 1 else 0.0,
        "clusters": float(np.mean(clusters)),
        "velocity_residual": (v_counts - v_expected) / np.sqrt(v_var),
        "mass_residual": (m_counts - m_expected) / np.sqrt(m_expected),
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

"""Observables of particles.observables against direct formulas and exact statistics."""

import math

import numpy as np
import pytest

from particles import observables as obs
from particles.validation import InvalidArgumentError


def test_energy_and_momentum_per_particle():
    v = np.array([1.0, -3.0, 2.0, 0.0])
    assert obs.energy(v) == pytest.approx(14.0 / 4)
    assert obs.momentum(v) == 0.0
    assert obs.energy(np.stack([v, 2 * v])) == pytest.approx([3.5, 14.0])


def test_structure_factor_matches_direct_dft_and_parseval():
    rng = np.random.default_rng(0)
    for n in (16, 17):  # even N has a Nyquist mode, odd N does not
        v = rng.standard_normal(n)
        k, s = obs.structure_factor(v)
        m = np.arange(n // 2 + 1)
        assert np.allclose(k, 2 * np.pi * m / n)
        direct = np.abs(np.exp(-1j * np.outer(k, np.arange(n))) @ v) ** 2 / n
        assert np.allclose(s, direct, rtol=1e-12, atol=1e-12)
        assert s[0] == pytest.approx(v.sum() ** 2 / n)
        # Parseval over the full circle: modes other than 0 and Nyquist appear twice.
        weights = np.full(s.size, 2.0)
        weights[0] = 1.0
        if n % 2 == 0:
            weights[-1] = 1.0
        assert np.sum(weights * s) / n == pytest.approx(np.mean(v**2), rel=1e-12)


def test_structure_factor_of_white_noise_is_flat_at_the_energy():
    # 64 runs of N = 4096 unit Gaussians: each S(k) (k != 0, Nyquist) is E * Exp(1); the mean
    # over 64 runs and 2047 modes has relative error 1/sqrt(64*2047) = 2.8e-3: 5 sigma = 1.4e-2.
    rng = np.random.default_rng(1)
    v = rng.standard_normal((64, 4096))
    k, s = obs.structure_factor(v)
    assert np.mean(s[1:-1]) == pytest.approx(1.0, abs=1.4e-2)
    kb, sb, count = obs.log_bin(k, s, bins_per_decade=4)
    assert np.all(kb > 0) and np.all(np.diff(kb) > 0)
    assert count.sum() == k.size - 1  # every k > 0 mode lands in exactly one bin
    # the smallest bins hold one mode of 64 runs: relative error 1/8; the rest far less.
    assert np.all(np.abs(sb - 1.0) < 5.0 / np.sqrt(64 * count))


def test_correlation_is_the_ring_autocorrelation():
    rng = np.random.default_rng(2)
    v = rng.standard_normal(50)
    c = obs.correlation(v)
    direct = np.array([np.mean(v * np.roll(v, -r)) for r in range(50)])
    assert np.allclose(c, direct, atol=1e-13)
    assert c[0] == pytest.approx(obs.energy(v))
    both = obs.correlation(np.stack([v, -2 * v]))
    assert np.allclose(both, 2.5 * direct, atol=1e-12)


def test_rescaled_histogram_density_and_binomial_error():
    # 2e5 unit Gaussians, bins of width 0.1: every bin density within 5 binomial errors of the
    # exact Gaussian bin probability / width (the error is the binomial standard deviation).
    from scipy.special import ndtr

    rng = np.random.default_rng(3)
    v = 3.0 * rng.standard_normal(200_000)
    h = obs.rescaled_histogram(v)
    assert h.v0 == pytest.approx(np.sqrt(np.mean(v**2)))
    x = v / h.v0
    assert h.count.sum() == np.count_nonzero((x >= -6) & (x <= 6))
    assert np.sum(h.density * np.diff(h.edges)) == pytest.approx(h.count.sum() / v.size)
    exact = np.diff(ndtr(h.edges)) / np.diff(h.edges)
    inner = exact > 1e-3
    assert np.all(np.abs(h.density - exact)[inner] < 5 * h.error[inner])
    p = h.count / v.size
    assert np.allclose(h.error, np.sqrt(v.size * p * (1 - p)) / (v.size * 0.1))


def test_rescaled_histogram_scale_and_bins_arguments():
    v = np.array([-2.0, -1.0, 1.0, 2.0])
    h = obs.rescaled_histogram(v, bins=[-3, 0, 3], v0=1.0)
    assert h.count.tolist() == [2, 2]
    assert obs.rescaled_histogram(v, bins=4).edges.tolist() == [-6, -3, 0, 3, 6]
    with pytest.raises(InvalidArgumentError, match="bins"):
        obs.rescaled_histogram(v, bins=[1.0, 0.0])
    with pytest.raises(InvalidArgumentError, match="v0"):
        obs.rescaled_histogram(v, v0=-1.0)
    with pytest.raises(InvalidArgumentError, match="energy"):
        obs.rescaled_histogram(np.zeros(4))


def test_rescaled_histogram_of_velocities_whose_energy_underflows():
    # |v| ~ 1e-160: ⟨v²⟩ is subnormal (~1e-320, few significant bits); |v| ~ 1e-170: it underflows
    # to 0.  x = v/√E is still well defined and must equal the histogram of the same velocities
    # at unit scale.  All zeros stay undefined (the error above); ⟨v²⟩ overflowing is the mirror.
    rng = np.random.default_rng(4)
    v = rng.standard_normal(1000)
    ref = obs.rescaled_histogram(v)
    for scale in (1e-160, 1e-170, 1e160):
        h = obs.rescaled_histogram(v * scale)
        assert np.array_equal(h.count, ref.count), scale
        assert h.v0 == pytest.approx(scale * ref.v0, rel=1e-14)
    assert 0 < np.mean((v * 1e-160) ** 2) < 1e-300 and np.mean((v * 1e-170) ** 2) == 0.0


def test_velocity_profile_is_label_ordered():
    # The profile is (i, v(i)) in label order, a copy.  Label order is ring order on the lattice
    # (late: neighbouring sites strongly correlated, and a shuffle of the labels destroys that),
    # while for Ulam it carries no spatial meaning (neighbour correlation at noise level).
    from particles.driver import simulate
    from particles.lattice import Lattice
    from particles.ulam import Ulam

    i, v = obs.velocity_profile([3.0, -1.0, 2.0])
    assert i.tolist() == [0, 1, 2] and v.tolist() == [3.0, -1.0, 2.0]
    rows = np.arange(6.0).reshape(2, 3)
    i, p = obs.velocity_profile(rows)
    assert i.tolist() == [0, 1, 2] and np.array_equal(p, rows)
    p[0, 0] = 99.0
    assert rows[0, 0] == 0.0  # a copy
    with pytest.raises(InvalidArgumentError, match="v="):
        obs.velocity_profile(np.zeros((2, 2, 2)))

    n = 4000
    lattice = simulate(Lattice(n, 0.5), [40.0], 1, progress=False).velocities
    i, prof = obs.velocity_profile(lattice)
    assert np.array_equal(prof, lattice) and np.array_equal(i, np.arange(n))

    def neighbour(u):
        return np.mean(u * np.roll(u, -1)) / np.mean(u * u)

    # Neighbour correlation C(1)/C(0), measured at τ = 40, N = 4000, r = 0.5: lattice 0.949 to
    # 0.955 over 10 seeds; Ulam mean 0.002, standard deviation 0.016 = 1.0/sqrt(N), largest
    # |value| 2.6/sqrt(N) over 60 seeds.  Bounds: lattice > 0.8; shuffled or Ulam < 5/sqrt(N).
    shuffled = np.random.default_rng(0).permutation(prof)
    assert neighbour(prof) > 0.8 and abs(neighbour(shuffled)) < 5 / np.sqrt(n)
    ulam = obs.velocity_profile(simulate(Ulam(n, 0.5), [40.0], 1, progress=False).velocities)[1]
    assert abs(neighbour(ulam)) < 5 / np.sqrt(n)


def test_mean_sem_is_the_standard_error_over_seeds():
    from particles.observables import mean_sem, mean_sem_json

    # [1, 2, 3, 4]: sample variance 5/3, so sem = sqrt(5/3) / 2
    mean, sem = mean_sem([1.0, 2.0, 3.0, 4.0])
    assert mean == 2.5 and sem == pytest.approx(math.sqrt(5.0 / 3.0) / 2.0, rel=1e-15)
    rows = np.array([[1.0, 10.0], [3.0, 10.0]])
    m, e = mean_sem(rows, axis=0)
    assert np.allclose(m, [2.0, 10.0]) and np.allclose(e, [1.0, 0.0])
    assert math.isnan(mean_sem([7.0])[1])
    assert mean_sem_json([7.0]) == [7.0, None] and mean_sem_json([]) == [None, None]
    assert mean_sem_json([1.0, 3.0]) == [2.0, 1.0]


def test_haff_time_and_energy():
    from particles.md.observables import haff_energy, haff_time

    t0 = haff_time(0.5, 2.0)
    assert t0 == pytest.approx(math.sqrt(math.pi) / (0.75 * 2.0), rel=1e-15)
    assert haff_energy(t0, 0.5, 2.0) == pytest.approx(0.25, rel=1e-15)  # T₀ / (1 + 1)²
    assert haff_time(1.0, 1.0) == math.inf


def test_kurtosis_by_hand_and_at_the_ends_of_float64():
    from particles.observables import kurtosis

    # ⟨v²⟩ = (1 + 1 + 4 + 4)/4 = 5/2, ⟨v⁴⟩ = (1 + 1 + 16 + 16)/4 = 17/2: 17/2 / (25/4) = 1.36
    assert kurtosis([1.0, -1.0, 2.0, -2.0]) == pytest.approx(1.36, rel=1e-15)
    assert kurtosis([1e300, -1e300, 2e300, -2e300]) == pytest.approx(1.36, rel=1e-15)
    assert kurtosis([1e-300, -1e-300, 2e-300, -2e-300]) == pytest.approx(1.36, rel=1e-15)
    assert np.isnan(kurtosis(np.zeros(5))) and np.isnan(kurtosis([1.0, np.inf]))

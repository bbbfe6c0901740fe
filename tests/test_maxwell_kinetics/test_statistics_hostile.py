"""The statistics helpers on hostile input: fits through points that are not distinct, NaN
inside bin edges and samples, mismatched lengths, and degrees that the points cannot determine.
Each raises ``InvalidArgumentError`` naming the argument (before: NumPy's RankWarning,
LinAlgError, ZeroDivisionError, or a silent NaN or negative count)."""

from __future__ import annotations

import numpy as np
import pytest

from maxwell_kinetics import statistics as st
from maxwell_kinetics.exact import f_hat
from particles.validation import InvalidArgumentError

NAN, INF = float("nan"), float("inf")
X = np.random.default_rng(1).normal(size=200)


@pytest.mark.parametrize("call, name", [
    (lambda: st.weighted_slope([1, 1, 1, 1, 1], [1, 2, 3, 4, 5]), "x"),  # one abscissa
    (lambda: st.weighted_slope([2.0, 2.0], [1.0, 2.0], [1.0, 1.0]), "x"),  # det = 0: NaN before
    (lambda: st.weighted_slope([1.0], [1.0]), "x"),
    (lambda: st.weighted_slope([1.0, 2.0, NAN], [1.0, 2.0, 3.0]), "x"),
    (lambda: st.weighted_slope([1.0, 2.0], [1.0, 2.0, 3.0]), "y"),
    (lambda: st.weighted_slope([1.0, 2.0], [1.0, 2.0], [0.0, 1.0]), "sigma"),
    (lambda: st.weighted_slope([1.0, 2.0], [1.0, 2.0], [1.0]), "sigma"),
    (lambda: st.seed_slope([1.0, 1.0, 1.0], [[1.0, 2.0, 3.0]]), "x"),
    (lambda: st.seed_slope([1.0, 2.0, 3.0], [[1.0, 2.0, 3.0]], degree=5), "x"),
    (lambda: st.seed_slope([1.0, 2.0, 3.0], [[1.0, 2.0, 3.0]], degree=0), "degree"),
    (lambda: st.seed_slope([1.0, 2.0, 3.0], [[1.0, 2.0, 3.0]], degree=True), "degree"),
    (lambda: st.seed_slope([1.0, 2.0, 3.0], [[1.0, INF, 3.0]]), "ys"),
    (lambda: st.bin_counts(X, [0.0, NAN, 1.0]), "edges"),  # gave a count of -20
    (lambda: st.bin_counts([NAN], [0.0, 1.0]), "samples"),
    (lambda: st.f_interval_probabilities([0.0, NAN, 1.0]), "edges"),
    (lambda: st.f_interval_probabilities([1.0, 0.0]), "edges"),  # a negative probability
    (lambda: st.interval_probabilities(f_hat, [0.0, NAN, 1.0], 40.0), "edges"),
    (lambda: st.interval_probabilities(f_hat, [0.0, INF], 40.0), "edges"),
    (lambda: st.interval_probabilities(f_hat, [0.0, 1.0], NAN), "q_max"),
    (lambda: st.interval_probabilities(None, [0.0, 1.0], 40.0), "G"),
    (lambda: st.compare_histograms([X], [0.0, 1.0], [0.3, 0.2]), "probabilities"),
    (lambda: st.compare_histograms([X], [0.0, NAN], [0.3]), "edges"),
    (lambda: st.compare_histograms([[]], [0.0, 1.0], [0.3]), "samples"),
    (lambda: st.compare_histograms([X], [0.0, 1.0], [0.3], min_expected=NAN), "min_expected"),
])
def test_hostile_arguments_are_invalid_arguments(call, name):
    with pytest.raises(InvalidArgumentError) as info:
        call()
    assert info.value.name == name


def test_good_fits_are_unchanged():
    # exact lines: the fit must return them to round-off
    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    slope, err, icpt = st.weighted_slope(x, 2.0 * x + 1.0)
    assert slope == pytest.approx(2.0, abs=1e-12) and icpt == pytest.approx(1.0, abs=1e-12)
    slope, err, icpt = st.weighted_slope(x, 2.0 * x + 1.0, np.ones(5))
    assert slope == pytest.approx(2.0, abs=1e-12) and err == pytest.approx(1 / np.sqrt(10))
    mean, _, slopes = st.seed_slope(x, [3.0 * x, 5.0 * x + x**2], degree=2)
    assert slopes == pytest.approx([3.0, 5.0], abs=1e-10) and mean == pytest.approx(4.0)
    assert st.f_interval_probabilities([-INF, 0.0, INF]) == pytest.approx([0.5, 0.5])


def test_interval_probabilities_many_bins_in_bounded_memory():
    # 2000 bins of f × 1072 nodes: the whole kernel at once peaked at ~100 MB (10⁷ bins: a
    # MemoryError); built in blocks of 2¹⁸ elements (4 MB complex, a few temporaries) it stays
    # under 40 MB (measured 15 MB).  The probabilities are f's CDF differences to round-off.
    import tracemalloc

    edges = np.linspace(-5.0, 5.0, 2001)
    st.interval_probabilities(f_hat, edges[:3], 40.0)  # the imports, outside the measure
    tracemalloc.start()
    try:
        prob = st.interval_probabilities(f_hat, edges, 40.0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 40e6, peak
    assert np.max(np.abs(prob - np.diff(st.f_cdf(edges)))) < 1e-12


def test_interval_probabilities_far_edge_is_refused_before_the_work():
    calls = []

    def G(q):
        calls.append(q.size)
        return f_hat(q)

    with pytest.raises(InvalidArgumentError) as err:
        st.interval_probabilities(G, [-1e7, 0.0, 1.0], 40.0)
    assert err.value.name == "edges" and "|edges| <=" in str(err.value)
    assert calls == []


def test_interval_probabilities_wide_bins_match_the_cdf():
    # Bins wider than 64 in reach, grouped by factor 2 of their reach: still f's CDF.
    edges = np.array([-3000.0, -700.0, -90.0, -1.0, 0.0, 2.0, 100.0, 150.0, 4000.0])
    prob = st.interval_probabilities(f_hat, edges, 40.0)
    assert np.max(np.abs(prob - np.diff(st.f_cdf(edges)))) < 1e-10


def test_a_million_bins_are_refused_before_any_work_and_a_thousand_are_not():
    # 10⁶ bins on [−6, 6] (1.1·10⁹ kernel elements at q_max = 35) ran for 280 s with no word
    from maxwell_kinetics.statistics import MAX_KERNEL_WORK, interval_probabilities

    def gaussian(q):
        return np.exp(-q * q / 2)

    with pytest.raises(InvalidArgumentError, match=r"edges=.*1000000 bins.*fewer bins"):
        interval_probabilities(gaussian, np.linspace(-6.0, 6.0, 10**6 + 1), 35.0)
    assert MAX_KERNEL_WORK == 5e8
    p = interval_probabilities(gaussian, np.linspace(-6.0, 6.0, 1001), 35.0)
    assert p.sum() == pytest.approx(1.0, abs=1e-8)  # the mass beyond ±6 is 2e-9

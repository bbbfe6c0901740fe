"""The observables on hostile input: non-finite values inside arrays (velocities, bin edges,
wavenumbers), booleans and complex numbers where reals are expected, and values near the float
limit (an overflow gives ±inf where the true value overflows, never NaN)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from particles import observables as obs
from particles.validation import InvalidArgumentError

NAN, INF = float("nan"), float("inf")
V = np.random.default_rng(0).normal(size=100)


@pytest.mark.parametrize("call, name", [
    (lambda: obs.rescaled_histogram(V, [0.0, NAN, 1.0]), "bins"),  # NaN passed diff(edges) > 0
    (lambda: obs.rescaled_histogram(V, [-INF, 0.0, INF]), "bins"),
    (lambda: obs.rescaled_histogram(V, [False, True]), "bins"),
    (lambda: obs.rescaled_histogram(V, [0j, 1.0]), "bins"),
    (lambda: obs.rescaled_histogram(V, None, True), "v0"),
    (lambda: obs.rescaled_histogram(V, None, 1j), "v0"),
    (lambda: obs.rescaled_histogram([1j, 1.0]), "v"),
    (lambda: obs.rescaled_histogram(["a"]), "v"),
    (lambda: obs.histogram_from_counts([0.0, NAN], [1], 1, 1.0), "edges"),
    (lambda: obs.histogram_from_counts([0.0, 1.0], [1, 2], 3, 1.0), "count"),
    (lambda: obs.histogram_from_counts([0.0, 1.0], [1], True, 1.0), "n"),
    (lambda: obs.energy([NAN]), "v"),
    (lambda: obs.energy([1j]), "v"),
    (lambda: obs.momentum(["x"]), "v"),
    (lambda: obs.structure_factor([NAN, 1.0]), "v"),
    (lambda: obs.correlation([INF, 1.0]), "v"),
    (lambda: obs.velocity_profile([NAN, 1.0]), "v"),
    (lambda: obs.wavenumbers(True), "n"),
    (lambda: obs.wavenumbers(2.5), "n"),
    (lambda: obs.log_bin([1.0, INF], [1.0, 2.0]), "k"),  # was "Maximum allowed size exceeded"
    (lambda: obs.log_bin([1.0, NAN], [1.0, 2.0]), "k"),  # was silently dropped
    (lambda: obs.log_bin([1.0, 2.0], [1.0, NAN]), "s"),
    (lambda: obs.log_bin([1.0, 2.0], [1.0, 2.0], NAN), "bins_per_decade"),
    (lambda: obs.log_bin([1.0, 2.0], [1.0, 2.0], 2.5), "bins_per_decade"),  # was taken as 2
    (lambda: obs.mean_sem(["x"]), "values"),
    (lambda: obs.mean_sem([1.0, 2.0], True), "axis"),
    (lambda: obs.mean_sem([1.0, 2.0], 5), "axis"),
])
def test_hostile_arguments_are_invalid_arguments(call, name):
    with pytest.raises(InvalidArgumentError) as info:
        call()
    assert info.value.name == name


def test_values_near_the_float_limit_overflow_to_inf_not_nan():
    # C(r) of v = ±1e200 alternating is ±1e400: ±inf, not the NaN the inverse FFT of inf gave
    c = obs.correlation([1e200, -1e200, 1e200, -1e200])
    assert c.tolist() == [INF, -INF, INF, -INF]
    k, s = obs.structure_factor([1e200, 3e199, 1.0])
    assert np.all(np.isinf(s))
    assert obs.energy([1e200]) == INF
    np.testing.assert_allclose(obs.correlation([1e152, 2e152]), [2.5e304, 2e304], rtol=1e-14)
    # the mean and error of values near 1e308 are finite (the sum overflowed to inf, then NaN)
    mean, sem = obs.mean_sem([1e308, 1e308, -1e308])
    assert mean == pytest.approx(1e308 / 3, rel=1e-14)
    assert sem == pytest.approx(np.std([1, 1, -1], ddof=1) / np.sqrt(3) * 1e308, rel=1e-14)


@pytest.mark.parametrize(("field", "value"), [
    ("density", np.nan), ("density", -1.0), ("error", np.inf), ("error", -0.5),
])
def test_histogram_distance_refuses_non_finite_or_negative_values(field, value):
    # Before: a density of nan gave chi2 = nan and ks = nan silently; a negative one a KS
    # distance of 2.
    import dataclasses

    from particles.observables import rescaled_histogram

    h = rescaled_histogram(np.random.default_rng(1).normal(size=(1, 2000)))
    bad = dataclasses.replace(h, **{field: np.where(np.arange(h.density.size) == 3, value,
                                                    getattr(h, field))})
    with pytest.raises(InvalidArgumentError) as err:
        h.distance(bad)
    assert err.value.name == "other" and field in str(err.value)
    with pytest.raises(InvalidArgumentError) as err:
        bad.distance(h)
    assert err.value.name == "histogram"


def test_refusals_word_for_word_and_the_types_returned():
    """The histogram's ``bins`` and ``v`` refusals and the velocity arrays' refusal name the
    argument, the value and what was expected; bins = 1 and 10⁶ are the ends of the range;
    energy and momentum are floats for one run and one value per run for (R, N)."""
    v = np.random.default_rng(0).standard_normal(100)
    for bins in (0, 2.5, True, 10**6 + 1, float("nan"), "x"):
        with pytest.raises(InvalidArgumentError) as info:
            obs.rescaled_histogram(v, bins=bins)
        assert str(info.value) == (f"argument bins={bins!r} is invalid: expected an integer in "
                                   "[1, 1e6] or an array of edges")
    assert obs.rescaled_histogram(v, bins=1).density.shape == (1,)
    assert obs.rescaled_histogram(v, bins=10**6).density.shape == (10**6,)
    with pytest.raises(InvalidArgumentError) as info:
        obs.rescaled_histogram(np.zeros(10))
    assert str(info.value) == ("argument v='energy [0.]' is invalid: expected a finite, "
                               "non-zero energy per run")
    for bad, shape in ((np.zeros((2, 2, 2)), "(2, 2, 2)"), (np.array([]), "(0,)")):
        for observable in (obs.energy, obs.momentum):
            with pytest.raises(InvalidArgumentError) as info:
                observable(bad)
            assert str(info.value) == (f"argument v='array of shape {shape}' is invalid: "
                                       "expected a 1..2-dimensional velocity array")
    runs = np.arange(6.0).reshape(2, 3)
    np.testing.assert_allclose(obs.energy(runs), [5.0 / 3.0, 50.0 / 3.0], rtol=1e-15)
    np.testing.assert_array_equal(obs.momentum(runs), [1.0, 4.0])
    for one_run in (obs.energy(runs[0]), obs.momentum(runs[0])):
        assert type(one_run) is float
    assert obs.momentum(runs[1]) == 4.0


def test_histogram_from_counts_by_hand_and_an_odd_ring_correlation():
    """Bins [0, 1) and [1, 3) holding 2 and 5 of n = 7 values: centres ½ and 2, densities
    2/7 and 5/(7·2); a negative count is refused with the counts and what was expected.  The
    correlation of an odd ring of 7 sites is (1/N) Σ_i v_i v_{i+k}, by direct sums."""
    hist = obs.histogram_from_counts(np.array([0.0, 1.0, 3.0]), np.array([2.0, 5.0]), 7, 1.0)
    np.testing.assert_array_equal(hist.centres, [0.5, 2.0])
    np.testing.assert_allclose(hist.density, [2.0 / 7.0, 5.0 / 14.0], rtol=1e-15)
    # JSON form: plain lists; error √(n p (1 − p))/(n · width), p = count/n
    d = hist.to_dict()
    assert sorted(d) == ["centres", "density", "error"]
    assert all(type(x) is list for x in d.values()) and d["centres"] == [0.5, 2.0]
    np.testing.assert_allclose(d["density"], [2.0 / 7.0, 5.0 / 14.0], rtol=1e-15)
    np.testing.assert_allclose(d["error"], [math.sqrt(2.0 * 5.0 / 7.0) / 7.0,
                                            math.sqrt(5.0 * 2.0 / 7.0) / 14.0], rtol=1e-15)
    with pytest.raises(InvalidArgumentError) as info:
        obs.histogram_from_counts(np.array([0.0, 1.0, 3.0]), np.array([2.0, -5.0]), 7, 1.0)
    assert str(info.value) == ("argument count=[2.0, -5.0] is invalid: expected 2 non-negative "
                               "counts, one per bin")
    v = np.random.default_rng(1).standard_normal(7)
    c = obs.correlation(v)
    assert c.shape == (7,)
    direct = [np.mean(v * np.roll(v, -k)) for k in range(7)]  # (1/N) Σ_i v_i v_{i+k}, periodic
    np.testing.assert_allclose(c, direct, rtol=1e-12, atol=1e-15)


def test_mean_sem_axes_refusals_and_warnings():
    """``mean_sem``: a single number is one value (error NaN); axes run from −ndim to ndim − 1,
    others (and booleans, floats) are refused word for word, as are no values along the axis;
    non-finite values give inf or NaN without a warning; near the float limit the rescaling is
    per column, so a column of ordinary values keeps its exact mean and error."""
    import warnings

    mean, sem = obs.mean_sem(3.0)
    assert mean == 3.0 and np.isnan(sem)
    a = np.arange(6.0).reshape(2, 3)
    mean, sem = obs.mean_sem(a, axis=-2)
    np.testing.assert_allclose(mean, [1.5, 2.5, 3.5], rtol=1e-15)
    np.testing.assert_allclose(sem, [1.5, 1.5, 1.5], rtol=1e-15)
    for axis in (2, -3, True, 1.0):
        with pytest.raises(InvalidArgumentError) as info:
            obs.mean_sem(a, axis=axis)
        assert str(info.value) == (f"argument axis={axis!r} is invalid: expected an axis of the "
                                   "2-dimensional values")
    with pytest.raises(InvalidArgumentError) as info:
        obs.mean_sem(np.zeros((0, 3)))
    assert str(info.value) == ("argument values=(0, 3) is invalid: expected at least one value "
                               "along the axis")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mean, sem = obs.mean_sem([np.inf, 1.0])
        assert mean == np.inf and np.isnan(sem)
        mean, sem = obs.mean_sem([np.nan, 1.0])
        assert np.isnan(mean) and np.isnan(sem)
        mean, sem = obs.mean_sem(np.array([[1e308, 1.0], [1e308, 3.0]]), axis=0)
    np.testing.assert_array_equal(mean, [1e308, 2.0])
    np.testing.assert_array_equal(sem, [0.0, 1.0])


def test_log_bin_by_hand():
    """Edges 10^(j/b): with b = 2 the bins [1, √10), [√10, 10), [10, 10√10), [10√10, 100) hold
    1.5 and 2, then 5, 15 and 40 (k = 0 dropped); with the default b = 10 the edge 10^0.1 ≈ 1.259
    puts 1.24 with 1 and 1.3 above it; b = 1 is allowed; no modes give empty arrays (the counts
    of integer type); ``k`` and ``s`` of other shapes are refused word for word."""
    k = np.array([0.0, 1.5, 2.0, 5.0, 15.0, 40.0])
    s = np.array([9.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    k_mean, s_mean, count = obs.log_bin(k, s, 2)
    np.testing.assert_allclose(k_mean, [1.75, 5.0, 15.0, 40.0], rtol=1e-15)
    np.testing.assert_allclose(s_mean, [1.5, 3.0, 4.0, 5.0], rtol=1e-15)
    np.testing.assert_array_equal(count, [2, 1, 1, 1])
    assert obs.log_bin(np.array([1.0, 1.24, 1.3]), np.ones(3))[2].tolist() == [2, 1]
    assert obs.log_bin(np.array([1.5, 15.0]), np.ones(2), 1)[2].tolist() == [1, 1]
    empty = obs.log_bin(np.array([]), np.array([]))
    assert [a.shape for a in empty] == [(0,), (0,), (0,)] and empty[2].dtype.kind == "i"
    with pytest.raises(InvalidArgumentError) as info:
        obs.log_bin(np.array([1.0, 2.0]), np.array([1.0]))
    assert str(info.value) == "argument s='shape (1,)' is invalid: expected the shape of k, (2,)"
    for bad_k, bad_s, name in ((np.ones((2, 2)), np.ones((2, 2)), "k"),
                               (np.ones(4), np.ones((2, 2)), "s")):
        with pytest.raises(InvalidArgumentError) as info:
            obs.log_bin(bad_k, bad_s)
        assert info.value.name == name


def test_log_bin_edges_kurtosis_and_smallest_inputs():
    """``log_bin``: a k exactly on an edge (100 = 10^(4/2)) opens its bin, apart from 50 in the
    bin below; k below 1 gets its own bins (0.05 and 0.5 apart, b = 2); the base is 10 (9.9
    and 10.5 straddle the edge 10 at b = 1).  The kurtosis of no velocities is NaN, of tiny
    ones their kurtosis without an underflow warning.  One wavenumber, one count of one value,
    and histograms of several runs (R, N) are allowed."""
    import warnings

    for k, b in (([1.5, 50.0, 100.0], 2), ([0.05, 0.5], 2), ([9.9, 10.5], 1)):
        k_mean, _, count = obs.log_bin(np.array(k), np.ones(len(k)), b)
        np.testing.assert_array_equal(k_mean, k)
        np.testing.assert_array_equal(count, [1] * len(k))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.isnan(obs.kurtosis(np.array([])))
        tiny = obs.kurtosis(np.array([1e-200, 2e-200, -3e-200]))
    assert tiny == pytest.approx(obs.kurtosis(np.array([1.0, 2.0, -3.0])), rel=1e-12)
    assert obs.wavenumbers(1).tolist() == [0.0]
    one = obs.histogram_from_counts(np.array([0.0, 1.0]), np.array([1.0]), 1, 1.0)
    assert one.density.tolist() == [1.0]
    runs = obs.rescaled_histogram(np.random.default_rng(0).standard_normal((3, 50)), bins=4)
    assert runs.count.sum() == 150 and runs.samples == 150


def test_histogram_from_counts_refusals_word_for_word():
    """Each argument of ``histogram_from_counts`` is refused by name, with its value and what
    was expected."""
    edges, count = np.array([0.0, 1.0]), np.ones(1)
    for args, message in (
            ((edges, np.ones((1, 1)), 1, 1.0), "argument count=[[1.0]] is invalid: expected a "
                                               "1-dimensional array (got shape (1, 1))"),
            ((np.array([1.0, 0.0]), count, 1, 1.0),
             "argument edges=[1.0, 0.0] is invalid: expected strictly increasing edges"),
            ((edges, count, 1, 0.0), "argument v0=0.0 is invalid: expected a finite number > 0"),
            ((edges, count, 0, 1.0), "argument n=0 is invalid: expected an integer >= 1")):
        with pytest.raises(InvalidArgumentError) as info:
            obs.histogram_from_counts(*args)
        assert str(info.value) == message


def test_mean_sem_over_a_later_axis_and_of_single_rows_and_columns():
    """``mean_sem`` over the last axis of a non-square array is each row's mean and s/√m; an
    (m, 1) input keeps one column (arrays of shape (1,), not floats); a single value per column
    gives NaN errors of the columns' shape; values at the float limit give a finite error
    (sem ≤ max|value|: [M, −M] has mean 0 and sem exactly M), without a warning."""
    import warnings

    a = np.array([[1.0, 2.0, 3.0, 4.0, 5.0], [2.0, 3.0, 4.0, 5.0, 7.0], [0.0, 0.0, 0.0, 0.0, 1.0]])
    for axis in (1, -1):
        mean, sem = obs.mean_sem(a, axis=axis)
        np.testing.assert_allclose(mean, [3.0, 4.2, 0.2], rtol=1e-15)
        # s² by hand: Σ(x − x̄)²/(m − 1) with m = 5
        s2 = np.array([10.0 / 4, (2.2**2 + 1.2**2 + 0.2**2 + 0.8**2 + 2.8**2) / 4, 0.8 / 4])
        np.testing.assert_allclose(sem, np.sqrt(s2 / 5), rtol=1e-14)
    mean, sem = obs.mean_sem(a.T[:, :1])  # the column (1, 2, 0)… as shape (5, 1)
    assert isinstance(mean, np.ndarray) and mean.shape == (1,) and sem.shape == (1,)
    np.testing.assert_allclose(mean, [3.0], rtol=1e-15)
    np.testing.assert_allclose(sem, [np.sqrt(10.0 / 4 / 5)], rtol=1e-15)
    mean, sem = obs.mean_sem(a[:1])  # one value per column
    assert mean.shape == (5,) and sem.shape == (5,) and np.all(np.isnan(sem))
    big = np.finfo(float).max
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert obs.mean_sem([big, -big]) == (0.0, big)
        # a row of huge values beside ordinary ones, over the last axis: sem = √(4M²/(4·3))
        mean, sem = obs.mean_sem(np.array([[big, -big, big, -big], [1.0, 2.0, 3.0, 4.0]]), axis=1)
    np.testing.assert_array_equal(mean, [0.0, 2.5])
    np.testing.assert_allclose(sem, [big / np.sqrt(3.0), np.sqrt(5.0 / 3.0 / 4.0)],
                               rtol=1e-15)
    # ordinary and tiny values are not rescaled: the smallest subnormal keeps its exact mean
    # (halved it would round to 0) and a zero error
    tiny = np.nextafter(0.0, 1.0)
    assert obs.mean_sem([tiny, tiny, tiny]) == (tiny, 0.0)


def test_spectrum_of_many_large_values_does_not_overflow():
    """The structure factor of N = 8192 alternating ±3e150 is N·(3e150)² = 7.4e304 at k = π and 0
    elsewhere: finite, although |v̂(π)|² = (N·3e150)² is beyond the float limit (the velocities
    are rescaled by a power of two before the transform, not only from 2⁵⁰⁰ on)."""
    n, x = 8192, 3e150
    v = x * (-1.0) ** np.arange(n)
    k, s = obs.structure_factor(v)
    assert s[-1] == pytest.approx(n * x * x, rel=1e-14)
    assert np.all(np.isfinite(s)) and np.all(np.abs(s[:-1]) <= 1e-12 * s[-1])
    c = obs.correlation(v)
    np.testing.assert_allclose(c, x * x * (-1.0) ** np.arange(c.size), rtol=1e-12)


def test_distance_keeps_bins_of_five_samples_by_default():
    """``Histogram.distance``'s default ``min_count`` is 5: a bin that holds exactly 5 samples
    enters χ², and not with ``min_count=6`` (15 of the 120 samples lie outside the edges, so
    no normalisation ties the bins: dof is the number of bins used)."""
    edges = np.array([0.0, 1.0, 2.0])
    a = obs.histogram_from_counts(edges, np.array([5, 100]), 120, 1.0)
    b = obs.histogram_from_counts(edges, np.array([7, 98]), 120, 1.0)
    assert a.distance(b).bins.tolist() == [True, True] and a.distance(b).dof == 2
    assert a.distance(b, min_count=6).bins.tolist() == [False, True]


def test_kurtosis_refuses_what_is_not_an_array_of_real_velocities_by_name():
    """Complex velocities raised a raw TypeError from ``float()``; one number raised NumPy's
    "return arrays must be of ArrayType".  Each is refused naming the argument; non-finite
    velocities still give NaN, as documented."""
    for bad in (np.array([1 + 1j, 2.0]), 1e308, 2.0, [True, 2.0], "1,2"):
        with pytest.raises(InvalidArgumentError, match=r"argument v="):
            obs.kurtosis(bad)
    assert math.isnan(obs.kurtosis(np.array([1.0, math.inf])))
    assert obs.kurtosis([1.0, -1.0]) == 1.0  # a list of real numbers is an array
    for values, counts, name in (([1 + 1j], [1.0], "values"), ([1.0, 2.0], [1.0], "counts"),
                                 ([1.0], [math.nan], "counts"), (2.0, [1.0], "values")):
        with pytest.raises(InvalidArgumentError, match=rf"argument {name}="):
            obs.weighted_kurtosis(values, counts)
    assert obs.weighted_kurtosis([1.0, -1.0], [2, 2]) == 1.0

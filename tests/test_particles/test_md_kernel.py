"""The MD kernel (particles/md/kernel.py) and every hand-written copy of it, bit for bit.

The scalar loops of the light-cone engine write the kernel's prediction and collision out for
speed between ``# kernel copy: LABEL (begin)`` and ``(end)`` comments.  These tests cut those very
lines out of the engine's source, execute them on many random and edge-case inputs (zero gap,
negative gap from round-off, equal velocities, |Δ| < δ, r = 1, r = 0, r next to 1, signed zeros,
the clip and the swap of the separation guard) and compare every result with the kernel's by its
bits; the array forms of the kernel are compared with the scalar forms the same way.  The edge
cases are counted, so that a generator that stopped producing them fails the test.
"""

import inspect
import math
import textwrap

import numpy as np
import pytest

from particles.md import kernel, lightcone
from particles.md.kernel import collide, collide_many, collision_time, collision_times

SAMPLES = 4000


def bits(values):
    """The IEEE bit patterns (so that -0.0 differs from 0.0 and every NaN shows)."""
    return np.asarray(values, dtype=np.float64).view(np.int64)


def copies(function):
    """{label: compiled code} of the kernel copies in ``function``'s source."""
    lines = inspect.getsource(function).splitlines()
    out = {}
    start = None
    for k, line in enumerate(lines):
        text = line.strip()
        if text.startswith("# kernel copy: ") and text.endswith(" (begin)"):
            start, label = k + 1, text[len("# kernel copy: ") : -len(" (begin)")]
        elif text.startswith("# kernel copy: ") and text.endswith(" (end)"):
            assert text[len("# kernel copy: ") : -len(" (end)")] == label
            body = textwrap.dedent("\n".join(lines[start:k]))
            out[label] = compile(body, f"<{function.__name__}: {label}>", "exec")
            start = None
    assert start is None
    return out


def test_every_copy_is_found():
    assert set(copies(lightcone._sequential_slab)) == {
        "collide",
        "collision_time, left pair (h, i) with h = bb",
        "collision_time, right pair (j, k)",
    }
    assert set(copies(lightcone._burst)) == {"collide, inelastic branch"}
    # no other function of the package carries a copy
    for module in (lightcone, kernel):
        for name, obj in vars(module).items():
            if inspect.isfunction(obj) and obj.__module__ == module.__name__:
                if name not in ("_sequential_slab", "_burst"):
                    assert "kernel copy" not in inspect.getsource(obj), name


# -- inputs ----------------------------------------------------------------------------------


def velocity_pairs(rng, size):
    """(vi, vj) with every edge case of the collision: equal, one ulp apart, signed zeros,
    magnitudes from 1e-30 to 1e30, both orders."""
    scale = 10.0 ** rng.uniform(-30, 30, (size, 2))
    v = rng.standard_normal((size, 2)) * np.where(rng.random((size, 1)) < 0.5, 1.0, scale)
    kind = rng.integers(0, 8, size)
    v[kind == 1, 1] = v[kind == 1, 0]  # equal
    v[kind == 2, 1] = np.nextafter(v[kind == 2, 0], -np.inf)  # one ulp apart
    v[kind == 3] = rng.choice([0.0, -0.0, 1e-300, -1e-300, 1.0], (np.sum(kind == 3), 2))
    v[kind == 4, 1] = -v[kind == 4, 0]  # symmetric
    return v[:, 0], v[:, 1]


RESTITUTIONS = [0.0, 0.5, 0.9, 1.0 - 2.0**-52, 1.0 - 1e-9, 1.0]


def collision_cases(rng, size):
    """(vi, vj, p, delta, elastic_only) tuples."""
    vi, vj = velocity_pairs(rng, size)
    r = rng.choice(RESTITUTIONS + [0.0, 0.0] + list(rng.random(4)), size)  # r = 0: swaps
    p = 0.5 * (1.0 + r)  # transfer_fraction
    delta = rng.choice([0.0, 1e-4, 0.3], size)
    same = rng.random(size) < 0.1  # δ exactly |Δ|: the boundary of the elastic test
    delta[same] = np.abs(vi - vj)[same]
    elastic_only = r == 1.0
    # Outside the physics, to exercise the clip of the guard (with p in [1/2, 1) and vi > vj
    # round-off never needed it in 4e5 tries, only the swap): p = 1 and p = 5/4 without the
    # elastic shortcut, and δ = -1, which sends non-approaching pairs through the rule.
    odd = rng.random(size) < 0.15
    p[odd] = rng.choice([1.0, 1.25], np.sum(odd))
    elastic_only[odd] = False
    delta[rng.random(size) < 0.1] = -1.0
    for case in zip(vi, vj, p, delta, elastic_only, strict=True):
        yield float(case[0]), float(case[1]), float(case[2]), float(case[3]), bool(case[4])


def test_scalar_collide_against_its_definition_and_the_guards_are_exercised():
    # the kernel itself against the collision rule and the guard written plainly
    rng = np.random.default_rng(0)
    clipped = swapped = elastic = 0
    for vi, vj, p, delta, elastic_only in collision_cases(rng, SAMPLES):
        a, e, el = collide(vi, vj, p, delta, elastic_only)
        if elastic_only or vi - vj < delta:
            assert el and bits([a, e]).tolist() == bits([vj, vi]).tolist()
            elastic += 1
            continue
        d = (vi - vj) * p
        raw = (vi - d, vj + d)
        ca, ce = (min(max(x, vj), vi) for x in raw)
        clipped += (ca, ce) != raw
        swapped += ca > ce
        assert not el and (a, e) == ((ce, ca) if ca > ce else (ca, ce))
        if vi > vj:
            assert vj <= a <= e <= vi  # the pair separates
    # measured with SAMPLES = 4000, seed 0: 2249 elastic, 210 clipped, 19 swapped
    assert elastic > 100 and clipped > 10 and swapped > 10, (elastic, clipped, swapped)


@pytest.mark.parametrize("seed", [1, 2])
def test_copy_of_collide_in_the_scalar_loop_is_the_kernel(seed):
    code = copies(lightcone._sequential_slab)["collide"]
    rng = np.random.default_rng(seed)
    for vi, vj, p, delta, elastic_only in collision_cases(rng, SAMPLES):
        ns = dict(vi=vi, vj=vj, p=p, delta=delta, elastic_only=elastic_only)
        ns.update(V={}, i=3, j=0, elastic=0)
        exec(code, ns)
        a, e, el = collide(vi, vj, p, delta, elastic_only)
        got = [ns["V"][3], ns["V"][0], ns["vi"], ns["vj"]]
        assert bits(got).tolist() == bits([a, e, a, e]).tolist(), (vi, vj, p, delta)
        assert ns["elastic"] == int(el)


@pytest.mark.parametrize("seed", [3, 4])
def test_copy_of_collide_in_the_burst_is_the_kernel(seed):
    # the burst runs this copy for inelastic collisions only (vi > vj, Δ ≥ δ, r < 1)
    code = copies(lightcone._burst)["collide, inelastic branch"]
    rng = np.random.default_rng(seed)
    seen = 0
    for vi, vj, p, delta, elastic_only in collision_cases(rng, 2 * SAMPLES):
        if elastic_only or not vi > vj or vi - vj < delta:
            continue
        ns = dict(vi=vi, vj=vj, p=p, d=vi - vj)
        exec(code, ns)
        a, e, el = collide(vi, vj, p, delta, elastic_only)
        assert not el
        assert bits([ns["a"], ns["e"]]).tolist() == bits([a, e]).tolist(), (vi, vj, p)
        seen += 1
    assert seen > SAMPLES / 4


@pytest.mark.parametrize("seed", [5, 6])
def test_collide_many_is_collide_elementwise(seed):
    rng = np.random.default_rng(seed)
    # r = 1 also without the elastic shortcut, r = 1.5 (p = 5/4) and δ = -1: outside the
    # physics, for the clip of the guard
    for r in RESTITUTIONS + [float(rng.random()), 1.0, 1.5]:
        vi, vj = velocity_pairs(rng, SAMPLES)
        delta = float(rng.choice([0.0, 1e-4, 0.3, -1.0]))
        p = 0.5 * (1.0 + r)
        elastic_only = bool(r == 1.0 and rng.random() < 0.5)
        keep = vi.copy(), vj.copy()
        a, e, el = collide_many(vi, vj, p, delta, elastic_only)
        assert bits(vi).tolist() == bits(keep[0]).tolist()  # inputs untouched
        assert bits(vj).tolist() == bits(keep[1]).tolist()
        pairs = zip(vi.tolist(), vj.tolist(), strict=True)
        want = [collide(x, y, p, delta, elastic_only) for x, y in pairs]
        assert bits(a).tolist() == bits([w[0] for w in want]).tolist(), r
        assert bits(e).tolist() == bits([w[1] for w in want]).tolist(), r
        assert el.dtype == bool and el.tolist() == [w[2] for w in want]  # a boolean mask


# -- predictions -----------------------------------------------------------------------------


def stores(rng, n):
    """Lazily stored positions, times and velocities of n particles on a ring of reduced length
    lr, in order at their common time, with the edge cases of the prediction: zero gaps,
    negative gaps of a few ulps (round-off), equal velocities, t_last equal or not."""
    lr = float(rng.choice([1.0, 7.5, 1e3]))
    t = float(rng.choice([1.0, 123.456]))  # times are never negative
    xt = np.sort(rng.uniform(0.0, lr, n))
    kind = rng.integers(0, 5, n)
    for k in range(1, n):
        if kind[k] == 1:
            xt[k] = xt[k - 1]  # zero gap
        elif kind[k] == 2:
            xt[k] = xt[k - 1] - abs(xt[k - 1]) * 4e-16 * rng.integers(1, 4)  # negative gap
    v = rng.standard_normal(n)
    v[kind == 3] = np.roll(v, 1)[kind == 3]  # equal to the left neighbour's
    v[rng.random(n) < 0.1] = 0.0
    tl = np.where(rng.random(n) < 0.5, t, t - rng.uniform(0.0, 1.0, n))
    tl[rng.random(n) < 0.2] = t - 2.0**-40
    tl[rng.random(n) < 0.1] = 0.0
    x = xt - v * (t - tl)  # stored at t_last, so that at t they are at xt (up to round-off)
    return x, tl, v, lr


def predictions_of_the_kernel(x, tl, v, lr):
    n = len(x)
    return [collision_time(x, tl, b, v[b], (b + 1) % n, v[(b + 1) % n], lr) for b in range(n)]


@pytest.mark.parametrize("seed", [7, 8])
def test_collision_times_is_collision_time_elementwise(seed):
    rng = np.random.default_rng(seed)
    counts = {"inf": 0, "zero gap": 0}
    for n in (2, 3, 5, 40) * 25:
        x, tl, v, lr = stores(rng, n)
        pairs = rng.permutation(n)
        keep = pairs.copy()
        got = collision_times(x, tl, v, pairs, lr)
        assert pairs.tolist() == keep.tolist()
        lists = x.tolist(), tl.tolist(), v.tolist()
        want = predictions_of_the_kernel(*lists, lr)
        assert bits(got).tolist() == bits([want[b] for b in pairs]).tolist()
        assert bits(want).tolist() == bits(predictions_of_the_kernel(x, tl, v, lr)).tolist()
        counts["inf"] += sum(w == math.inf for w in want)
        counts["zero gap"] += sum(w == max(tl[b], tl[(b + 1) % n]) for b, w in enumerate(want))
    # measured (seeds 7, 8): 718 and 722 non-approaching pairs, 129 and 135 immediate collisions
    # (zero or negative gaps) of 1300 pairs
    assert counts["inf"] > 200 and counts["zero gap"] > 100, counts


@pytest.mark.parametrize("seed", [9, 10])
def test_copies_of_collision_time_in_the_scalar_loop_are_the_kernel(seed):
    # the loop's state right after the collision of pair b = (i, j) at time cb: X[i] = xc,
    # TL[i] = TL[j] = cb (X[j] = xc - lr at the seam); the copies predict pairs (h, i), (j, k)
    found = copies(lightcone._sequential_slab)
    left = found["collision_time, left pair (h, i) with h = bb"]
    right = found["collision_time, right pair (j, k)"]
    rng = np.random.default_rng(seed)
    counts = {"inf": 0, "now": 0}
    for n in (2, 3, 4, 30) * 40:
        x, tl, v, lr = stores(rng, n)
        X, TL, V = x.tolist(), tl.tolist(), v.tolist()
        b = int(rng.integers(n))
        i, j = b, (b + 1) % n
        cb = max(TL[i], TL[j]) + float(rng.choice([0.0, 2.0**-30, 0.5]))
        xc = X[i] + V[i] * (cb - TL[i])
        X[i], TL[i] = xc, cb
        X[j], TL[j] = (xc - lr if j == 0 else xc), cb
        bb, k = (b - 1) % n, (j + 1) % n
        common = dict(V=V, TL=TL, X=X, cb=cb, lr=lr, inf=math.inf)
        ns = dict(common, bb=bb, vi=V[i], xc=xc, i=i)
        exec(left, ns)
        ns_r = dict(common, j=j, k=k, vj=V[j])
        exec(right, ns_r)
        want_l = collision_time(X, TL, bb, V[bb], i, V[i], lr)
        want_r = collision_time(X, TL, j, V[j], k, V[k], lr)
        assert bits([ns["cl"], ns_r["cr"]]).tolist() == bits([want_l, want_r]).tolist(), (n, b)
        counts["inf"] += (want_l == math.inf) + (want_r == math.inf)
        counts["now"] += (want_l == cb) + (want_r == cb)
    # measured (seeds 9, 10): 177 and 200 non-approaching pairs, 33 and 23 immediate collisions
    # of 320 predictions
    assert counts["inf"] > 40 and counts["now"] > 10, counts


def test_md_observables_refusals_word_for_word():
    """The MD observables refuse what is not an MD state, parameters that are not MDParams or
    not this state's, and a bad restitution, density or initial energy, naming the argument,
    the value received and what was expected."""
    from particles.md import MDEngine, MDParams
    from particles.md import observables as mdo
    from particles.validation import InvalidArgumentError

    params = MDParams(8, 1.0, 0.5)
    state = MDEngine(params).initial_state(np.random.default_rng(0))
    other = MDParams(9, 1.0, 0.5)
    cases = [
        (lambda: mdo.collisions_per_particle("x"),
         "argument state='str' is invalid: expected a particles.MDState"),
        (lambda: mdo.total_momentum(3),
         "argument state='int' is invalid: expected a particles.MDState"),
        (lambda: mdo.profile_i(None),
         "argument state='NoneType' is invalid: expected a particles.MDState"),
        (lambda: mdo.rod_positions(state, "p"),
         "argument params='str' is invalid: expected a particles.MDParams"),
        (lambda: mdo.rod_positions(state, other),
         "argument params='n = 9' is invalid: expected the parameters of this state (N = 8)"),
        (lambda: mdo.profile_x(state, other),
         "argument params='n = 9' is invalid: expected the parameters of this state (N = 8)"),
        (lambda: mdo.haff_time(0.5, -1.0),
         "argument density=-1.0 is invalid: expected a finite number > 0"),
        (lambda: mdo.haff_time(0.5, 1.0, 0.0),
         "argument t0_energy=0.0 is invalid: expected a finite number > 0"),
        (lambda: mdo.haff_energy(1.0, 2.0, 1.0),
         "argument restitution=2.0 is invalid: expected a number in [0, 1]"),
        (lambda: mdo.initial_cooling_rate(0.5, 1.0, -2.0),
         "argument t0_energy=-2.0 is invalid: expected a finite number > 0"),
    ]
    for call, message in cases:
        with pytest.raises(InvalidArgumentError) as info:
            call()
        assert str(info.value) == message
    assert mdo.rod_positions(state, params).shape == (8,)  # this state's own parameters pass


def test_rod_positions_stream_freely_to_the_time_asked_and_haff_at_r_one():
    """Between collisions the rods stream freely: at time t the contact points are x_i + v_i t
    (unwrapped) plus i ℓ for the rod length ℓ, computed here by hand; the profile is ordered
    by those positions.  Haff's time is infinite for elastic rods (r = 1: no cooling); the
    refusals name ``t``."""
    from particles.md import MDEngine, MDParams
    from particles.md import observables as mdo
    from particles.validation import InvalidArgumentError

    params = MDParams(8, 1.0, 0.5, rod_length=0.01)
    state = MDEngine(params).initial_state(np.random.default_rng(0))
    assert state.time == 0.0
    by_hand = state.positions + 0.25 * state.velocities + 0.01 * np.arange(8)
    np.testing.assert_allclose(mdo.rod_positions(state, params, 0.25), by_hand, rtol=1e-15)
    np.testing.assert_allclose(mdo.rod_positions(state, params),
                               state.positions + 0.01 * np.arange(8), rtol=1e-15)
    y, v = mdo.profile_x(state, params, 0.25)
    order = np.argsort(by_hand)
    np.testing.assert_allclose(y, by_hand[order], rtol=1e-15)
    np.testing.assert_array_equal(v, state.velocities[order])
    assert mdo.haff_time(1.0, 1.0) == math.inf and math.isfinite(mdo.haff_time(0.999, 1.0))
    # Haff's law T(t) = T₀/(1 + t/t₀)²: a quarter of T₀ at t₀ (density 2 and T₀ = 9, so that
    # n and √T₀ cannot stand in for each other)
    t0 = mdo.haff_time(0.5, 2.0, 9.0)
    assert mdo.haff_energy(t0, 0.5, 2.0, 9.0) == pytest.approx(9.0 / 4.0, rel=1e-14)
    with pytest.raises(InvalidArgumentError) as info:
        mdo.haff_energy([1.0, -0.5], 0.5, 1.0)
    assert str(info.value) == "argument t=[1.0, -0.5] is invalid: expected times >= 0"
    with pytest.raises(InvalidArgumentError) as info:  # 40 times are listed, more are a shape
        mdo.haff_energy(np.linspace(-1.0, 1.0, 40), 0.5, 1.0)
    assert str(info.value).startswith("argument t=[-1.0, ")
    with pytest.raises(InvalidArgumentError) as info:
        mdo.haff_energy(np.linspace(-1.0, 1.0, 41), 0.5, 1.0)
    assert str(info.value) == "argument t='shape (41,)' is invalid: expected times >= 0"
    for call in (lambda: mdo.rod_positions(state, params, math.nan),
                 lambda: mdo.haff_energy(math.nan, 0.5, 1.0)):
        with pytest.raises(InvalidArgumentError) as info:
            call()
        assert info.value.name == "t"

"""The spectral solver of inelastic hard spheres and disks (maxwell_kinetics.sphere_spectral),
against references that do not use its code: the weak form of the collision operator by Monte
Carlo, a direct double sum of the energy dissipation on the grid, the exact moment equations of
the Maxwell model (variable hard spheres at γ = 0, derived below), the exact cooling rate of a
Maxwellian, and the DSMC of particles.hard_sphere_dsmc.

Grids: the named "coarse" grids (d = 2: 32² modes; d = 3: 16³) and, where the reference needs a
tighter grid, a small custom one.  Each tolerance says where it comes from.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import gammaln

from maxwell_kinetics.sphere_grid import GRIDS, SphereGrid
from maxwell_kinetics.sphere_spectral import SphereOperator, solve_spheres
from particles.sphere_kernels import HardSpheres, VariableHardSpheres

ALPHA = 0.5


def mixture(dimension):
    """An anisotropic two-Gaussian law with a non-zero mean: (density, sampler)."""
    mus = [np.array([0.5, -0.2, 0.1][:dimension]), np.array([-0.75, 0.3, -0.15][:dimension])]
    sig = [np.array([0.9, 1.0, 0.95][:dimension]), np.array([0.8, 0.75, 0.85][:dimension])]
    weights = (0.6, 0.4)

    def density(x):
        out = 0.0
        for w, m, s in zip(weights, mus, sig, strict=True):
            z = np.sum(((x - m) / s) ** 2, axis=-1)
            out = out + w * np.exp(-0.5 * z) / np.prod(np.sqrt(2 * np.pi) * s)
        return out

    def sample(rng, n):
        first = rng.random(n) < weights[0]
        z = rng.standard_normal((n, dimension))
        return np.where(first[:, None], mus[0] + sig[0] * z, mus[1] + sig[1] * z)

    return density, sample


def hard_directions(rng, g_hat, dimension):
    """n of density |ĝ·n|/β_d on the sphere (n and −n one collision)."""
    m = g_hat.shape[0]
    sign = np.where(rng.random(m) < 0.5, 1.0, -1.0)
    if dimension == 2:
        theta = np.arcsin(2 * rng.random(m) - 1)  # density cos θ / 2 on (−π/2, π/2)
        base = np.arctan2(g_hat[:, 1], g_hat[:, 0]) + theta
        return sign[:, None] * np.stack([np.cos(base), np.sin(base)], axis=1)
    mu = np.sqrt(rng.random(m))  # density 2μ on (0, 1): |μ| on the sphere
    helper = np.where(np.abs(g_hat[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    e1 = np.cross(g_hat, helper)
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = np.cross(g_hat, e1)
    phi = 2 * np.pi * rng.random(m)
    perp = np.sqrt(1 - mu**2)[:, None] * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)
    return sign[:, None] * (mu[:, None] * g_hat + perp)


@pytest.mark.parametrize("dimension", [2, 3])
def test_the_collision_operator_is_the_weak_form(dimension):
    # Σ ψ Q h^d on the grid against a Monte Carlo of d/dt ∫ψ f = ∫∫ f f ∫dn |g·n| [ψ(v′) − ψ(v)]
    # (v, w from f, n from |ĝ·n|/β_d, weight β_d |g|), for six ψ.  Tolerance: 4 standard
    # errors of the 20 batch means (the grid's own error, below 1e-4 relative on these grids
    # for this law, is far smaller).
    grid = GRIDS[2]["coarse"] if dimension == 2 else SphereGrid(24, 9.0, 7.0, 17, 10)
    operator = SphereOperator(HardSpheres(ALPHA), dimension, grid)
    density, sample = mixture(dimension)
    c = operator.nodes
    gain, loss = operator.collision(density(c))
    k = np.array([0.7, -0.4, 0.5][:dimension])
    tests = {"cos": lambda v: np.cos(v @ k), "sin": lambda v: np.sin(v @ k),
             "vx2": lambda v: v[..., 0] ** 2, "vxvy": lambda v: v[..., 0] * v[..., 1],
             "v4": lambda v: np.sum(v * v, axis=-1) ** 2, "vx3": lambda v: v[..., 0] ** 3}
    rng = np.random.default_rng(2024)
    beta_d = HardSpheres.sphere_factor(dimension)
    batches = {name: [] for name in tests}
    for _ in range(20):
        v, w = sample(rng, 100_000), sample(rng, 100_000)
        g = v - w
        speed = np.linalg.norm(g, axis=1)
        n = hard_directions(rng, g / speed[:, None], dimension)
        after = v - (1 + ALPHA) / 2 * np.sum(g * n, axis=1)[:, None] * n
        for name, psi in tests.items():
            batches[name].append(np.mean(beta_d * speed * (psi(after) - psi(v))))
    for name, psi in tests.items():
        on_grid = np.sum(psi(c) * (gain - loss)) * operator.weight
        values = np.array(batches[name])
        error = values.std(ddof=1) / math.sqrt(values.size)
        assert abs(on_grid - values.mean()) < 4 * error, (name, on_grid, values.mean(), error)


@pytest.mark.parametrize("dimension", [2, 3])
def test_the_scaled_right_hand_side_conserves_mass_momentum_and_energy(dimension):
    operator = SphereOperator(HardSpheres(ALPHA), dimension, "coarse")
    density, _ = mixture(dimension)
    rhs, _ = operator.scaled_rhs(density(operator.nodes))
    c = operator.nodes
    size = np.sum(np.abs(rhs) * (1 + np.sum(c * c, axis=-1))) * operator.weight
    assert abs(np.sum(rhs)) * operator.weight < 1e-13 * size
    for a in range(dimension):
        assert abs(np.sum(c[..., a] * rhs)) * operator.weight < 1e-13 * size
    assert abs(np.sum(np.sum(c * c, axis=-1) * rhs)) * operator.weight < 1e-13 * size


def truncated_cube_weight(r, dimension, cutoff):
    """V(r) = ∫ dn |g·n|³ over the n whose cylinder |g·n| ≤ R, |g − (g·n)n| ≤ R holds g."""
    r = np.asarray(r, dtype=float)
    hi = np.minimum(1.0, cutoff / np.where(r > 0, r, 1.0))
    lo = np.sqrt(np.clip(1.0 - hi * hi, 0.0, None))
    if dimension == 3:  # 2π r³ · 2 ∫_lo^hi μ³ dμ
        return np.pi * r**3 * (hi**4 - lo**4)
    s_lo, s_hi = np.sqrt(1 - lo**2), np.sqrt(1 - hi**2)  # sin θ at cos θ = lo, hi
    return 4 * r**3 * ((s_lo - s_lo**3 / 3) - (s_hi - s_hi**3 / 3))


def pair_sum(F, c, weight, function):
    """Σ_i Σ_j F_i F_j function(|c_i − c_j|) weight² (direct, in chunks)."""
    flat, points = F.reshape(-1), c.reshape(-1, c.shape[-1])
    keep = np.abs(flat) > 1e-10 * np.abs(flat).max()  # the rest: below 1e-9 of the sum
    flat, points = flat[keep], points[keep]
    total = 0.0
    for start in range(0, flat.size, 512):
        d = np.linalg.norm(points[start:start + 512, None, :] - points[None, :, :], axis=-1)
        total += flat[start:start + 512] @ function(d) @ flat
    return total * weight**2


@pytest.fixture(scope="module", params=[2, 3])
def cooling_solution(request):
    return solve_spheres(HardSpheres(ALPHA), [0.0, 0.4], dimension=request.param,
                         grid="coarse")


def test_mass_and_momentum_stay_exact_in_a_solve(cooling_solution):
    sol = cooling_solution
    c = sol.nodes()
    w = sol.grid.spacing**sol.dimension
    for F in sol.F:
        assert abs(F.sum() * w - 1.0) < 1e-12
        assert np.all(np.abs(np.tensordot(F, c, axes=sol.dimension) * w) < 1e-12)
        assert abs(np.sum(F * np.sum(c * c, axis=-1)) * w - sol.dimension) < 1e-11


def test_the_energy_identity_holds_on_the_solution(cooling_solution):
    # d⟨|v|²⟩/dt = −(1 − α²)/4 n ∫∫ f f ∫dn |g·n|³ (the weak form with ψ = |v|²), for the
    # kernel as truncated (cylinder of half-size R in the scaled c): the solver's cooling rate ζ
    # against a direct double sum over the grid's nodes, at t = 0 and t = 0.4.  Tolerance 3e-4
    # relative: the double sum of V, whose derivative jumps at |g| = R and √2 R, is a
    # low-order rule (at t = 0 it differs from the one-dimensional quadrature of haff_rate by
    # 2.7e-5 in d = 2, where the solver agrees with that quadrature to 1e-6); measured
    # 3.9e-5 (d = 2) and 1.5e-4 (d = 3) at t = 0.4.  An error of 1e-3 in α moves the
    # dissipation (1 − α²) by 1.3e-3: still caught.
    sol = cooling_solution
    d, R = sol.dimension, sol.grid.cutoff
    c = sol.nodes()
    w = sol.grid.spacing**d
    for k in range(len(sol.t)):
        F, s = sol.F[k], sol.scale[k]
        dissipation = (1 - ALPHA**2) / 4 * s**3 * pair_sum(
            F, c, w, lambda r: truncated_cube_weight(r, d, R))
        energy_rate = sol.cooling_rate[k] * d * sol.temperature[k]
        assert energy_rate == pytest.approx(dissipation, rel=3e-4)


def haff_rate(dimension, cutoff=math.inf):
    """ζ(0) of the Maxwellian of T = 1 (n = 1): (1 − α²)/(4d) ⟨V(|g|)⟩, g ~ N(0, 2 I_d)."""
    def law(r):  # density of |g| = √2 χ_d
        x = r / math.sqrt(2)
        return math.exp((dimension - 1) * math.log(x) - x * x / 2 - (dimension / 2 - 1)
                        * math.log(2) - gammaln(dimension / 2)) / math.sqrt(2)

    mean = quad(lambda r: float(truncated_cube_weight(r, dimension, cutoff)) * law(r), 0,
                40, points=[cutoff] if math.isfinite(cutoff) else None, limit=200)[0]
    return (1 - ALPHA**2) / (4 * dimension) * mean


def test_haff_cooling_rate_of_the_maxwellian(cooling_solution):
    dimension = cooling_solution.dimension
    nu0 = (8.0 if dimension == 3 else 4.0) * math.sqrt(math.pi)
    zeta0 = (1 - ALPHA**2) * nu0 / dimension
    assert haff_rate(dimension) == pytest.approx(zeta0, rel=1e-8)  # the reference itself
    R = cooling_solution.grid.cutoff
    # the truncated kernel's exact rate: tolerance 5e-5, the accuracy of Q on the coarse grids
    # (the elastic Maxwellian's |Q|/loss below: 6.2e-7 in d = 2, 4.3e-5 in d = 3)
    assert cooling_solution.cooling_rate[0] == pytest.approx(haff_rate(dimension, R), rel=5e-5)
    # and Haff's ζ₀ of the full kernel, within what the truncation at R removes
    assert abs(cooling_solution.cooling_rate[0] / zeta0 - 1) < 2 * (1 - haff_rate(dimension, R)
                                                                    / zeta0) + 5e-5


@pytest.mark.parametrize("dimension", [2, 3])
def test_an_elastic_maxwellian_is_stationary(dimension):
    # |Q(M)| ≤ 1e-4 of the loss: the gain's quadrature and aliasing error on the coarse grids
    # (benchmarks/README.md, "Spectral hard spheres": measured 6.2e-7 (d = 2), 4.3e-5 (d = 3)).
    operator = SphereOperator(HardSpheres(1.0), dimension, "coarse")
    M = operator.initial("gaussian")[0]
    gain, loss = operator.collision(M)
    assert np.max(np.abs(gain - loss)) < 1e-4 * np.max(loss)


def maxwell_moments(t, dimension, alpha):
    """E = ⟨|v|²⟩ and K = ⟨|v|⁴⟩/E² of the Maxwell model (σ isotropic, each particle colliding
    at rate 1 per unit n t) from the Maxwellian of T = 1.

    With v′ = V + A g + B|g|σ (V = (v + w)/2, A = (1 − α)/4, B = (1 + α)/4), u = V + A g =
    p v + B w (p = (3 − α)/4): E_σ|v′|² = X = a|v|² + b|w|² + c v·w (a = p² + B², b = 2B²,
    c = 2B(p − B)) and E_σ|v′|⁴ = X² + 4B²|g|²|u|²/d.  For independent v, w of zero mean and
    isotropic second moments (⟨(v·w)²⟩ = E²/d):
    dE/dt = (a + b − 1) E = −(1 − α²)/4 E and
    dM₄/dt = (a² + b² − 1) M₄ + 2ab E² + c² E²/d
             + (4B²/d) [(p² + B²)(M₄ + E²) − 4pB E²/d].
    """
    d = dimension
    A, B = (1 - alpha) / 4, (1 + alpha) / 4
    p = 0.5 + A
    a, b, c = p * p + B * B, 2 * B * B, 2 * B * (p - B)
    k4 = a * a + b * b - 1 + 4 * B * B * (p * p + B * B) / d
    k2 = 2 * a * b + c * c / d + 4 * B * B * (p * p + B * B) / d - 16 * B * B * p * B / d**2
    mu = (1 - alpha**2) / 2  # E² ∝ e^{−μ t}
    E0, M0 = float(d), float(d * (d + 2))
    t = np.asarray(t, dtype=float)
    forced = -k2 * E0**2 / (k4 + mu)  # the particular solution's amplitude
    M4 = M0 * np.exp(k4 * t) + forced * (np.exp(-mu * t) - np.exp(k4 * t))
    E = E0 * np.exp(-mu * t / 2)
    return E, M4 / E**2


def test_the_maxwell_moment_equations_hold_for_an_elastic_maxwellian():
    for d in (2, 3):
        _, K = maxwell_moments([0.0, 1.0, 5.0], d, 1.0)
        np.testing.assert_allclose(K, (d + 2) / d, rtol=1e-14)


def truncated_share(dimension, cutoff, power):
    """The share of ⟨|g|^power⟩ (Maxwellian of T = 1) that the cylinder truncation removes: pairs
    with |g| > R keep only the directions n whose cylinder holds g (a fraction (μ₂² − μ₁²) in
    d = 3 for the isotropic kernel, (arccos μ₁ − arccos μ₂)/(π/2) in d = 2)."""
    def law(r):
        x = r / math.sqrt(2)
        return math.exp((dimension - 1) * math.log(x) - x * x / 2 - (dimension / 2 - 1)
                        * math.log(2) - gammaln(dimension / 2)) / math.sqrt(2)

    def kept(r):
        if r <= cutoff:
            return 1.0
        hi = cutoff / r
        lo = math.sqrt(max(0.0, 1 - hi * hi))
        return hi**2 - lo**2 if dimension == 3 else (math.acos(lo) - math.acos(hi)) / (math.pi / 2)

    full = quad(lambda r: r**power * law(r), 0, 40, points=[cutoff])[0]
    left = quad(lambda r: r**power * law(r) * kept(r), 0, 40,
                points=[cutoff, cutoff * math.sqrt(2)], limit=200)[0]
    return 1 - left / full


@pytest.mark.parametrize("dimension", [2, 3])
def test_variable_hard_spheres_at_gamma_zero_follow_the_maxwell_moments(dimension):
    # Energy and ⟨|v|⁴⟩/⟨|v|²⟩² against the exact moment equations of the (untruncated) Maxwell
    # model.  The solver's kernel is truncated at R: to first order it drops a share δ_k of
    # the pairs' ⟨|g|^k⟩, so E is off by δ₂ (1 − α²) t/4 and the kurtosis by at most δ₄ t
    # (rates of at most 1 per unit t), δ_k of the initial Maxwellian; the tails fill as the gas
    # cools, so δ grows: in d = 3, E(2) is off by 4.2e-4 against 2.3e-4 from δ₂(0).
    # Tolerances: 3 times the estimates, plus 2e-5 (the grid's accuracy of Q, the elastic
    # test's bound); in d = 2 (R = 7) δ is 30 times smaller.
    times = np.array([0.0, 0.5, 1.0, 2.0])
    sol = solve_spheres(VariableHardSpheres(ALPHA, exponent=0.0), times, dimension=dimension,
                        grid="coarse")
    E, K = maxwell_moments(times, dimension, ALPHA)
    R = sol.grid.cutoff
    energy_tolerance = 3 * truncated_share(dimension, R, 2) * (1 - ALPHA**2) / 4 * times + 2e-5
    kurtosis_tolerance = 3 * truncated_share(dimension, R, 4) * times + 2e-5
    assert np.all(np.abs(sol.energy / E - 1) <= energy_tolerance), sol.energy / E - 1
    assert np.all(np.abs(sol.kurtosis / K - 1) <= kurtosis_tolerance), sol.kurtosis / K - 1
    assert K[-1] - K[0] > 5 * kurtosis_tolerance[-1]  # the test sees the kurtosis move


def test_the_result_keeps_its_contract_and_round_trips(cooling_solution, tmp_path):
    from maxwell_kinetics.kinetic_result import KineticResult
    from maxwell_kinetics.sphere_solution import SphereSolution

    sol = cooling_solution
    assert isinstance(sol, KineticResult) and sol.time_name == "t"
    path = tmp_path / "spheres.npz"
    sol.save(path)
    back = SphereSolution.load(path)
    assert np.array_equal(back.F, sol.F) and np.array_equal(back.t, sol.t)
    assert back.grid == sol.grid and np.array_equal(back.temperature, sol.temperature)
    # the histogram of one component integrates the marginal's Fourier series: total 1 over a
    # wide range, and the bins' Σ x_b² p_b is ⟨x²⟩ = 1 (unit variance of the rescaled
    # component) plus the midpoint rule's width²/12.  Tolerance: twice the trigonometric
    # interpolation error of a Gaussian sampled at spacing h (in standard deviations),
    # e^{−π²/(2h²)}: 6e-6 (d = 2, h = 0.625), 9e-4 (d = 3, h = 0.8); ten times that for the
    # x²-weighted sum over |x| ≤ 6.
    interpolation = 2 * math.exp(-math.pi**2 / (2 * sol.grid.spacing**2))
    edges = np.linspace(-6, 6, 241)
    hist = sol.histogram(edges, time=0.4)
    width = np.diff(edges)
    assert np.sum(hist.density * width) == pytest.approx(1.0, abs=interpolation)
    assert np.sum(hist.density * width * hist.centres**2) == pytest.approx(
        1.0 + 0.05**2 / 12, abs=10 * interpolation + 1e-5)
    x, P = sol.density(np.array([0.0, 1.0, 2.5]), time=0.0)
    np.testing.assert_allclose(P, np.exp(-0.5 * x**2) / math.sqrt(2 * math.pi),
                               atol=interpolation / math.sqrt(2 * math.pi))
    moments = sol.moments((2, 4))
    assert moments.values[:, 0] == pytest.approx(sol.dimension)
    assert len(sol.plot().lines) == len(sol.t)
    np.testing.assert_allclose(moments.values[:, 1] / sol.dimension**2, sol.kurtosis)


#: The coarse grid's error at t = 0.4 (α = 0.5, from the unit Maxwellian), measured as its
#: distance to the default grid: |T_coarse − T_default| and |a₂_coarse − a₂_default| (d = 2:
#: T 0.42419 and 0.42416, a₂ 0.05861 and 0.05837; d = 3: T 0.34136 and 0.34080, a₂ 0.04440
#: and 0.04356).  The default grid's own distance to the DSMC is checked in the `full` test.
COARSE_GRID_ERROR = {2: {"T": 4e-5, "a2": 2.4e-4}, 3: {"T": 5.7e-4, "a2": 8.4e-4}}


def test_the_cooling_solve_agrees_with_the_dsmc(cooling_solution):
    # α = 0.5, from the unit Maxwellian to t = 0.4 (about four collisions per particle, where
    # a₂ has reached 0.04-0.06): T and a₂ of the fixture's coarse solve against the DSMC of
    # particles.hard_sphere_dsmc, N = 10⁵, 16 seeds.  Tolerance: 3 standard errors of the 16
    # seeds' mean (measured with 64 seeds: the error of one seed is 8.7e-4 for T and 2.8e-3
    # for a₂ in d = 3, 1.3e-3 and 3.9e-3 in d = 2) plus the coarse grid's error
    # (COARSE_GRID_ERROR).  A collision rate 1 % off moves T(0.4) by 0.8 %, 2.2 (d = 3) and 3.3
    # (d = 2) of these tolerances; a planted 1 % rate failed both dimensions.
    from particles.hard_sphere_dsmc import SphereDSMC
    from particles.sphere_observables import sonine_coefficients, temperature

    sol, dimension = cooling_solution, cooling_solution.dimension
    temperatures, a2 = [], []
    for seed in range(16):
        engine = SphereDSMC(100_000, ALPHA, dimension=dimension)
        rng = np.random.default_rng(seed)
        state = engine.advance(engine.initial_state(rng), sol.t[-1], rng)
        temperatures.append(temperature(state.velocities))
        a2.append(sonine_coefficients(state.velocities)["a2"])
    for name, solved, sample in (("T", sol.temperature[-1], temperatures),
                                 ("a2", sol.a2[-1], a2)):
        sample = np.asarray(sample)
        error = sample.std(ddof=1) / math.sqrt(sample.size)
        tolerance = 3 * error + COARSE_GRID_ERROR[dimension][name]
        assert abs(solved - sample.mean()) < tolerance, (name, solved, sample.mean(), error)


@pytest.mark.full
def test_the_cooling_state_agrees_with_the_dsmc():
    # d = 3, α = 0.5: the cooling state's a₂ on the default grid against the DSMC of
    # particles.hard_sphere_dsmc (N = 10⁵, 4 seeds, each the mean of a₂ at 10, 12, 14 and 16
    # collisions per particle, in the cooling state).  Tolerance: 3 standard errors of the
    # seeds' mean (the normal law's 3σ; Student's t for 3 degrees of freedom would allow
    # more).  N = 10⁶ gave 0.048 (benchmarks/README.md, "Hard-sphere DSMC").  Not the coarse
    # grid: its cutoff R = 6 truncates the collisions of the HCS's overpopulated tail and
    # raises a₂ by 2e-3 (benchmarks/README.md, "Spectral hard spheres").
    from maxwell_kinetics.sphere_spectral import cooling_state
    from particles.hard_sphere_dsmc import SphereDSMC
    from particles.sphere_observables import sonine_coefficients

    d = 3
    nu0 = 8 * math.sqrt(math.pi)
    zeta0 = (1 - ALPHA**2) * nu0 / d
    seeds = []
    for seed in range(4):
        engine = SphereDSMC(100_000, ALPHA, dimension=d)
        rng = np.random.default_rng(seed)
        state = engine.initial_state(rng)
        values = []
        for per_particle in (10, 12, 14, 16):  # Haff's t of that many collisions per particle
            t = (2 / zeta0) * math.expm1(zeta0 * per_particle / (2 * nu0))
            state = engine.advance(state, t, rng)
            values.append(sonine_coefficients(state.velocities)["a2"])
        seeds.append(np.mean(values))
    seeds = np.array(seeds)
    error = seeds.std(ddof=1) / math.sqrt(seeds.size)
    state = cooling_state(HardSpheres(ALPHA), dimension=d, grid="default")
    assert abs(state.a2 - seeds.mean()) < 3 * error, (state.a2, seeds.mean(), error)

"""The density of the speed |v| from the isotropic characteristic function (item 1).

Checks of the radial inverse transform against closed forms that do not come from it (the
Maxwell speed law; multivariate Student laws, whose characteristic functions have |k|³ and
non-integer |k|^ν terms at k = 0), of the solver's speed density against the exact invariants
(mass, ⟨s²⟩ = d) and against the component density through real-space integrals (the Abel
projection), of the tail exponent against the equation's 1 + 2s*, and of the refusals: bad
speeds, and the distances to the one-dimensional f̂ for d ≥ 2.
"""

import math

import numpy as np
import pytest
from helpers import run_error, run_json
from scipy.special import gammaln, kv

from maxwell_kinetics.solver import solve
from maxwell_kinetics.tails import tail_exponent
from maxwell_kinetics.velocity import density_at, radial_density_at, speed_density_at
from particles.validation import InvalidArgumentError

SPHERE = {1: 2.0, 2: 2.0 * math.pi, 3: 4.0 * math.pi}


def _gauss_legendre(edges, nodes=64):
    """Nodes and weights of composite Gauss–Legendre quadrature on the given panel edges."""
    t, w = np.polynomial.legendre.leggauss(nodes)
    edges = np.asarray(edges, dtype=float)
    half = 0.5 * np.diff(edges)
    x = (edges[:-1, None] + half[:, None] * (t + 1.0)).ravel()
    return x, (half[:, None] * w).ravel()


def _student(nu, d):
    """Multivariate Student law with ν degrees of freedom and scale 1 in d dimensions:
    Φ(k) = 2^{1−ν/2}/Γ(ν/2) (√ν k)^{ν/2} K_{ν/2}(√ν k), f(v) = Γ((ν+d)/2)/(Γ(ν/2)(νπ)^{d/2})
    (1 + v²/ν)^{−(ν+d)/2}.  Φ = 1 − k²ν/(2(ν−2)) + … + c |k|^ν + …: for ν = 3 it is
    (1 + √3 k) e^{−√3 k}."""

    def phi(k):
        z = math.sqrt(nu) * np.asarray(k, dtype=float)
        return np.exp((1 - nu / 2) * math.log(2) - gammaln(nu / 2)) * z ** (nu / 2) * kv(nu / 2, z)

    log_c = gammaln((nu + d) / 2) - gammaln(nu / 2) - (d / 2) * math.log(nu * math.pi)

    def f(v):
        return np.exp(log_c) * (1 + np.asarray(v) ** 2 / nu) ** (-(nu + d) / 2)

    return phi, f


# -- the transform against closed forms ---------------------------------------------------------

S = np.concatenate([[0.0, 1e-7], np.linspace(0.01, 12.0, 240), [20.0, 40.0]])


@pytest.mark.parametrize("d", [1, 2, 3])
def test_gaussian_gives_the_maxwell_speed_law(d):
    # Φ = e^{−k²/2} (unit variance per component): P(s) = S_d s^{d−1} e^{−s²/2} / (2π)^{d/2},
    # i.e. √(2/π) e^{−s²/2}, s e^{−s²/2}, √(2/π) s² e^{−s²/2}.  Measured max error ≤ 3.1e-15.
    P = speed_density_at(lambda k: np.exp(-0.5 * k * k), S, d)
    exact = SPHERE[d] * S ** (d - 1) * np.exp(-0.5 * S * S) / (2 * math.pi) ** (d / 2)
    assert np.max(np.abs(P - exact)) < 1e-13
    named = {1: math.sqrt(2 / math.pi) * np.exp(-S * S / 2), 2: S * np.exp(-S * S / 2),
             3: math.sqrt(2 / math.pi) * S * S * np.exp(-S * S / 2)}[d]
    np.testing.assert_allclose(exact, named, rtol=1e-14, atol=0)


@pytest.mark.parametrize("d", [1, 2, 3])
def test_scaling_profile_is_the_student_law_with_three_degrees(d):
    # Φ(k) = (1 + k) e^{−k} (the |k|³ kink of f̂) is the ν = 3 Student law scaled by 1/√3:
    # f(v) = C_d (1 + v²)^{−(d+3)/2}, C_1 = 2/π, C_2 = 3/(2π), C_3 = 4/π² (the normalisations
    # are written out here, not taken from _student).  Measured: relative error ≤ 3.3e-8 up to
    # v = 40 (there f ~ 1e-12 in d = 3 and round-off ~1e-16 ∫ k²|Φ| dk dominates), absolute
    # ≤ 4.5e-16.
    C = {1: 2 / math.pi, 2: 3 / (2 * math.pi), 3: 4 / math.pi**2}[d]
    exact = C * (1 + S * S) ** (-(d + 3) / 2)
    f = radial_density_at(lambda k: (1 + k) * np.exp(-k), S, d, q_max=60.0)
    assert np.max(np.abs(f - exact)) < 1e-14
    assert np.max(np.abs(f / exact - 1)) < 1e-6
    phi3, f3 = _student(3.0, d)  # the helper agrees with the closed form above
    np.testing.assert_allclose(f3(S * math.sqrt(3)) * 3 ** (d / 2), exact, rtol=1e-13)
    k = np.linspace(0.01, 5, 50)
    np.testing.assert_allclose(phi3(k / math.sqrt(3)), (1 + k) * np.exp(-k), rtol=1e-13)


@pytest.mark.parametrize("d", [2, 3])
def test_non_integer_power_at_small_k(d):
    # ν = 2.5: Φ has a |k|^{2.5} term at k = 0, the kind of non-analytic term the solver's G
    # has (|q|^{2s*}).  Speeds up to 30.  Measured: absolute ≤ 7.4e-15, relative (where
    # P > 1e-8) 1.7e-11 (d = 2) and 8.4e-11 (d = 3); without the graded first panel 3.6e-10
    # and 7.5e-11: the |k|^ν term costs little even ungraded, as density_at's docstring says.
    phi, f = _student(2.5, d)
    v = np.concatenate([[0.0], np.geomspace(1e-3, 30.0, 80)])
    P = speed_density_at(phi, v, d, q_max=60.0)
    exact = SPHERE[d] * v ** (d - 1) * f(v)
    assert np.max(np.abs(P - exact)) < 1e-12
    big = exact > 1e-8
    assert np.max(np.abs(P[big] / exact[big] - 1)) < 1e-9


def test_one_dimension_folds_the_two_signs():
    # d = 1: the speed |x| has P(s) = f(s) + f(−s), also for an asymmetric law (complex G):
    # a two-Gaussian mixture with means 1 and −0.5, against the component density of itself.
    def G(k):
        return 0.3 * np.exp(1j * k - 0.5 * k * k) + 0.7 * np.exp(-0.5j * k - 0.5 * k * k)

    s = np.linspace(0.0, 6.0, 25)
    P = speed_density_at(G, s, 1)
    both = density_at(G, s) + density_at(G, -s)
    assert np.max(np.abs(P - both)) < 1e-14
    exact = sum(c * (np.exp(-0.5 * (s - m) ** 2) + np.exp(-0.5 * (s + m) ** 2))
                for c, m in ((0.3, 1.0), (0.7, -0.5))) / math.sqrt(2 * math.pi)
    assert np.max(np.abs(P - exact)) < 1e-14


# -- the solver's speed density ---------------------------------------------------------------


@pytest.fixture(scope="module")
def planar():
    # d = 2, r = 0, uniform directions: τ = 3 (light tails) and τ = 400 (the scaling regime).
    # The default 16 angular nodes: the compilation of test_moments.py's d = 2 solves (r is
    # data, not part of it), which tests/conftest.py runs on the same worker before this file.
    # The values measured below are those of 8 nodes and of 16 alike (to the digits given).
    return solve(0.0, "gaussian", [3.0, 400.0], "default", dimension=2)


@pytest.fixture(scope="module")
def spatial():
    # d = 3, r = 0.5, the CLI's 16 angular nodes (the CLI test reuses this compilation).
    return solve(0.5, "gaussian", [3.0], "default", dimension=3)


def _moments(sol, tau_index, top=15.0):
    s, w = _gauss_legendre(np.linspace(0.0, top, 31))
    _, P = sol.speed_density(s, tau_index)
    return float(w @ P), float(w @ (s * s * P))


@pytest.mark.parametrize("which", ["planar", "spatial"])
def test_solver_speed_density_has_unit_mass_and_mean_square_d(which, request):
    # ∫ P ds = 1 (G(0) = 1) and ⟨s²⟩ = d (G''(0) = −1: unit variance per component) at τ = 3,
    # integrated over s ≤ 15.  Measured on the default grid: mass − 1 = 5.1e-12 (d = 2) and
    # −6.8e-11 (d = 3), ⟨s²⟩ − d = 1.2e-9 and −1.5e-8 (the coarse grid's interpolation error of
    # G, ~4e-7, gives ~1e-7 and ~1e-4).  A wrong S_d, kernel or variance unit is an O(1) error.
    sol = request.getfixturevalue(which)
    mass, mean_square = _moments(sol, 0)
    assert mass == pytest.approx(1.0, abs=1e-8)
    assert mean_square == pytest.approx(sol.dimension, abs=1e-6)
    _, P = sol.speed_density([0.0, 0.5, 1.0, 2.0, 4.0], 0)
    assert P[0] == 0.0 and np.all(P[1:] > 0)


def test_speed_and_component_densities_agree_in_three_dimensions(spatial):
    # Independent routes: f₁(x) = 2π ∫_x^∞ v f(v) dv = ∫_x^∞ P(v) / (2v) dv (real-space
    # projection of the speed density; equivalently −f₁'(x)/(2πx) = f(x)) against the component
    # density (1D inverse transform).  Measured max difference 3.3e-11 (default grid).
    x = np.array([0.0, 0.5, 1.0, 2.0, 3.0, 5.0])
    _, f1 = spatial.density(x)
    t, w = _gauss_legendre(np.concatenate([[0.0], np.geomspace(1e-3, 30.0, 30)]), nodes=24)
    v = x[:, None] + t[None, :]
    _, P = spatial.speed_density(v)
    projected = (P / (2 * v)) @ w
    assert np.max(np.abs(projected - f1)) < 1e-9


def test_speed_and_component_densities_agree_in_two_dimensions(planar):
    # f₁(x) = ∫ f(√(x² + y²)) dy = 2 ∫_0^∞ P(v) / (2π v) dy, v = √(x² + y²) (the Abel
    # projection).  Measured max difference 1.8e-12 (default grid).
    x = np.array([0.0, 0.5, 1.0, 2.0, 3.0, 5.0])
    _, f1 = planar.density(x, 0)
    y, w = _gauss_legendre(np.concatenate([[0.0], np.geomspace(1e-3, 30.0, 30)]), nodes=24)
    v = np.sqrt(x[:, None] ** 2 + y[None, :] ** 2)
    _, P = planar.speed_density(v, 0)
    projected = 2 * (P / (2 * math.pi * v)) @ w
    assert np.max(np.abs(projected - f1)) < 1e-9


def test_speed_tail_has_the_component_exponent(planar):
    # Exact: the speed and one component both decay as s^{−1−2s*} (the d-dimensional density
    # as s^{−d−2s*}; P = S_d s^{d−1} f makes that relation exact, so it is not tested).
    # d = 2, r = 0, uniform, τ = 400, default grid, slopes of ln P on s ∈ [20, 60]: measured
    # speed 5.2804 (halves differ by 0.012), component 5.2810, 1 + 2s* = 5.2875.  Tolerances:
    # 0.03 against 1 + 2s* (~2.5 × the drift of the local slope), 0.01 between the two.
    s = np.geomspace(20.0, 60.0, 41)
    _, P = planar.speed_density(s, 1)
    _, f1 = planar.density(s, 1)
    speed = -np.polyfit(np.log(s), np.log(P), 1)[0]
    component = -np.polyfit(np.log(s), np.log(f1), 1)[0]
    exact = tail_exponent(2, 0.0, "uniform").exponents
    assert exact["speed"] == exact["component"]
    assert abs(speed - exact["speed"]) < 0.03
    assert abs(speed - component) < 0.01


# -- input checks and the distances to f̂ --------------------------------------------------------


@pytest.mark.parametrize("bad", [-1.0, math.nan, math.inf, [1.0, -0.5]])
def test_bad_speeds_name_the_argument(bad, planar):
    with pytest.raises(InvalidArgumentError, match="argument s="):
        planar.speed_density(bad)
    with pytest.raises(InvalidArgumentError, match="argument s="):
        speed_density_at(lambda k: np.exp(-k * k / 2), bad, 3)
    with pytest.raises(InvalidArgumentError, match="argument v="):
        radial_density_at(lambda k: np.exp(-k * k / 2), bad, 3)


def test_bad_dimension_and_tau_index(planar):
    for d in (0, 4, 2.5, True, "3"):
        with pytest.raises(InvalidArgumentError, match="dimension"):
            speed_density_at(lambda k: np.exp(-k * k / 2), [1.0], d)
    with pytest.raises(InvalidArgumentError, match="tau_index"):
        planar.speed_density([1.0], 5)


def test_distances_to_f_hat_refuse_two_and_three_dimensions(planar, spatial):
    # f̂ = (1 + |q|) e^{−|q|} is the scaling solution of the d = 1 equation only.
    for sol in (planar, spatial):
        with pytest.raises(InvalidArgumentError, match="dimension"):
            sol.sup_error()
        with pytest.raises(InvalidArgumentError, match="dimension"):
            sol.sup_error(0)
        with pytest.raises(InvalidArgumentError, match="dimension"):
            sol.fourier_distance(2.5)
    # d = 1 keeps them: the Gaussian at τ = 0 is sup|e^{−q²/2} − f̂| away (brute force on q;
    # r = 1 keeps G = φ without a compilation)
    one = solve(1.0, "gaussian", [0.0, 1.0], "coarse")
    q = np.linspace(0.0, 10.0, 200_001)
    brute = np.max(np.abs(np.exp(-q * q / 2) - (1 + q) * np.exp(-q)))
    assert one.sup_error(0) == pytest.approx(brute, rel=1e-6)
    assert one.sup_error().shape == (2,)
    assert np.isfinite(one.fourier_distance(2.5, 0))
    # the one-dimensional speed is |x|: P(s) = 2 f(s) for this symmetric law (two quadratures of
    # the piecewise interpolant of G: measured difference 6.6e-13)
    s = np.array([0.0, 0.7, 2.0])
    np.testing.assert_allclose(one.speed_density(s, 0)[1], 2 * one.density(s, 0)[1],
                               rtol=0, atol=1e-11)


def test_solution_figure_shows_the_speed_density_in_two_dimensions(planar):
    from maxwell_kinetics.figures import plot_solution

    fig = plot_solution(planar)
    right = fig.axes[1]
    assert right.get_ylabel() == "P(s)"  # not |G − f̂|, which means nothing for d ≥ 2
    s, p = right.get_lines()[-1].get_data()
    expected = planar.speed_density(s, len(planar.tau) - 1)[1]
    drawn = np.isfinite(p)  # non-positive values are not drawn on the log axis
    assert np.array_equal(drawn, expected > 0)
    np.testing.assert_allclose(p[drawn], expected[drawn])
    assert "d = 2" in fig.axes[0].get_title()


# -- the command line -------------------------------------------------------------------------


def test_solve_cli_reports_the_speed_density(capsys, spatial):
    out = run_json(capsys, ["solve", "-r", "0.5", "--tau", "3", "--resolution", "default",
                            "--dimension", "3", "--speed", "0,0.5,1,2,4", "--json"])
    assert out["speed"] == [0.0, 0.5, 1.0, 2.0, 4.0]
    assert out["sup_error"] is None  # no distance to the one-dimensional f̂ in d = 3
    _, P = spatial.speed_density(out["speed"])
    np.testing.assert_allclose(np.asarray(out["speed_density"]), P[None, :], rtol=1e-12,
                               atol=1e-15)


@pytest.mark.parametrize("bad", ["-1,2", "1,nan", "inf", "a"])
def test_solve_cli_bad_speed_writes_nothing(bad, capsys, tmp_path):
    save = tmp_path / "s.npz"
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", "1", "--resolution", "coarse",
                             "--dimension", "2", "--speed", bad, "--save", str(save)])
    assert f"speed={bad!r}" in err
    assert not save.exists()


@pytest.mark.parametrize(("argv", "named"), [
    (["--dimension", "2", "--angular-rule", "exact"], "angular-rule='exact'"),
    (["--dimension", "4"], "dimension='4'"),
    (["--dimension", "2", "--angular", "soft"], "angular='soft'"),
])
def test_solve_cli_bad_model_writes_nothing(argv, named, capsys, tmp_path):
    save = tmp_path / "s.npz"
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", "1", "--resolution", "coarse",
                             *argv, "--save", str(save)])
    assert named in err
    assert not save.exists()

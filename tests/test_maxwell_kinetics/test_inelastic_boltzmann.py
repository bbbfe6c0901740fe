"""The velocity-space solver of the inelastic Boltzmann equation with rate n|v − w|^γ
(:mod:`maxwell_kinetics.inelastic_boltzmann`): conservation, the energy identity against an
independent double sum, γ = 0 against the exact moment equation, the hard-rod scaling state, and
the refusals of the command line.  Small grids keep the file cheap; the convergence in the grid
and the long runs are in benchmarks/hard_rods.py."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from helpers import run_error

from maxwell_kinetics.app.cli import main
from maxwell_kinetics.inelastic_boltzmann import scaling_state, solve_boltzmann
from maxwell_kinetics.velocity_grid import MappedGrid, VelocityGrid
from particles.initial import InitialLaw
from particles.validation import InvalidArgumentError

# An asymmetric, smooth law with zero mean and unit variance: 0.7 N(a, s²) + 0.3 N(b, s²)
_W, _S = 0.7, 0.6
_A = math.sqrt((1.0 - _S**2) * 0.3 / 0.7)
_B = -0.7 * _A / 0.3


def _mixture_cdf(v):
    from scipy.special import ndtr

    return _W * ndtr((v - _A) / _S) + (1.0 - _W) * ndtr((v - _B) / _S)


ASYMMETRIC = InitialLaw("two_gaussians", lambda k, xp: (
    _W * xp.exp(1j * _A * k) + (1 - _W) * xp.exp(1j * _B * k)) * xp.exp(-0.5 * _S**2 * k**2),
    None, 0.0, "asymmetric mixture", distribution=_mixture_cdf)


@pytest.fixture(scope="module")
def rods():
    # hard rods at density 2 from an asymmetric law: momentum is not zero by symmetry
    return solve_boltzmann(0.8, [0.5, 2.0, 8.0], density=2.0, initial=ASYMMETRIC,
                           grid=VelocityGrid(61, 7.0), rtol=1e-9)


def test_mass_and_momentum_are_conserved_to_round_off(rods):
    for t in rods.t:
        v, f = rods.velocity_density(t)
        dv = v[1] - v[0]
        assert abs(dv * f.sum() - 1.0) <= 1e-12
        assert abs(dv * (f @ v)) <= 1e-12
    assert rods.energy[-1] < 0.5 * rods.energy[0]  # it cooled (n = 2 makes it fast)


def test_the_energy_loss_is_lambda_n_times_the_mean_cubed_relative_speed(rods):
    # an independent double sum over the solution's own f(v, t) on its grid
    lam = (1 - 0.8**2) / 4
    for t, rate in zip(rods.t, rods.energy_rate, strict=True):
        v, f = rods.velocity_density(t)
        dv = v[1] - v[0]
        g3 = dv * dv * np.sum(f[:, None] * f[None, :] * np.abs(v[:, None] - v[None, :]) ** 3)
        assert rate == pytest.approx(-lam * 2.0 * g3, rel=1e-8)


def test_one_collision_term_against_the_collision_integral_by_quadrature():
    """Q_h(F) of the hard-rod scheme at the nodes against the collision integral of a Gaussian,
    evaluated here by adaptive quadrature: rate |v − w| (γ = 1, n = 1), r = 1/2 (p = 3/4), the
    partner that keeps 1 − p had v, the other w = (c − (1 − p)v)/p, |v − w| = |v − c|/p and
    dw = dc/p:

        gain(c) = p⁻² ∫ φ(v) φ((c − (1 − p)v)/p) |v − c| dv,
        loss(c) = φ(c) ∫ |c − w| φ(w) dw = φ(c) (c (2Φ(c) − 1) + 2φ(c)).

    The trapezoid rule has a kink at v = c (a node); with Navot's correction −2ζ(−1) h² = h²/6
    (times p⁻² − 1, gain less loss) it errs by O(h⁴): measured 1.9e-8 at h = 0.1 and 6e-10 at
    h = 0.05 (N = 321 on ±8).  Tolerance 2e-9: the h = 0.1 error scaled by 2⁻⁴ (1.2e-9), with a
    margin.  The correction itself is 5e-5 at c = 0; off by 0.1 % it moves Q_h by 6e-9."""
    import jax
    import jax.numpy as jnp
    from scipy.integrate import quad
    from scipy.special import ndtr

    from maxwell_kinetics import _boltzmann_scheme as scheme
    from maxwell_kinetics.inelastic_boltzmann import tables_for
    from maxwell_kinetics.model import RelativeVelocityModel

    p = 0.75
    phi = lambda x: math.exp(-0.5 * x * x) / math.sqrt(2 * math.pi)  # noqa: E731
    grid = VelocityGrid(321, 8.0)
    c, h = grid.c, grid.h
    with jax.enable_x64(True):
        tables = tables_for(RelativeVelocityModel(0.5), grid)
        F = jnp.asarray(np.exp(-0.5 * c * c) / math.sqrt(2 * math.pi))
        q = np.asarray(jax.jit(scheme.collision_term)(F, tables, jnp.asarray(c), h, 3 / 16))
    for k in range(100, 221, 4):  # c from −3 to 3
        ck = float(c[k])
        gain = quad(lambda v, ck=ck: phi(v) * phi((ck - (1 - p) * v) / p) * abs(v - ck), -12, 12,
                    points=[ck], epsabs=1e-15, epsrel=1e-13, limit=200)[0] / p**2
        loss = phi(ck) * (ck * (2 * ndtr(ck) - 1) + 2 * phi(ck))
        assert abs(q[k] - (gain - loss)) <= 2e-9, (ck, q[k] - (gain - loss))


def test_the_energy_follows_its_rate_in_time():
    # E(t) itself: a fourth-order difference of saved energies against the saved rate (step
    # 0.01: the difference errs by ~1e-9, the integration by rtol / step ~ 1e-10)
    d, t0 = 0.01, 0.3
    sol = solve_boltzmann(0.5, [t0 - 2 * d, t0 - d, t0, t0 + d, t0 + 2 * d],
                          grid=VelocityGrid(61, 7.0), rtol=1e-12, atol=1e-15)
    E = sol.energy
    slope = (E[0] - 8 * E[1] + 8 * E[3] - E[4]) / (12 * d)
    assert slope == pytest.approx(sol.energy_rate[2], rel=1e-6)


def test_gamma_zero_has_the_maxwell_models_kurtosis():
    # rate constant: tau = n t, and <v^4>/<v^2>^2 = -3 + 6 e^{9 tau/128} at r = 0.5; at
    # n t = 1 the tail stays inside +-7.5 (edge mass checked)
    sol = solve_boltzmann(0.5, [0.5, 1.0], exponent=0.0, density=1.0,
                          grid=VelocityGrid(61, 7.5), rtol=1e-11)
    exact = -3 + 6 * np.exp(9 * sol.t / 128)
    assert np.max(sol.edge_mass) < 1e-9
    np.testing.assert_allclose(sol.kurtosis, exact, rtol=1e-6)
    np.testing.assert_allclose(sol.energy, np.exp(-2 * (3 / 16) * sol.t), rtol=1e-10)


def test_a_mapped_grid_conserves_and_keeps_the_energy_identity():
    # gamma = 0 from the asymmetric law on c = a sinh(s): the same exact identities with the
    # mapped trapezoid weights (an independent double sum over the solution's own f)
    grid = MappedGrid(61, 30.0, 0.2)
    sol = solve_boltzmann(0.8, [0.5, 2.0], exponent=0.0, density=2.0, initial=ASYMMETRIC,
                          grid=grid, rtol=1e-9)
    lam = (1 - 0.8**2) / 4
    for t, rate in zip(sol.t, sol.energy_rate, strict=True):
        v, f = sol.velocity_density(t)
        dv = grid.weights * sol.scale[sol.time_index(t)]
        assert abs(dv @ f - 1.0) <= 1e-12 and abs(dv @ (f * v)) <= 1e-12
        g2 = np.sum(np.outer(dv * f, dv * f) * (v[:, None] - v[None, :]) ** 2)
        assert rate == pytest.approx(-lam * 2.0 * g2, rel=1e-8)
    with pytest.raises(InvalidArgumentError, match="grid=.*exponent=1"):
        solve_boltzmann(0.8, [0.5], grid=grid)


def test_a_mapped_grid_follows_the_maxwell_models_tail():
    # gamma = 0, r = 1/2 at tau = 10: the kurtosis -3 + 6 e^{9 tau/128} = 9.12 has 6 % of its
    # fourth moment beyond |x| = 10 and reaches |x| ~ 100, which 161 uniform points cannot hold
    # at a core spacing of 0.1.  The tolerance is this grid's discretisation error, measured
    # -4.6e-6 (it falls to -7.6e-7 at 201 points, core 0.08; 561 points on +-2e5 reach 1.2e-8
    # at tau = 10 and 5.5e-8 at tau = 50 in benchmarks/hard_rods.py mapped)
    sol = solve_boltzmann(0.5, [10.0], exponent=0.0, grid=MappedGrid(161, 1000.0, 0.1))
    exact = -3 + 6 * np.exp(9 * sol.t / 128)
    np.testing.assert_allclose(sol.kurtosis, exact, rtol=1e-5)
    np.testing.assert_allclose(sol.energy, np.exp(-2 * (3 / 16) * sol.t), rtol=1e-10)
    assert np.max(sol.edge_mass) < 1e-20


def test_the_mapped_grid_refuses_a_core_coarser_than_the_uniform_grid():
    with pytest.raises(InvalidArgumentError, match="core_spacing=0.5"):
        MappedGrid(101, 10.0, 0.5)
    with pytest.raises(InvalidArgumentError, match="core_spacing=0.3"):
        solve_boltzmann(0.5, [1.0], exponent=0.0, grid=MappedGrid(101, 100.0, 0.3))
    with pytest.raises(InvalidArgumentError, match="grid="):
        scaling_state(0.9, grid=MappedGrid(101, 100.0, 0.2))


def test_the_hard_rod_scaling_state_has_two_humps_and_is_stationary():
    # stationary: the residual of the rescaled equation Q_h(F) + sigma' d(cF)/dc at the state
    state = scaling_state(0.9, grid=VelocityGrid(61, 6.0), relaxation=20.0)
    assert state.residual <= 1e-11
    assert 1.0 < state.kurtosis < 3.0
    P = state.density([0.0, 1.0])
    assert P[1] > P[0]  # the humps at |c| ~ 1, a dip at 0


def test_the_histogram_integrates_to_one_and_matches_the_density(rods):
    edges = np.linspace(-7, 7, 29)  # the whole grid
    hist = rods.histogram(edges, t=2.0)
    assert float(np.sum(hist.density * np.diff(edges))) == pytest.approx(1.0, abs=1e-6)
    mid = hist.centres[14]
    assert hist.density[14] == pytest.approx(float(rods.density([mid], t=2.0)[1][0]), rel=0.02)
    with pytest.raises(InvalidArgumentError, match="t=3"):
        rods.histogram(edges, t=3.0)


@pytest.mark.parametrize(("argv", "needle"), [
    (["--rate", "hard"], "rate='hard'"),
    (["--rate", "relative_velocity", "--tau", "1"], "tau='1'"),
    (["--rate", "relative_velocity", "--t", "1", "--exponent", "2.5"], "exponent="),
    (["--rate", "relative_velocity", "--t", "1", "--density", "0"], "density='0'"),
    (["--rate", "relative_velocity", "--t", "1", "--density", "inf"], "density='inf'"),
    (["--rate", "relative_velocity", "--t", "1", "--points", "31"], "at least 49 points"),
    (["--rate", "relative_velocity", "--t", "1", "--half-width", "4"], "--half-width >= "),
    (["--rate", "relative_velocity", "--t", "1", "--initial", "uniform"], "about 801 points"),
    (["--rate", "relative_velocity", "--t", "1", "--core-spacing", "x"], "core-spacing='x'"),
    (["--rate", "relative_velocity", "--t", "1", "--core-spacing", "0.05"], "gamma = 0 only"),
    (["--rate", "relative_velocity", "--t", "1", "--exponent", "0", "--core-spacing", "0.3"],
     "core-spacing='0.3'"),  # the default 401 points on +-40 are finer than 0.3
    (["--rate", "relative_velocity", "--t", "1", "--exponent", "0", "--points", "101",
      "--half-width", "100", "--core-spacing", "0.5"], "core-spacing='0.5'"),
    (["--core-spacing", "0.1", "--tau", "1"], "core-spacing='0.1'"),
])
def test_bad_input_is_refused_naming_the_argument(capsys, tmp_path, argv, needle):
    err = run_error(capsys, ["solve", "-r", "0.9", *argv, "--json"])
    assert needle in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_fixed_point_refuses_an_unknown_rate_and_gamma_zero(capsys):
    assert "rate='x'" in run_error(capsys, ["fixed-point", "-r", "0.9", "--rate", "x"])
    err = run_error(capsys, ["fixed-point", "-r", "0.9", "--rate", "relative_velocity",
                             "--exponent", "0"])
    assert "exponent='0'" in err and "x^-4" in err


def test_the_commands_print_energy_and_kurtosis(capsys):
    assert main(["solve", "-r", "0.9", "--rate", "relative_velocity", "--t", "0,1",
                 "--points", "61", "--half-width", "7", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["t"] == [0.0, 1.0] and out["energy"][0] == pytest.approx(1.0, rel=1e-12)
    assert out["kurtosis"][0] == pytest.approx(3.0, rel=1e-6) and out["energy"][1] < 1.0


def test_solve_takes_a_mapped_grid_for_gamma_zero(capsys):
    # the grid of test_a_mapped_grid_conserves_and_keeps_the_energy_identity; gamma = 0 at
    # density 1: <v^2> = exp(-2 lambda t) exactly, lambda = (1 - r^2)/4
    assert main(["solve", "-r", "0.8", "--rate", "relative_velocity", "--exponent", "0",
                 "--t", "0,0.5", "--points", "61", "--half-width", "30", "--core-spacing",
                 "0.2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["core_spacing"] == 0.2 and out["points"] == 61
    np.testing.assert_allclose(out["energy"], np.exp(-2 * 0.09 * np.array([0.0, 0.5])),
                               rtol=1e-10)


# --------------------------------------------------------------------------- hostile inputs


def _gaussian_solution():
    """A BoltzmannSolution and a ScalingState built by hand (no solve): a Gaussian F on a small
    grid at the saved times 0 and 1."""
    from maxwell_kinetics.inelastic_boltzmann import BoltzmannSolution, ScalingState

    grid = VelocityGrid(121, 6.0)
    f = np.exp(-0.5 * grid.c**2) / math.sqrt(2.0 * math.pi)
    sol = BoltzmannSolution(0.5, 1.0, 1.0, "gaussian", grid, np.array([0.0, 1.0]),
                            np.array([f, f]), np.zeros(2))
    return sol, ScalingState(0.5, 1.0, grid, f)


@pytest.mark.parametrize("edges", [[True, 2.0], [0.0, True], [False, 1, 2], (False, 0.5),
                                   [np.True_, 2.0], np.array([False, True])])
def test_booleans_are_not_histogram_edges(edges):
    """Booleans mixed into a list of edges were read as 0 and 1."""
    from particles.validation import check_real_array

    sol, _ = _gaussian_solution()
    with pytest.raises(InvalidArgumentError, match="argument edges="):
        sol.histogram(edges)
    with pytest.raises(InvalidArgumentError, match="argument edges="):
        check_real_array(edges, "edges")
    assert sol.histogram([-1.0, 0, 1]).density.size == 2  # ints and floats still taken


@pytest.mark.parametrize("rtol", [1.0, 1e300, 2, 0.0, -1e-3, True, float("nan")])
def test_rtol_is_a_relative_tolerance_below_one(rtol):
    """Rtol=1e300 was taken (no step-size control at all); a relative
    tolerance is in (0, 1)."""
    from maxwell_kinetics.solution import SolverOptions

    with pytest.raises(InvalidArgumentError, match=r"argument rtol="):
        SolverOptions(rtol=rtol)
    with pytest.raises(InvalidArgumentError, match=r"argument rtol="):
        solve_boltzmann(0.5, [1.0], rtol=rtol)
    assert SolverOptions(rtol=0.5).rtol == 0.5


def test_the_solutions_methods_refuse_bad_input_by_name():
    """A NaN x gave P = 0, order 2.5 gave NaN, and time_index(True) and
    time_index('2') were taken.  Each is refused naming the argument."""
    sol, state = _gaussian_solution()
    for t in (True, np.True_, "2", "1", float("nan"), [1.0], 1j):
        with pytest.raises(InvalidArgumentError, match=r"argument t="):
            sol.time_index(t)
        with pytest.raises(InvalidArgumentError, match=r"argument t="):
            sol.density([0.0], t)
    for x in (float("nan"), [0.0, np.inf], [True, 0.5], "1", 1j):
        with pytest.raises(InvalidArgumentError, match=r"argument x="):
            sol.density(x)
        with pytest.raises(InvalidArgumentError, match=r"argument x="):
            state.density(x)
    for order in (2.5, -1, True, "2", float("nan")):
        with pytest.raises(InvalidArgumentError, match=r"argument order="):
            state.moment(order)
        with pytest.raises(InvalidArgumentError, match=r"argument orders="):
            sol.moments((2, order))
    # what was right stays right
    assert sol.time_index(1.0) == 1 and sol.time_index(np.float64(0.0)) == 0
    assert sol.time_index(1) == 1 and sol.time_index() == 1
    assert sol.moments((2, 4.0)).values.shape == (2, 2)
    assert state.moment(np.int64(2)) == pytest.approx(1.0, rel=1e-6)
    assert state.moment(2.0) == state.moment(2)
    assert sol.density(0.0)[1].shape == () and state.density([0.0, 1.0]).shape == (2,)

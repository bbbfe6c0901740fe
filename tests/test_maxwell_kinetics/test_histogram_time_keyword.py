"""The time of a kinetic histogram is keyword-only: a second positional argument read as an index
into tau by Solution.histogram and as a time t by the hard-rod (and hard-sphere) solutions is
refused with a TypeError that names the keyword to use."""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest

from maxwell_kinetics.boltzmann_solution import BoltzmannSolution
from maxwell_kinetics.exact import f_hat
from maxwell_kinetics.grid import RESOLUTIONS
from maxwell_kinetics.solution import Solution
from maxwell_kinetics.sphere_solution import SphereSolution
from maxwell_kinetics.velocity_grid import VelocityGrid

EDGES = [-2.0, -0.5, 0.0, 0.5, 2.0]


def _fourier_solution():
    """A d = 1 Solution built from G = f̂ at τ = 0.5 and 1 (no solve)."""
    grid = RESOLUTIONS["coarse"]
    G = np.array([f_hat(grid.q), f_hat(grid.q)], dtype=complex)
    return Solution(0.5, "gaussian", grid, np.array([0.5, 1.0]), G, G - f_hat(grid.q))


def _rod_solution():
    """A hard-rod BoltzmannSolution built by hand (no solve): a Gaussian at t = 0 and 1."""
    grid = VelocityGrid(121, 6.0)
    f = np.exp(-0.5 * grid.c**2) / math.sqrt(2.0 * math.pi)
    return BoltzmannSolution(0.5, 1.0, 1.0, "gaussian", grid, np.array([0.0, 1.0]),
                             np.array([f, f]), np.zeros(2))


@pytest.mark.parametrize("second", [1, 0.5, -1])
def test_a_positional_time_of_the_fourier_solution_names_tau_index_and_tau(second):
    sol = _fourier_solution()
    with pytest.raises(TypeError, match=rf"Solution\.histogram\(\).*tau_index={second!r} "
                                        rf".*tau={second!r}"):
        sol.histogram(EDGES, second)


def test_the_fourier_solution_takes_its_time_by_keyword():
    sol = _fourier_solution()
    by_index = sol.histogram(EDGES, tau_index=1)
    assert np.array_equal(by_index.density, sol.histogram(EDGES, tau=1.0).density)
    assert np.array_equal(by_index.density, sol.histogram(EDGES, time=1.0).density)
    assert np.array_equal(by_index.density, sol.histogram(edges=EDGES).density)  # the last
    assert by_index.v0 != sol.histogram(EDGES, tau_index=0).v0


@pytest.mark.parametrize("second", [1.0, 0])
def test_a_positional_time_of_the_hard_rod_solution_names_t(second):
    sol = _rod_solution()
    with pytest.raises(TypeError, match=rf"BoltzmannSolution\.histogram\(\).*t={second!r} "):
        sol.histogram(EDGES, second)


def test_the_hard_rod_solution_takes_its_time_by_keyword():
    sol = _rod_solution()
    assert np.array_equal(sol.histogram(EDGES, t=1.0).density,
                          sol.histogram(EDGES, time=1.0).density)
    assert sol.histogram(EDGES, t=0.0).density.size == len(EDGES) - 1


def test_a_positional_time_of_the_hard_sphere_solution_names_t():
    sol = SphereSolution.__new__(SphereSolution)  # refused before any field is read
    with pytest.raises(TypeError, match=r"SphereSolution\.histogram\(\).*t=0\.4 "):
        sol.histogram(EDGES, 0.4)


@pytest.mark.parametrize("cls, keywords", [(Solution, ["tau_index", "tau", "time"]),
                                           (BoltzmannSolution, ["t", "time"]),
                                           (SphereSolution, ["t", "time"])])
def test_the_signature_shows_the_time_keyword_only(cls, keywords):
    params = inspect.signature(cls.histogram).parameters
    assert [p.name for p in params.values()
            if p.kind is inspect.Parameter.KEYWORD_ONLY] == keywords
    assert [p.name for p in params.values()
            if p.kind is inspect.Parameter.POSITIONAL_OR_KEYWORD] == ["self", "edges"]

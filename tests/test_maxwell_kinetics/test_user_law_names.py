"""A user's initial law is never matched to a built-in law by its name: a user law called
"uniform" is known by its own characteristic function only, in the solve, in the histogram's
treatment of the never-collided particles, and after a save and load."""

import dataclasses

import numpy as np
import pytest

from maxwell_kinetics import solve
from maxwell_kinetics.solution import Solution
from particles.initial import law_from_characteristic


@pytest.fixture(scope="module")
def gaussian_called_uniform():
    # A Gaussian, under the built-in uniform law's name, at r = 1 (elastic: G(q, τ) = φ(q) at
    # every τ, no time stepping to compile).  The uniform law's φ = sinc has a 1/k tail, so
    # taking its exact CDF for the never-collided particles (weight e^{−τ} = 0.61) instead of
    # cutting the user's φ at q_max moves bins near x = ±√3 by ~1e-4.
    law = law_from_characteristic(lambda k: np.exp(-0.5 * k**2), 1.0, name="uniform")
    return solve(1.0, law, tau=[0.5], resolution="coarse", progress=False)


def test_the_solve_uses_the_users_law_not_the_builtin_of_that_name(gaussian_called_uniform):
    sol = gaussian_called_uniform
    q = np.array([0.5, 2.0, 5.0])
    # the user's e^{−q²/2} (to the interpolation on the coarse grid, measured 1.3e-8), not the
    # uniform law's sinc(√3 q) (−0.09 at q = 2)
    assert np.max(np.abs(sol.evaluate(q, 0) - np.exp(-0.5 * q**2))) < 1e-6


def test_the_histogram_of_a_user_law_does_not_depend_on_its_name(gaussian_called_uniform,
                                                                   tmp_path):
    sol = gaussian_called_uniform
    edges = np.linspace(-4.0, 4.0, 33)
    renamed = dataclasses.replace(sol, initial="mine")  # not a built-in name: no CDF to take
    expected = renamed.histogram(edges).density
    assert np.array_equal(sol.histogram(edges).density, expected)
    sol.save(tmp_path / "sol.npz")
    assert np.array_equal(Solution.load(tmp_path / "sol.npz").histogram(edges).density,
                          expected)


def test_the_flag_is_the_solves_and_the_builtin_keeps_its_cdf(gaussian_called_uniform):
    from maxwell_kinetics.app.comparisons import never_collided_cut
    from particles.initial import LAWS
    from particles.validation import InvalidArgumentError

    assert gaussian_called_uniform.initial_law() is None
    builtin = solve(1.0, "uniform", tau=[0.5], resolution="coarse", progress=False)
    assert builtin.initial_law() is LAWS["uniform"]
    edges = np.linspace(-4.0, 4.0, 33)
    assert np.max(np.abs(never_collided_cut(builtin, 0, edges))) > 1e-5  # the sinc's ringing
    with pytest.raises(InvalidArgumentError, match="argument sol=.*user's law has no CDF"):
        never_collided_cut(gaussian_called_uniform, 0, edges)


def test_a_record_with_a_flag_that_is_not_a_bool_is_refused(gaussian_called_uniform):
    from particles.persistence import FileFormatError

    meta, arrays = gaussian_called_uniform.to_record()
    assert meta["builtin_law"] is False
    with pytest.raises(FileFormatError, match="builtin_law"):
        Solution.from_record({**meta, "builtin_law": "no"}, arrays)
    older = {k: v for k, v in meta.items() if k != "builtin_law"}  # records before the flag
    assert Solution.from_record(older, arrays).builtin_law is True

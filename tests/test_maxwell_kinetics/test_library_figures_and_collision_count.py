"""The library's own homes of what a library user needs from the application: the figures
(:mod:`maxwell_kinetics.figures`, moved from ``maxwell_kinetics.app.plotting``, whose old names
still work with a DeprecationWarning naming the new home) and the collisions per particle τ(t)
of a hard-rod solution (:meth:`maxwell_kinetics.BoltzmannSolution.collisions_per_particle`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from maxwell_kinetics import BoltzmannSolution, solve_boltzmann
from maxwell_kinetics.velocity_grid import VelocityGrid
from particles.validation import InvalidArgumentError

MOVED = ["new_figure", "plot_solution", "plot_density", "Figure"]


@pytest.mark.parametrize("name", MOVED)
def test_an_old_plotting_name_warns_and_names_its_new_home(name):
    import maxwell_kinetics.figures as figures
    from maxwell_kinetics.app import plotting

    with pytest.warns(DeprecationWarning, match=rf"maxwell_kinetics\.figures\.{name}\b"):
        old = getattr(plotting, name)
    assert old is getattr(figures, name)
    with pytest.warns(DeprecationWarning, match=r"moved to maxwell_kinetics\.figures"):
        exec(f"from maxwell_kinetics.app.plotting import {name}", {"__name__": "user_code"})


def test_no_module_of_the_project_imports_a_moved_name_from_its_old_home():
    # the application's own modules import the figures from the library (an import from the
    # old place would warn in every command that draws)
    import ast
    from pathlib import Path

    import maxwell_kinetics
    from maxwell_kinetics.app import plotting

    root = Path(maxwell_kinetics.__file__).parent
    found = []
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").endswith("plotting"):
                moved = [a.name for a in node.names if a.name in MOVED]
                if moved:
                    found.append(f"{path.relative_to(root)}: {moved}")
    assert found == []
    assert "plot_convergence" in plotting.__all__
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        plotting.nothing  # noqa: B018


def test_the_library_figures_are_outside_pyplot_and_their_legends_legible():
    import matplotlib
    import matplotlib.pyplot as plt

    from maxwell_kinetics.figures import MIN_LEGEND_POINTS, legend_floor, new_figure, plot_density

    before = plt.get_fignums()
    fig, axes = new_figure(3, width=2.0, height=1.5, nrows=2)
    assert axes.shape == (2, 3)
    assert tuple(fig.get_size_inches()) == (6.0, 3.0)
    assert plt.get_fignums() == before
    assert fig._repr_png_().startswith(b"\x89PNG")
    # a legend asked for at 5 points (text and title) is drawn at the tick labels' size
    ticks = matplotlib.rcParams["xtick.labelsize"]
    floor = legend_floor()
    assert floor >= MIN_LEGEND_POINTS == 8.0
    axes[0, 0].plot([0, 1], [0, 1], label="line")
    legend = axes[0, 0].legend(fontsize=5, title="title", title_fontsize=5)
    sizes = [t.get_fontsize() for t in legend.get_texts()] + [legend.get_title().get_fontsize()]
    tick_size = axes[0, 0].xaxis.get_ticklabels()[0].get_fontsize()
    assert sizes == [floor, floor] and floor >= tick_size, (sizes, tick_size, ticks)
    # also on a twin axis and with a font dictionary, and a larger size is kept
    twin = axes[0, 1].twinx()
    twin.plot([0, 1], [1, 0], label="twin")
    assert twin.legend(prop={"size": 4}).get_texts()[0].get_fontsize() == floor
    assert twin.legend(fontsize=floor + 3).get_texts()[0].get_fontsize() == floor + 3
    x = np.linspace(-3, 3, 61)
    drawn = plot_density(x, np.exp(-x * x / 2) / math.sqrt(2 * math.pi), 1.0, title="unit")
    labels = [t.get_text() for t in drawn.axes[0].get_legend().get_texts()]
    assert labels == ["P(v)", "Gaussian, same variance"]


def test_collisions_per_particle_of_the_elastic_and_the_maxwell_gas():
    """At r = 1 from the unit Gaussian the law does not change, and each particle collides at
    rate n⟨|v − w|⟩ = 2n/√π: τ(t) = 2nt/√π, times the grid's factor 1 − h²/24 − h⁴/960 of the
    trapezoid rule of |x| across its kink (h = 0.12; derived in the planted-survivor tests of
    the same count), to 1e-7.  The Maxwell kernel (γ = 0) collides at rate n: τ = n t to
    round-off, whatever r."""
    grid = VelocityGrid(101, 6.0)
    t = np.array([0.0, 0.3, 1.0, 2.5])
    factor = 1.0 - grid.h**2 / 24.0 - grid.h**4 / 960.0
    for n in (1.0, 2.5):
        rods = solve_boltzmann(1.0, t, density=n, grid=grid)
        assert isinstance(rods, BoltzmannSolution)
        tau = rods.collisions_per_particle()
        assert tau[0] == 0.0
        np.testing.assert_allclose(tau[1:] / (2.0 * n * t[1:] / math.sqrt(math.pi)), factor,
                                   rtol=0, atol=1e-7)
    maxwell = solve_boltzmann(0.5, t, exponent=0.0, density=2.0, grid=grid)
    np.testing.assert_allclose(maxwell.collisions_per_particle(), 2.0 * t, rtol=1e-12, atol=0)


def test_collisions_per_particle_is_the_application_count_and_starts_at_zero():
    from maxwell_kinetics.app.comparisons import collisions_per_particle

    grid = VelocityGrid(101, 6.0)
    t = np.linspace(0.0, 2.0, 11)
    rods = solve_boltzmann(0.8, t, density=1.5, grid=grid)
    np.testing.assert_allclose(rods.collisions_per_particle(), collisions_per_particle(rods),
                               rtol=1e-13, atol=0)
    late = solve_boltzmann(0.8, t[1:], grid=grid)
    with pytest.raises(InvalidArgumentError, match="argument t=0.2 is invalid"):
        late.collisions_per_particle()

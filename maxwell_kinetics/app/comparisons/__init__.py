"""The comparisons of ``maxwell-kinetics reproduce``: kinetic theory, the paper's figures, and
kinetic theory against the particle models, each returning numbers and the data of a figure.

Every comparison is a function ``name(size=None, progress=None, **overrides)`` returning a
:class:`Comparison`: ``summary`` (JSON-able: every fitted exponent and distance with its
uncertainty, the parameters used, wall-clock seconds) and ``data`` (arrays for the figure,
drawn by ``Comparison.figure()``).  ``size`` is one of :data:`SIZES`:

``small``    seconds; what the tests and the notebooks (``MAXWELL_KINETICS_SMALL=1``) run;
``default``  what ``maxwell-kinetics reproduce`` runs (≤ 10 minutes in all on 2 cores);
``full``     the paper's sizes where affordable (N = 10⁶ for the Ulam model; see each function).

Keyword overrides replace single parameters of the preset (e.g. ``n=20000``).

Statistical conventions: see :mod:`maxwell_kinetics.statistics`.  Uncertainties are one
standard error; where several independent runs (seeds) exist, they come from the scatter
between runs, which includes the correlations between the particles of one run.

The protocol and the registry (:mod:`.base`): a comparison is a :class:`ComparisonSpec`,
its ``name``, ``presets`` (size → parameters), ``run(size=None, progress=None, **overrides) ->
Comparison``, ``plot(comparison, ax=None)`` (draws only), ``verdicts(summary) -> list of
Verdict`` (the claims it tests, each a :func:`.verdicts.judge` of a :class:`.verdicts.Check`
read from the summary) and ``order`` (``reproduce`` runs the comparisons by increasing order),
registered once with :func:`register`.  Everything that lists the comparisons is read from that
registry: :data:`COMPARISONS` (name → run function, in reproduce's order), :data:`PRESETS`,
:data:`VERDICTS`, the ``plot`` that ``Comparison.figure()`` draws with, and this package's
functions ``kinetic_theory`` … (made from :data:`COMPARISONS` when the package is imported).
:func:`registered` registers a comparison for the duration of a ``with`` block only.

Adding a comparison: a new module ``_<name>.py`` here, with ``NAME``, ``PRESETS``, ``run``
(ending with ``return Comparison(NAME, with_verdicts(summary, verdicts), data)``, which puts
the verdicts' records in ``summary["verdicts"]``), ``plot`` and ``verdicts``, whose last line
registers it::

    COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=13))

plus its name in the ``from . import (...)`` below, which imports (and so registers) every
comparison.  Nothing else lists the comparisons.

Layout (imports run downwards only; no module of the package imports this one):

* :mod:`.base` — the :class:`Comparison` record, its file format, sizes and presets, and the
  protocol (:class:`ComparisonSpec`) with the registry;
* :mod:`.particle_runs` — Ulam, lattice and MD runs through the run driver, cached read-only;
* :mod:`.kinetic_predictions` — the solver's solutions and predicted bin probabilities;
* :mod:`.analysis` — estimators on arrays (profiles, S(k) fits, jackknife);
* :mod:`.drawing` — array-level drawing helpers;
* :mod:`.verdicts` — a claim's measured value against its expected one, judged ``agrees``,
  ``disagrees`` or ``explained``;
* one private module per comparison (``_kinetic_theory`` …), registered as above.
"""

from __future__ import annotations

# Importing a comparison's module registers it: one name here per comparison.
from . import (  # noqa: F401
    _driven_steady,
    _energy_decay,
    _hard_spheres,
    _kinetic_theory,
    _kinetic_vs_ulam,
    _late_stage,
    _rate_vs_correlations,
    _sticky_vs_md,
    _structure_factors,
    _tail_exponents,
    _ulam_collapse,
    _velocity_distributions,
    _velocity_profiles,
)
from ._rate_vs_correlations import (
    collisions_per_particle,
    kurtosis_sampling_error,
    kurtosis_split,
    maxwell_kurtosis,
)
from .analysis import (
    block_means,
    coarse_increment_skewness,
    porod_fit,
    profile_scales,
    velocity_on_grid,
)
from .base import (
    COMPARISONS,
    PRESETS,
    REGISTRY,
    SIZES,
    VERDICTS,
    Comparison,
    ComparisonSpec,
    comparison_spec,
    default_size,
    register,
    registered,
    unregister,
)
from .kinetic_predictions import (
    fft_bin_probabilities,
    kinetic_solution,
    law_cdf,
    never_collided_cut,
    solution_bin_probabilities,
)
from .particle_runs import (
    ParticleRuns,
    lattice_at_energy,
    lattice_runs,
    md_runs,
    sticky_runs,
    ulam_snapshots,
)

# The package's function of each comparison (``kinetic_theory`` …): its registered ``run``.
globals().update(COMPARISONS)

__all__ = [
    "SIZES",
    "Comparison",
    "default_size",
    *COMPARISONS,
    "coarse_increment_skewness",
    "block_means",
    "velocity_on_grid",
    "profile_scales",
    "porod_fit",
    "lattice_at_energy",
    "COMPARISONS",
    "kinetic_solution",
    "solution_bin_probabilities",
    "fft_bin_probabilities",
    "never_collided_cut",
    "law_cdf",
    "lattice_runs",
    "ParticleRuns",
    "md_runs",
    "sticky_runs",
    "ulam_snapshots",
    "ABS_MEAN_F",
    "ABS_MEAN_GAUSSIAN",
    "collisions_per_particle",
    "maxwell_kurtosis",
    "kurtosis_split",
    "kurtosis_sampling_error",
    "PRESETS",
    "VERDICTS",
    "z_drift",
    "ComparisonSpec",
    "REGISTRY",
    "register",
    "unregister",
    "registered",
    "comparison_spec",
]

z_drift = _structure_factors.z_drift

ABS_MEAN_F = _velocity_distributions.ABS_MEAN_F
ABS_MEAN_GAUSSIAN = _velocity_distributions.ABS_MEAN_GAUSSIAN

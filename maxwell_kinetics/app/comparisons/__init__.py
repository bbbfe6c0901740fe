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

Layout (imports run downwards only; no module of the package imports this one):

* :mod:`.base` — the :class:`Comparison` record, its file format, sizes and presets;
* :mod:`.particle_runs` — Ulam, lattice and MD runs through the run driver, cached read-only;
* :mod:`.kinetic_predictions` — the solver's solutions and predicted bin probabilities;
* :mod:`.analysis` — estimators on arrays (profiles, S(k) fits, jackknife);
* :mod:`.drawing` — array-level drawing helpers;
* :mod:`.verdicts` — a claim's measured value against its expected one, judged ``agrees``,
  ``disagrees`` or ``explained``;
* one private module per comparison (``_kinetic_theory`` …), each with ``PRESETS``,
  ``run(size=None, progress=None, **overrides) -> Comparison``, ``plot(comparison, ax=None)``
  (draws only; registered so that ``Comparison.figure()`` finds it) and
  ``verdicts(summary) -> list of Verdict`` (the claims it tests, each a
  :func:`.verdicts.judge` of a :class:`.verdicts.Check` read from the summary); ``run`` ends
  with ``return Comparison(NAME, with_verdicts(summary, verdicts), data)``, which puts the
  verdicts' records in ``summary["verdicts"]``.
"""

from __future__ import annotations

from . import (
    _driven_steady,
    _energy_decay,
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
from .base import SIZES, Comparison, default_size
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

__all__ = [
    "SIZES",
    "Comparison",
    "default_size",
    "kinetic_theory",
    "kinetic_vs_ulam",
    "ulam_collapse",
    "energy_decay",
    "structure_factors",
    "velocity_distributions",
    "velocity_profiles",
    "sticky_vs_md",
    "late_stage",
    "tail_exponents",
    "driven_steady",
    "rate_vs_correlations",
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
]

kinetic_theory = _kinetic_theory.run
kinetic_vs_ulam = _kinetic_vs_ulam.run
ulam_collapse = _ulam_collapse.run
velocity_distributions = _velocity_distributions.run
energy_decay = _energy_decay.run
structure_factors = _structure_factors.run
velocity_profiles = _velocity_profiles.run
sticky_vs_md = _sticky_vs_md.run
late_stage = _late_stage.run
tail_exponents = _tail_exponents.run
driven_steady = _driven_steady.run
rate_vs_correlations = _rate_vs_correlations.run

z_drift = _structure_factors.z_drift

ABS_MEAN_F = _velocity_distributions.ABS_MEAN_F
ABS_MEAN_GAUSSIAN = _velocity_distributions.ABS_MEAN_GAUSSIAN

#: The comparisons of ``reproduce``, in the order it runs them: name → run function.
COMPARISONS = {
    "kinetic_theory": kinetic_theory,
    "kinetic_vs_ulam": kinetic_vs_ulam,
    "ulam_collapse": ulam_collapse,
    "velocity_distributions": velocity_distributions,
    "energy_decay": energy_decay,
    "structure_factors": structure_factors,
    "velocity_profiles": velocity_profiles,
    "sticky_vs_md": sticky_vs_md,
    "late_stage": late_stage,
    "tail_exponents": tail_exponents,
    "driven_steady": driven_steady,
    "rate_vs_correlations": rate_vs_correlations,
}

_MODULES = {
    "kinetic_theory": _kinetic_theory, "kinetic_vs_ulam": _kinetic_vs_ulam,
    "ulam_collapse": _ulam_collapse, "velocity_distributions": _velocity_distributions,
    "energy_decay": _energy_decay, "structure_factors": _structure_factors,
    "velocity_profiles": _velocity_profiles, "sticky_vs_md": _sticky_vs_md,
    "late_stage": _late_stage, "tail_exponents": _tail_exponents,
    "driven_steady": _driven_steady, "rate_vs_correlations": _rate_vs_correlations,
}
#: Each comparison's size presets: name → {size: parameters}.
PRESETS = {name: module.PRESETS for name, module in _MODULES.items()}
#: Each comparison's judge of its claims: name → ``verdicts(summary) -> list of Verdict``.
VERDICTS = {name: module.verdicts for name, module in _MODULES.items()}

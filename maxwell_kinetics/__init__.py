"""maxwell_kinetics: kinetic theory of inelastic Maxwell models in Fourier space (JAX in float64,
diffrax, pyfftw), and, in its own subpackage :mod:`maxwell_kinetics.app`, the application built on
it and on :mod:`particles`: the command line (:mod:`.app.cli`, one module per subcommand in
:mod:`.app.commands`), the comparisons with the paper (:mod:`.app.comparisons`), ``reproduce``,
plotting and output.  The kinetic library (every module outside ``app``) imports nothing from the
application.

Importing an application module by a path outside ``app`` (``maxwell_kinetics.cli``,
``maxwell_kinetics.comparisons``, ... listed in :data:`MOVED`) raises an :class:`ImportError`
that names its home in ``app`` (a finder for those names alone is put first on
``sys.meta_path`` on import; it finds no other module).

Importing this package changes no global configuration.  The JAX computations (:mod:`.solver`,
:mod:`.stationary`) run in float64 inside ``jax.enable_x64(True)``, a thread-local context that
restores the caller's setting, so a user's own float32 JAX code is not affected.

Public names are loaded lazily so that ``import maxwell_kinetics`` stays light (no JAX until a
solver runs).
"""

from __future__ import annotations

import importlib
import importlib.abc
import sys

__version__ = "0.2.0"

_LAZY = {
    "MaxwellModel": "model",
    "RelativeVelocityModel": "model",
    "solve_boltzmann": "inelastic_boltzmann",
    "BoltzmannSolution": "inelastic_boltzmann",
    "scaling_state": "inelastic_boltzmann",
    "ScalingState": "inelastic_boltzmann",
    "VelocityGrid": "velocity_grid",
    "MappedGrid": "velocity_grid",
    "Resolution": "grid",
    "RESOLUTIONS": "grid",
    "solve": "solver",
    "solve_fourier": "solver",
    "FourierScheme": "methods",
    "VelocitySpace": "methods",
    "Solution": "solution",
    "SolverOptions": "solution",
    "Moments": "moments",
    "fixed_point": "stationary",
    "FixedPoint": "stationary",
    "linear_decay_rates": "linear_rates",
    "LinearRates": "linear_rates",
    "f_hat": "exact",
    "f_density": "exact",
    "get_law": "particles.initial",
    "law_from_characteristic": "particles.initial",
    "InitialLaw": "particles.initial",
    "InvalidArgumentError": "particles.validation",
    "tail_exponent": "tails",
    "TailExponent": "tails",
    "decay_rate": "tails",
    "moment_rates": "tails",
    "steady_state": "driven",
    "DrivenSteadyState": "driven",
    "Comparison": "maxwell_kinetics.app.comparisons",
    "COMPARISONS": "maxwell_kinetics.app.comparisons",
}

#: Modules moved into :mod:`maxwell_kinetics.app`: old dotted name -> new one.  Importing an old
#: name (or a module below it) raises an ImportError naming the new home.
MOVED = {f"maxwell_kinetics.{name}": f"maxwell_kinetics.app.{name}"
         for name in ("cli", "commands", "comparisons", "reproduce", "plotting", "output",
                      "convergence")}


def _moved_message(fullname: str) -> str | None:
    for old, new in MOVED.items():
        if fullname == old or fullname.startswith(old + "."):
            return f"{fullname} moved to {new + fullname[len(old):]}"
    return None


class _MovedFinder(importlib.abc.MetaPathFinder):
    """Refuses the old paths of the moved modules with an ImportError naming the new home."""

    def find_spec(self, fullname, path=None, target=None):
        message = _moved_message(fullname)
        if message is not None:
            raise ImportError(message, name=fullname)
        return None


if not any(type(f).__name__ == "_MovedFinder" for f in sys.meta_path):
    sys.meta_path.insert(0, _MovedFinder())

#: The public names: each is loaded on first access.
__all__ = list(_LAZY)


def __getattr__(name):
    if name in _LAZY:
        where = _LAZY[name]
        module = importlib.import_module(where if "." in where else f".{where}", __name__)
        return getattr(module, name)
    message = _moved_message(f"{__name__}.{name}")
    if message is not None:
        raise AttributeError(message)
    raise AttributeError(f"module 'maxwell_kinetics' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))

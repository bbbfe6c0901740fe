"""particles: exact stochastic counterparts of the kinetic theory (NumPy only).

Modules, one job each: :mod:`.collision` (the collision rule), :mod:`.driver` (initial
velocities, the run loop, checkpoints, results), :mod:`.observables`, :mod:`.ulam` (mean-field
pseudo-Maxwell model), :mod:`.lattice` (ring lattice model), :mod:`.cli` (``simulate``).
No module here imports JAX.
"""

from .driver import CheckpointError as CheckpointError
from .driver import RunResult as RunResult
from .driver import initial_velocities as initial_velocities
from .driver import simulate as simulate
from .lattice import Lattice as Lattice
from .lattice import LatticeState as LatticeState
from .observables import correlation as correlation
from .observables import energy as energy
from .observables import log_bin as log_bin
from .observables import rescaled_histogram as rescaled_histogram
from .observables import structure_factor as structure_factor
from .ulam import Ulam as Ulam
from .ulam import UlamState as UlamState

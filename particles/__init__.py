"""particles: exact stochastic counterparts of the kinetic theory (NumPy only).

The base layer of maxwell-kinetics: it imports nothing from :mod:`maxwell_kinetics` and no JAX.
Modules, one job each:

* :mod:`.validation` — argument checks (``InvalidArgumentError``);
* :mod:`.parsing` — exact parsing of command-line text into typed values;
* :mod:`.paths` — file-system checks of input and output paths;
* :mod:`.workers` — worker limits of parallel runs;
* :mod:`.initial` — the initial velocity laws with their characteristic functions;
* :mod:`.collision` — the collision rule;
* :mod:`.kernels` — the collision kernels (:mod:`.sphere_kernels`: hard spheres in d = 2, 3);
* :mod:`.observables` — energy, histograms, C(r), S(k);
* :mod:`.persistence` — the one way every file is saved and loaded (atomic, hashed, bounded);
* :mod:`.budget` — memory and work estimated before a run starts;
* :mod:`.progress` — progress bars (plain lines when stderr is not a terminal);
* :mod:`.driver` — the run loop shared by every engine: seeds, checkpoints, results;
* the models: :mod:`.ulam` (mean-field pseudo-Maxwell), :mod:`.lattice` (ring lattice),
  :mod:`.md` (event-driven inelastic hard rods), :mod:`.sticky` (the sticky gas, exact);
* :mod:`.models` — the catalogue of the models: factories and typed parameters, from which the
  command line, the ensembles and the comparisons' runs are generated;
* :mod:`.ensemble` — many runs of one model over parameters and seeds (dask or serial).
"""

from .driver import CheckpointError as CheckpointError
from .driver import RunResult as RunResult
from .driver import initial_velocities as initial_velocities
from .driver import simulate as simulate
from .initial import get_law as get_law
from .initial import law_from_characteristic as law_from_characteristic
from .lattice import Lattice as Lattice
from .lattice import LatticeState as LatticeState
from .md import InelasticCollapseError as InelasticCollapseError
from .md import MDEngine as MDEngine
from .md import MDParams as MDParams
from .md import MDState as MDState
from .observables import correlation as correlation
from .observables import energy as energy
from .observables import log_bin as log_bin
from .observables import rescaled_histogram as rescaled_histogram
from .observables import structure_factor as structure_factor
from .persistence import FileFormatError as FileFormatError
from .sphere_kernels import HardSpheres as HardSpheres  # registers the sphere kernels
from .sphere_kernels import VariableHardSpheres as VariableHardSpheres
from .sticky import StickyGas as StickyGas
from .sticky import StickyParams as StickyParams
from .sticky import StickyState as StickyState
from .ulam import Ulam as Ulam
from .ulam import UlamState as UlamState
from .validation import InvalidArgumentError as InvalidArgumentError

__all__ = [
    "CheckpointError",
    "RunResult",
    "initial_velocities",
    "simulate",
    "get_law",
    "law_from_characteristic",
    "Lattice",
    "LatticeState",
    "InelasticCollapseError",
    "MDEngine",
    "MDParams",
    "MDState",
    "correlation",
    "energy",
    "log_bin",
    "rescaled_histogram",
    "structure_factor",
    "FileFormatError",
    "HardSpheres",
    "VariableHardSpheres",
    "StickyGas",
    "StickyParams",
    "StickyState",
    "Ulam",
    "UlamState",
    "InvalidArgumentError",
]

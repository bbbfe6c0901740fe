"""The application built on the kinetic library (:mod:`maxwell_kinetics`) and on
:mod:`particles`: the command line ``maxwell-kinetics`` (:mod:`.cli`, one module per subcommand in
:mod:`.commands`, the cache option in :mod:`.cache_options`), the comparisons with the paper
(:mod:`.comparisons`), ``reproduce`` (:mod:`.reproduce`), the convergence study
(:mod:`.convergence`), plotting (:mod:`.plotting`) and the output helpers (:mod:`.output`).

The kinetic library (every module of :mod:`maxwell_kinetics` outside this subpackage) imports
nothing from here; this subpackage imports the library.  Importing it loads nothing: each module
is imported where used.
"""

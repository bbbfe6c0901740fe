"""One module per subcommand of ``maxwell-kinetics``: ``solve``, ``fixed_point``,
``convergence``, ``reproduce``, ``simulate``.  Each has ``add_parser(subparsers)`` and a handler
``run(args) -> int``; shared output code is in :mod:`maxwell_kinetics.app.output`.  Modules that
need JAX import it inside their handler, so that ``maxwell-kinetics simulate`` never loads it."""

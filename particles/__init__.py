"""particles: exact stochastic counterparts of the kinetic theory (NumPy only)."""

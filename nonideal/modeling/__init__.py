"""Stage 1 -- what the user declares: the :class:`Model` (coordinates, energies, forces,
bodies, constraints, contacts, initial state), the safe expression parser, model files and the
bridge from ``sympy.physics.mechanics``.  Imports nothing but :mod:`nonideal.errors`."""

"""Stage 2 -- symbolic only: the :class:`~nonideal.equations.dynamics.Dynamics` of a model
(T, V, M, F, acceleration energy S, constraint rows) and the classical forms of the equations
of motion (:mod:`nonideal.equations.formalisms`), each filling one
:class:`~nonideal.equations.eom.EquationsOfMotion`."""

"""Stage 4 -- the motion at one state in one mode.

:mod:`~nonideal.modes.types` holds the data (:class:`Mode`, :class:`ContactState`,
:class:`Solution`) and imports nothing above :mod:`nonideal.modeling`;
:mod:`~nonideal.modes.solver` (:class:`ModeSolver`) computes the motion by one of its routes
(Lagrange I saddle-point systems in :mod:`~nonideal.modes.system`, a derived form, Lagrange II on
its charts in :mod:`~nonideal.modes.charts`, the Gauss principle in :mod:`~nonideal.modes.gauss`);
:mod:`~nonideal.modes.switching` chooses the mode at a state; :mod:`~nonideal.modes.indeterminate`
distributes statically indeterminate reactions; :mod:`~nonideal.modes.diagnosis` says why a
state is singular.
"""

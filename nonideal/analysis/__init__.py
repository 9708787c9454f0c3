"""Stage 6 -- analyses built on the earlier stages: the motion and reactions at a state
(:mod:`~nonideal.analysis.evaluation`), the checks of a model, cross-checks of the forms,
realizability of rolling by Coulomb friction (Kalinin & Novozhilov), the friction law of a
system (Manglieva & Beknazarov 2022)."""

"""Stability: linearization on the constraint manifold, linear systems, Routh–Hurwitz, programmed motions (Persidsky), controllability and LQR, the Riccati regimes of Briskin et al. 2021."""

"""Studies over parameters: sweeps (on all cores or a Dask cluster), quasi-ideal design measures and their minimization (Briskin et al. 2021)."""

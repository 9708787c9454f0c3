"""Stage 3 -- compiled callables: the model's kernel (M, F, G, gamma, B at a state, SymEngine
with common-subexpression elimination), the contacts' kernel, compiled forms, and consistent
initial states (the constraints completed, the projection back onto the constraint manifold)."""

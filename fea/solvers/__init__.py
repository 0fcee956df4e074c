"""Solvers of the finite-element model: explicit dynamics, statics, modes, and their checks."""

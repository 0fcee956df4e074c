"""Finite elements, one module per element: its geometry, kernel, tangent and mass."""

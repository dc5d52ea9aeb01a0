"""Leakage through the gap: Reynolds flow by finite volumes, its face matrix, and its solves
(sparse LU, pixel-block multigrid), also in a background thread."""

"""The contact problem: constrained conjugate gradients with their buffers and preconditioners, the
stiffness, the area estimators, the solution record and load paths."""

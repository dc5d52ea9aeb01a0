"""The discrete asperity model with first-order interaction: point-force interaction, assembly, the
complementarity solver, path steps and the result."""

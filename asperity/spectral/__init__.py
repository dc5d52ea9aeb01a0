"""Theories from the power spectrum: Nayak's summit statistics, Bush-Gibson-Thomas with elliptic
Hertz summits, and Persson's theory with its gaps."""

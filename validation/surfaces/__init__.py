"""Rough surfaces: Weierstrass-Mandelbrot (:mod:`~validation.surfaces.wm`), self-affine spectra,
measured height maps, the statistics of any height map (:mod:`~validation.surfaces.statistics`),
the `[surface]` table of a scene (:mod:`~validation.surfaces.spec`) and the families that turn it
into heights (:mod:`~validation.surfaces.families`)."""

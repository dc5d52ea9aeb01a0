"""Each theory's error predicted from the surface, before any boundary-element solve.

* :mod:`.design` -- the atlas' design points over the surface descriptors, one scene each;
* :mod:`.build` -- the atlas computed (cached, resumable): every theory's error per
  realization, load and quantity, ``python -m validation atlas``;
* :mod:`.model` -- the error model fitted to it (mean and 90 % prediction interval as functions
  of the descriptors and the load), stored in ``error_model.json`` beside this file;
* :mod:`.predict` -- :func:`predict_errors`, ``python -m validation predict SCAN``.
"""

"""What every layer of :mod:`validation` shares, at the bottom where each can reach it: the model
registry (:mod:`~validation.common.models`), the names and labels of models and quantities
(:mod:`~validation.common.labels`) and the field checks of scenes and their surfaces
(:mod:`~validation.common.checks`). It imports nothing else of :mod:`validation`."""

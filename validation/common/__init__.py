"""What every layer of :mod:`validation` shares, at the bottom where each can reach it: the model
registry (:mod:`~validation.common.models`), the names and labels of models and quantities
(:mod:`~validation.common.labels`), the field checks of scenes and their surfaces
(:mod:`~validation.common.checks`) and the names of the verdicts with their confidence
(:mod:`~validation.common.verdicts`). It imports nothing else of :mod:`validation`."""

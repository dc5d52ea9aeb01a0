"""Running scenes: the model registry (:mod:`~validation.run.models`), the runner with its result
cache, the task cost model and progress bar, and the theory curves of theory scenes."""

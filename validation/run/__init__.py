"""Running scenes: the runner with its result cache, the task cost model and progress bar, and
the theory curves of theory scenes; models are built by name from the registry
(:mod:`validation.common.models`)."""

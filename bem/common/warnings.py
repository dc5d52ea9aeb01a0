"""Warning classes shared by every solver of the project."""

__all__ = ["ConvergenceWarning"]


class ConvergenceWarning(UserWarning):
    """An iterative solver stopped before meeting its tolerance; its result says so too."""

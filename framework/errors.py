"""The framework's exceptions.

Every message says what was wrong, the value received and what was expected.
The classes also derive from the matching built-in so that callers may catch
``ValueError`` or ``RuntimeError`` as usual.
"""


class FrameworkError(Exception):
    """Base class of every exception raised on purpose by the framework."""


class ParameterError(FrameworkError, ValueError):
    """A parameter has a value outside its admissible range or of the wrong kind."""


class FileError(ParameterError):
    """A file cannot be read as what it should be: missing, of another kind, damaged, or refused (it takes data
    from other files). The message names the file and what is wrong with it, on one line."""


class ShapeError(FrameworkError, ValueError):
    """An array does not have the shape the operation needs."""


class InclusionError(ParameterError):
    """Inclusions that cannot be modelled as placed: overlapping, cutting the surface, leaving the grid, under-resolved."""


class GridTooSmallError(FrameworkError, ValueError):
    """The contact reaches the edge of a non-periodic grid: enlarge the grid or lower the load."""


class LoadNotCarriedError(FrameworkError, ValueError):
    """No contact of the body can carry the load where it is applied (e.g. an offset beyond a punch's face)."""


class ConvergenceError(FrameworkError, RuntimeError):
    """An iterative solver stopped before meeting its tolerance."""

    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result


class FrameworkWarning(UserWarning):
    """Base class of the framework's warnings: a result was produced, but read it with care."""


class CoverageWarning(FrameworkWarning):
    """A fit claims more than its data cover. No longer raised by the dynamic Prony fit, whose times now stay within
    half a decade of the data; kept so that scripts that catch it still run."""


class DataWarning(FrameworkWarning):
    """Points of measured data were dropped (unusable values, repeated frequencies): the warning lists each."""


class UncheckedFileWarning(FrameworkWarning):
    """A file was read without checksums, as its format predates them: damage to it would go unnoticed."""


class ResolutionWarning(FrameworkWarning):
    """A result is resolved too coarsely to trust its numbers to a percent (e.g. a contact a few cells wide): the
    warning gives the numbers and what to change."""

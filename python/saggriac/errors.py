"""Exceptions raised by saggriac. Every one derives from :class:`SaggriacError`."""

from __future__ import annotations


class SaggriacError(Exception):
    """Base class of every error raised by saggriac."""


class ParameterError(SaggriacError, ValueError):
    """A parameter broke a rule. ``param`` names it and ``value`` shows what was given."""

    def __init__(self, message: str, param: str | None = None, value: str | None = None):
        super().__init__(message)
        self.param = param
        self.value = value


class InputError(SaggriacError, ValueError):
    """Input data that cannot be used as given."""


class StorageError(SaggriacError, OSError):
    """A run directory cannot be written or read."""


class ConformanceError(SaggriacError, TypeError):
    """A user's environment or goal selector does not follow the protocol saggriac needs."""


class WorkerRefusalError(SaggriacError, RuntimeError):
    """A worker process refused the teacher it was given (a ConformanceError there), raised in the
    process that started the worker. Not a TypeError like ConformanceError: it arrives from a
    signal, wherever that process was, and code there that catches TypeError (pathlib does)
    must not swallow it."""

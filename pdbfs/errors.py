"""Errors pdbfs raises on bad input. Each message names the culprit."""


class PdbfsError(Exception):
    """Base of every error pdbfs raises on purpose; the CLI prints its message."""


class ParameterError(PdbfsError, ValueError):
    """A parameter name or value is wrong (unknown, NaN, out of bounds)."""


class ConnectError(PdbfsError, ValueError):
    """A connect() call is wrong (self-connection, incompatible connectors)."""


class ModelError(PdbfsError):
    """The rig's equations are inconsistent: under- or over-determined, singular."""


class SolverError(PdbfsError, RuntimeError):
    """The integrator failed; the message gives the time reached and a likely cause."""


class ExportError(PdbfsError, ValueError):
    """A rig cannot be turned into C code or an FMU (algebraic variables
    left, no compiler, a compilation failure)."""


class DataError(PdbfsError, ValueError):
    """A data file (a measured trace, a target curve) is missing or malformed;
    the message names the file and what is wrong with it."""

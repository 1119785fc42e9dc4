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


class MissingExtraError(PdbfsError, ImportError):
    """A feature needs a package of one of pdbfs's extras that is not
    installed; the message names the extra and the pip command that adds it."""


#: the extras of ``pip install pdbfs[...]``: the packages each brings (as imported)
EXTRAS = {"app": ("dash", "diskcache", "multiprocess", "orjson"),
          "dask": ("dask", "distributed"),
          "parquet": ("pyarrow",),
          "sensitivity": ("SALib",),
          "control": ("control",)}


def missing_extra(extra: str) -> str | None:
    """The first package of one of pdbfs's extras that is not installed
    (looked up without importing it).

    Parameters
    ----------
    extra : str
        A key of :data:`EXTRAS` ("app", "dask", "parquet", "sensitivity", "control").

    Returns
    -------
    str or None
        The module that cannot be imported, or None when all are installed.
    """
    from importlib.util import find_spec
    for module in EXTRAS[extra]:
        try:
            if find_spec(module) is None:
                return module
        except (ImportError, ValueError):
            return module
    return None


def require_extra(extra: str, what: str) -> None:
    """Raise :class:`MissingExtraError` if ``extra`` is not installed.

    Parameters
    ----------
    extra : str
        A key of :data:`EXTRAS` ("app", "dask", "parquet", "sensitivity", "control").
    what : str
        The feature that needs it, as the message names it (e.g. "pdbfs app").
    """
    module = missing_extra(extra)
    if module is not None:
        raise MissingExtraError(f"{what} needs pdbfs's extra [{extra}] ({module} is not "
                                f"installed): pip install 'pdbfs[{extra}]'")


class PdbfsWarning(UserWarning):
    """Base of pdbfs's warnings; the CLI prints each as one line on stderr."""


class PulseIncompleteWarning(PdbfsWarning):
    """A pulse is still running at the end of the run: figures that need its
    end are not reported; the message names a horizon that would hold it."""


class ImplausibleResultWarning(PdbfsWarning):
    """A figure of a run lies outside its physical range (a restitution
    coefficient above 1): the message names the likely cause."""


class SampleTooSmallWarning(PdbfsWarning):
    """A sample is too small for the statistics computed from it to mean anything."""


def plain(value) -> str:
    """A value as an error message shows it.

    Parameters
    ----------
    value : object
        A number, a numpy scalar, a list, tuple or dict of them, or anything.

    Returns
    -------
    str
        Numbers plainly (``3.0``, never ``np.float64(3.0)``; floats to 6
        significant digits), containers of them likewise, anything else by
        repr.
    """
    if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:    # a numpy scalar
        value = value.item()
    if isinstance(value, dict):
        return "{" + ", ".join(f"{plain(k)}: {plain(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        inner = ", ".join(plain(v) for v in value)
        return f"({inner}{',' if len(value) == 1 else ''})" if isinstance(value, tuple) \
            else f"[{inner}]"
    if isinstance(value, float):
        return f"{value:.6g}"
    return repr(value)


class BackendFallbackWarning(PdbfsWarning):
    """The compiled backend could not be built for a rig (no C compiler, no
    SUNDIALS, ...): the run uses CasADi instead; the message says why."""

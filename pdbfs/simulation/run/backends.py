"""Which back end runs a run whose method needs CVODE, when "auto" chose the
compiled one: without CVODE's sources within reach (no network, no
prepared cache) the compiled library holds the explicit method alone, and
such a run falls back to CasADi, with one short warning line; a fetch of the
sources that failed minutes ago is not waited for again (sundials.py)."""
from __future__ import annotations

import warnings

from pdbfs.errors import BackendFallbackWarning, ParameterError, PdbfsError

from .compiled import CVODE_METHODS


def backend_for_method(sim, asked: str, backend: str, method: str) -> str:
    """The back end of a run of ``sim`` (a Simulator) with ``method``:
    ``backend`` as resolved, but for ``asked`` "auto" and a CVODE method whose
    library cannot be had, "casadi", with a BackendFallbackWarning (decided
    once per DAE; an explicit backend="c" gets the error instead)."""
    if asked != "auto" or backend != "c" or method not in CVODE_METHODS:
        return backend
    from pdbfs.native.sundials import SundialsNotFound, remembered_failures
    chosen = sim._cache.get("cvode backend")
    if chosen is None:
        chosen = "c"
        try:
            with remembered_failures():       # a dead index is waited for once, not each run
                sim.compiled(method)
        except ParameterError:
            raise
        except PdbfsError as err:
            cause = err.__cause__
            if isinstance(cause, SundialsNotFound) and cause.short:
                why = f"CVODE unavailable ({cause.short}): simulating with CasADi; " \
                    "run `pdbfs prepare-offline`"
            else:
                first = str(err).splitlines()[0] if str(err) else type(err).__name__
                why = f"the compiled backend has no CVODE for method {method!r} ({first}); " \
                    "simulating with CasADi"
            warnings.warn(f"rig {sim.dae.name}: {why}",
                          BackendFallbackWarning, stacklevel=4)
            chosen = "casadi"
        sim._cache["cvode backend"] = chosen
    return chosen

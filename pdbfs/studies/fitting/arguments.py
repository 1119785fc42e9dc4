"""The arguments of the fitting entry points (calibrate, design), checked for
type before anything is built: each wrong one is a ParameterError naming it."""
from __future__ import annotations

from pdbfs.errors import ParameterError, plain
from pdbfs.simulation.setup.settings import check_t_end, mapping, real, whole


def check_fit_arguments(*, free, bounds, start, params, starts, t_end, seed=0, signal=None):
    """free, bounds, start, params, starts, t_end, seed and signal, as their
    docstrings say; returns (start, params) as dicts."""
    if isinstance(free, str) or (isinstance(free, (list, tuple))
                                 and all(isinstance(f, str) for f in free)):
        pass
    else:
        raise ParameterError(f"free = {free!r}: name the free parameters as a list of names "
                             "or one comma-separated string, e.g. free='oil.k,seal.c'")
    if bounds is not None and not isinstance(bounds, (dict, str)) and not (
            isinstance(bounds, (list, tuple)) and all(isinstance(b, str) for b in bounds)):
        raise ParameterError(f"bounds = {bounds!r}: give a dict {{name: (lo, hi)}} or "
                             "'NAME=LO:HI' strings")
    if isinstance(bounds, dict):
        for k, v in bounds.items():
            if not (isinstance(v, (list, tuple)) and len(v) == 2):
                raise ParameterError(f"bounds of {k} = {plain(v)}: give a pair (lo, hi)")
            for x in v:
                real(x, f"bounds of {k}")
    if whole(starts, "starts") < 1:
        raise ParameterError(f"starts = {starts}: need at least 1")
    whole(seed, "seed")
    if t_end is not None:
        check_t_end(t_end)
    if signal is not None and not isinstance(signal, str):
        raise ParameterError(f"signal = {signal!r}: name a rig variable, e.g. 'oil.pressure'")
    return mapping(start, "start"), mapping(params, "params", "'seal.c': 25560.0")

"""The settings of a run, checked before anything is integrated: tolerances,
method, back end, step limits, and the output grid."""
from __future__ import annotations

import numpy as np

from pdbfs.errors import ParameterError

#: "erk": the explicit Runge-Kutta method of order 8 (compiled backend only)
METHODS = ("auto", "adams", "bdf", "erk")
#: "auto" (the default): "c" where the compiled backend can be built, else "casadi"
BACKENDS = ("auto", "casadi", "c")
MAX_NUM_STEPS = 500000
#: relative tolerance when none is given, per method: the explicit method's
#: long steps put the peak pressure (a small difference of two displacements)
#: within 1e-7 of a tight reference only from 1e-9 on (paper rig, v0 1.5-5.5
#: m/s, oil.k 1e8-5e8 Pa/m: at 1e-8 some step sequences missed it by 2e-7)
DEFAULT_RTOL = {"erk": 1e-9}
RTOL = 1e-8


def default_rtol(method: str, rtol=None) -> float:
    """``rtol``, or the default of ``method`` when it is None."""
    return float(rtol) if rtol is not None else DEFAULT_RTOL.get(method, RTOL)


def check_settings(rtol, atol, method, max_step, max_num_steps=MAX_NUM_STEPS,
                   backend="auto"):
    if backend not in BACKENDS:
        raise ParameterError(f"unknown backend {backend!r}; choose one of "
                             f"{', '.join(BACKENDS)}")
    if method not in METHODS:
        raise ParameterError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
    if method == "erk" and backend == "casadi":
        raise ParameterError("method='erk' (explicit Runge-Kutta) runs in the compiled backend "
                             "only: use backend='c' or 'auto', or method 'adams'/'bdf'")
    for name, v in (("rtol", rtol), ("atol", atol)):
        if not (np.isfinite(v) and v > 0):
            raise ParameterError(f"{name} = {v}: must be a positive number")
    if max_step is not None and not (np.isfinite(max_step) and max_step > 0):
        raise ParameterError(f"max_step = {max_step}: must be a positive number")
    if isinstance(max_num_steps, bool) or not isinstance(max_num_steps, (int, np.integer)) \
            or not 1 <= max_num_steps < 2 ** 62:
        raise ParameterError(f"max_num_steps = {max_num_steps!r}: must be a whole number >= 1")


def output_grid(t_end, n_out, t_out=None) -> np.ndarray:
    if t_out is None:
        if not (np.isfinite(t_end) and t_end > 0):
            raise ParameterError(f"t_end = {t_end}: must be a positive time in s")
        if int(n_out) < 2:
            raise ParameterError(f"n_out = {n_out}: need at least 2 output points")
        return np.linspace(0.0, float(t_end), int(n_out))
    g = np.asarray(t_out, dtype=float).ravel()
    if g.size < 2 or g[0] != 0.0 or not np.all(np.diff(g) > 0) or not np.all(np.isfinite(g)):
        raise ParameterError("t_out must start at 0 and increase strictly, with 2+ points")
    return g

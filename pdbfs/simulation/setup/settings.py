"""The settings of a run, checked before anything is integrated: tolerances,
method, back end, step limits, and the output grid."""
from __future__ import annotations

import numbers

import numpy as np

from pdbfs.errors import ParameterError, plain
from pdbfs.native.tolerances import (ATOL_DEFAULT, RTOL_MAX, RTOL_MIN, check_rtol,  # noqa: F401
                                     default_atol)

#: "erk": the explicit Runge-Kutta method of order 8 (compiled backend only)
METHODS = ("auto", "adams", "bdf", "erk")
#: "auto" (the default): "c" where the compiled backend can be built, else "casadi"
BACKENDS = ("auto", "casadi", "c")
MAX_NUM_STEPS = 500000
#: relative tolerance when none is given, per method: the explicit method's
#: peak pressure on the paper rig is within 1.1e-8 of a tight reference at
#: 5e-8 (the paper's 8 cases; 3.2e-8 over 300 sweep points, hammer.v0
#: 1.5-5.5 m/s x oil.k 1e8-5e8 Pa/m; tests/test_erk_default.py): 9x inside
#: the 1e-7 asked, where 1e-7 left 2x
DEFAULT_RTOL = {"erk": 5e-8}
RTOL = 1e-8
#: the smallest absolute tolerance, in each state's unit: RTOL_MIN of a state of 1e-15,
#: finer than double precision resolves on any state of physical size; far below it the
#: error test's weights (1 / atol) overflow (atol 1e-300 failed every method at t = 0)
ATOL_MIN = 1e-30
#: the finest time a run resolves, s, near its end (double precision's relative
#: resolution of t_end): the longest run, T_END_MAX, is about 140 years
TIME_RESOLUTION = 1e-6
T_END_MAX = TIME_RESOLUTION / float(np.finfo(float).eps)
#: the closest output points (and the shortest run), s: CasADi's integrators do not
#: integrate between output times closer than 1e-9 s (they copy the state over),
#: and a nanosecond is shorter than anything a rig does
MIN_SPACING = 1e-9


def default_rtol(method: str, rtol=None) -> float:
    """``rtol`` as given (check_settings refuses what is not a number), or the
    default of ``method`` when it is None."""
    if rtol is not None:
        return rtol
    return DEFAULT_RTOL.get(method, RTOL) if isinstance(method, str) else RTOL


def real(value, name: str) -> float:
    """``value`` as a float if it is a real number (not a bool, a string or a
    list: those are mistakes, refused naming ``name``)."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ParameterError(f"{name} = {plain(value)}: must be a number, not {type(value).__name__}")
    return float(value)


def whole(value, name: str) -> int:
    """``value`` as an int if it is a whole number (not a bool), else a ParameterError naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise ParameterError(f"{name} = {plain(value)}: must be a whole number, not "
                             f"{type(value).__name__}")
    return int(value)


def name_list(value, name: str, example: str = "'oil.pressure'", distinct: bool = True
              ) -> list[str]:
    """``value`` as a list of variable or parameter names: one name as a str
    (never read letter by letter), or a list, tuple or array of str. With
    ``distinct``, a name listed twice is refused (two columns of one
    parameter are no two inputs: a derivative would be split between them).

    Parameters
    ----------
    value : str or sequence of str
        What the caller gave.
    name : str
        The argument's name, for the message (``inputs``, ``outputs``, ...).
    example : str
        A name shown in the message of a refusal.
    distinct : bool
        Refuse a name listed twice (the columns or rows of a linearization);
        names to show or export may repeat.
    """
    if isinstance(value, str):
        return [value]
    if isinstance(value, np.ndarray) and value.ndim == 1:
        value = value.tolist()
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
        raise ParameterError(f"{name} = {plain(value)}: give a name or a list of names, e.g. "
                             f"{name}=[{example}]")
    seen = set()
    for v in value if distinct else ():
        if v in seen:
            raise ParameterError(f"{name}: {v!r} is listed twice")
        seen.add(v)
    return list(value)


def mapping(value, name: str, example: str = "'hammer.v0': 3.0") -> dict:
    """``value`` as a dict {name: value} (None: empty); anything else is refused."""
    from collections.abc import Mapping
    if value is None:
        return {}
    if type(value) is not dict and not isinstance(value, Mapping):
        raise ParameterError(f"{name} must be a dict {{name: value}}, e.g. {name}={{{example}}}; "
                             f"got a {type(value).__name__}")
    for k in value:
        if not isinstance(k, str):
            raise ParameterError(f"{name}: the key {k!r} is not a name (a str such as "
                                 f"{example.split(':')[0]})")
    return dict(value)


def check_settings(rtol, atol, method, max_step, max_num_steps=MAX_NUM_STEPS,
                   backend="auto"):
    """Refuse, with a ParameterError naming it, a setting that is not valid."""
    if backend not in BACKENDS:
        raise ParameterError(f"unknown backend {backend!r}; choose one of "
                             f"{', '.join(BACKENDS)}")
    if method not in METHODS:
        raise ParameterError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
    if method == "erk" and backend == "casadi":
        raise ParameterError("method='erk' (explicit Runge-Kutta) runs in the compiled backend "
                             "only: use backend='c' or 'auto', or method 'adams'/'bdf'")
    if rtol is not None:                 # None: the method's default (default_rtol)
        check_rtol(real(rtol, "rtol"))   # the one rule of every path, the FMU's included
    if atol is not None:                 # None: default_atol of the run's rtol
        atol = real(atol, "atol")
        if not (np.isfinite(atol) and atol > 0):
            raise ParameterError(f"atol = {atol}: must be a positive number (the absolute "
                                 "tolerance, in each state's unit)")
        if atol < ATOL_MIN:
            raise ParameterError(f"atol = {atol:g}: below {ATOL_MIN:g}, finer than double "
                                 "precision resolves on a state of any physical size (it is in "
                                 "each state's unit); give at least that")
    if max_step is not None and not (np.isfinite(real(max_step, "max_step")) and max_step > 0):
        raise ParameterError(f"max_step = {max_step}: must be a positive number")
    if max_step is not None and max_step < MIN_SPACING:
        raise ParameterError(f"max_step = {max_step:g}: below {MIN_SPACING:g} s, shorter than "
                             "anything a rig does; give a longer step limit")
    if isinstance(max_num_steps, bool) or not isinstance(max_num_steps, (int, np.integer)) \
            or not 1 <= max_num_steps < 2 ** 62:
        raise ParameterError(f"max_num_steps = {plain(max_num_steps)}: must be a whole number >= 1")


def check_atol_scale(dae, x0, atol) -> None:
    """Refuse an absolute tolerance ``atol`` (given, in each state's unit)
    that is not below the scale of the rig's states, their largest start
    value: every answer would pass the error test (atol 1e10 gave the paper
    rig a restitution of 1.25). A rig starting at rest has no scale to
    compare with: its atol is taken as given."""
    x = np.abs(np.asarray(x0, float))
    if atol is None or not x.size or not x.max() > 0 or atol < x.max():
        return
    k = int(np.argmax(x))
    info = dae.x_info[k] if k < len(dae.x_info) else None
    name = info.name if info else dae.x_names[k]
    unit = f" {info.unit}" if info and info.unit not in ("", "1") else ""
    raise ParameterError(f"atol = {atol:g} is not below the scale of rig {dae.name}'s states "
                         f"(its largest start value, {name} = {x[k]:g}{unit}): every answer "
                         f"would pass the error test; give an atol well below it, or none "
                         f"(the default, {ATOL_DEFAULT:g})")


def output_grid(t_end, n_out, t_out=None) -> np.ndarray:
    """The output times: ``t_out`` checked (increasing from 0), else n_out
    points on [0, t_end]; a run longer than T_END_MAX or points closer than
    MIN_SPACING are refused."""
    if t_out is None:
        check_t_end(t_end)
        if whole(n_out, "n_out") < 2:
            raise ParameterError(f"n_out = {n_out}: need at least 2 output points")
        spacing = float(t_end) / (int(n_out) - 1)
        if spacing < MIN_SPACING:
            raise ParameterError(f"t_end = {t_end:g} s with n_out = {n_out}: output points "
                                 f"{spacing:.2g} s apart, closer than {MIN_SPACING:g} s (the "
                                 "integrators' resolution); give a longer horizon or fewer points")
        return np.linspace(0.0, float(t_end), int(n_out))
    try:
        g = np.asarray(t_out, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"t_out: must be a list or array of times in s, not "
                             f"{type(t_out).__name__}") from None
    if g.ndim != 1:
        raise ParameterError(f"t_out: must be one row of times, not an array of shape {g.shape}")
    if g.size < 2 or g[0] != 0.0 or not np.all(np.diff(g) > 0) or not np.all(np.isfinite(g)):
        raise ParameterError("t_out must start at 0 and increase strictly, with 2+ points")
    if g[-1] > T_END_MAX:
        raise ParameterError(f"t_out ends at {g[-1]:g} s, {_too_long}")
    k = int(np.argmin(np.diff(g)))
    if g[k + 1] - g[k] < MIN_SPACING:
        raise ParameterError(f"t_out: {g[k]:.17g} and {g[k + 1]:.17g} s are {g[k + 1] - g[k]:.2g} s "
                             f"apart, closer than {MIN_SPACING:g} s (the integrators' resolution)")
    return g


def check_t_end(t_end, name: str = "t_end") -> float:
    """``t_end`` as a float: a time in s from MIN_SPACING to T_END_MAX, else a
    ParameterError naming ``name``.

    Parameters
    ----------
    t_end : float
        A run's horizon, s.
    name : str
        The argument's name, for the message.

    Returns
    -------
    float
        ``t_end``.
    """
    t = real(t_end, name)
    if not (np.isfinite(t) and t > 0):
        raise ParameterError(f"{name} = {t_end}: must be a positive time in s")
    if t < MIN_SPACING:
        raise ParameterError(f"{name} = {t:g} s: shorter than {MIN_SPACING:g} s (the "
                             "integrators' resolution)")
    if t > T_END_MAX:
        raise ParameterError(f"{name} = {t:g} s: {_too_long}")
    return t


_too_long = (f"longer than {T_END_MAX:.2g} s (about {T_END_MAX / 3.156e7:.0f} years), beyond "
             f"which double precision resolves times more coarsely than {TIME_RESOLUTION:g} s")

"""The simplified rig as one CasADi DAE, what every back end consumes (DAE
says its parts), and the records of its parameters, inputs and variables."""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np


@dataclass(frozen=True)
class ParamInfo:
    """One free parameter of the rig (an entry of ``p``; ``rig.parameters()`` lists them).

    Attributes
    ----------
    name, unit, description : str
        Its dotted name in the rig (``"hammer.m"``), SI unit ("1": none), meaning.
    value : float
        Its default value, SI units.
    min, max : float or None
        Inclusive bounds (None: unbounded).
    positive : bool
        Whether it must be strictly greater than zero.
    tunable : bool
        Whether a change during a run means something (False: fixed in the FMU).
    """

    name: str            # dotted name, e.g. "hammer.m"
    value: float         # default value
    unit: str            # SI unit, e.g. "kg", "N/m^1.5", "1" for none
    description: str
    min: float | None = None       # inclusive lower bound, None if unbounded
    max: float | None = None       # inclusive upper bound
    positive: bool = False         # value must be > 0 (strictly)
    tunable: bool = True           # meaningful to change during a run


@dataclass(frozen=True)
class InputInfo:
    """One input of the rig (its value and slope are entries of ``p``)."""

    name: str            # the component's dotted path, e.g. "command"
    unit: str
    description: str
    start: float = 0.0   # its value where none is given


@dataclass(frozen=True)
class VarInfo:
    """One named variable of a compiled rig (an entry of ``y``, a state or an algebraic).

    Attributes
    ----------
    name, unit, description : str
        Its dotted name in the rig (``"oil.pressure"``), SI unit, meaning.
    output : bool
        Whether it is offered as an FMU output and shown in summaries.
    min, max : float or None
        The values its equations describe: a run leaving them stops (SolverError).
    beyond : str
        What leaving them means, said in that error.
    """

    name: str
    unit: str
    description: str
    output: bool = False   # offered as an FMU output / shown in summaries
    # the values the equations describe (Variable's min, max): a run leaving them stops
    min: float | None = None
    max: float | None = None
    beyond: str = ""       # what leaving them means, for the run's error
    # a signal input's (min, max, nominal): the range its component clamps it to, its magnitude
    span: tuple = (None, None, None)


@dataclass
class DAE:
    """A rig compiled: one semi-explicit CasADi DAE in SX, with the names,
    units and descriptions of its states, algebraic variables, parameters
    and outputs. ``rig.compile()`` makes it; every back end (simulation, FMU
    export, the studies) reads it:

        der(x) = ode(t, x, z, p)        x: states
             0 = alg(t, x, z, p)        z: algebraic variables left after BLT
             y = out(t, x, z, p)        every named variable of the rig
            x0 = start(p)               start values may depend on parameters
             e = events(t, x, z, p)     event indicators (contact onset, slack oil)
            te = time_events(p)         switch times: the first len(te) events are t - te

    Parameters stay symbolic: changing one never rebuilds anything. A rig with
    n_u inputs has 2 n_u + 1 more entries at the end of ``p``: each input's value
    at t_ref, its slope, t_ref (their rows: ``input_rows()``); ``params`` and
    ``p_names`` list the parameters only.

    Attributes
    ----------
    name : str
        The rig's name (the FMU's model name).
    t, x, z, p : casadi.SX
        Time, the states, the algebraic variables (empty for an ODE rig) and
        the free parameters, as column vectors of symbols.
    ode, alg, x0, y, events : casadi.SX
        The expressions above.
    x_info, z_info, y_info : list of VarInfo
        Name, unit and description of each state, algebraic variable, output.
    params : list of ParamInfo
        The free parameters, in ``p``'s order.
    event_names : list of str
        The event indicators (what each sign change marks: ``event_text``).
    calculated : dict
        Parameters computed from others: name -> (expression of ``p``, VarInfo).
    description : str
        What the rig is (the first sentence of its class's description).
    time_events : casadi.SX
        Switch times, functions of ``p``: every integrator stops there.
    inputs : list
        The rig's inputs (name, unit, description, start value).
    """

    name: str
    t: ca.SX
    x: ca.SX                 # column, states
    z: ca.SX                 # column, algebraic variables (empty for ODE rigs)
    p: ca.SX                 # column, free parameters
    ode: ca.SX               # der(x)
    alg: ca.SX               # residuals, 0 = alg
    x0: ca.SX                # start values, function of p only
    y: ca.SX                 # outputs, every named variable
    events: ca.SX            # event indicators; sign changes mark non-smooth points
    x_info: list[VarInfo]
    z_info: list[VarInfo]
    params: list[ParamInfo]
    y_info: list[VarInfo]
    event_names: list[str]
    # parameters computed from others (FMI calculatedParameter): name -> expr(p)
    calculated: dict[str, tuple[ca.SX, VarInfo]] = field(default_factory=dict)
    # initial guess of z for IDAS (declared start values, else 0), function of p
    z0: ca.SX | None = None
    # event name -> what its sign change marks (from the component)
    event_text: dict[str, str] = field(default_factory=dict)
    # what the rig is (the first sentence of its class docstring)
    description: str = ""
    # initialization (initialization.py): which starts are fixed, and the
    # initial equations in (t, x, z, p) with where each comes from
    x_fixed: list[bool] | None = None
    init: ca.SX | None = None
    init_names: list[str] = field(default_factory=list)
    # switch times (valves, prescribed motions), functions of p: every
    # integrator stops and restarts at each (events[:n] are t - time_events)
    time_events: ca.SX = field(default_factory=lambda: ca.SX(0, 1))

    # physical consistency: (expression of p that must be >= 0, (where, text, names))
    conditions: list = field(default_factory=list)
    # the rig's inputs: their values, slopes and t_ref end p (input_rows())
    inputs: list[InputInfo] = field(default_factory=list)

    def _conditions_function(self):
        conds = getattr(self, "conditions", None) or []
        if not conds:
            return None
        f = self.__dict__.setdefault("_functions", {}).get("conditions")
        if f is None:
            f = self.__dict__["_functions"]["conditions"] = ca.Function(
                "conditions", [self.p], [ca.vertcat(*[e for e, _ in conds])])
        return f

    def conditions_hold(self, P: np.ndarray) -> np.ndarray:
        """Whether the components' physical conditions hold, for many points at once.

        Parameters
        ----------
        P : numpy.ndarray
            Parameter vectors, one per row (points x len(p)).

        Returns
        -------
        numpy.ndarray
            One bool per row; ``check_conditions`` names what fails.
        """
        P = np.atleast_2d(np.asarray(P, float))
        f = self._conditions_function()
        if f is None or P.shape[0] == 0:
            return np.ones(P.shape[0], dtype=bool)
        v = np.array(f.map(P.shape[0])(P.T), float).reshape(-1, P.shape[0])
        return np.all(v >= 0, axis=0)

    def check_conditions(self, p: np.ndarray) -> None:
        """Refuse parameters that contradict each other physically (each
        component's ``conditions()``).

        Parameters
        ----------
        p : numpy.ndarray
            One parameter vector (len(p)).

        Raises
        ------
        pdbfs.ParameterError
            Naming the first condition that fails, its parameters and values.
        """
        f = self._conditions_function()
        if f is None:
            return
        conds = self.conditions
        p = np.asarray(p, float)
        for (_, (where, text, names)), v in zip(conds, np.array(f(p), float).ravel()):
            if not v >= 0:
                from pdbfs.errors import ParameterError
                units = {q.name: q.unit for q in self.params}
                from .symbols import quantity
                values = ", ".join(f"{n} = {quantity(self._value_of(n, p), units.get(n, ''))}"
                                   for n in names)
                raise ParameterError(f"{where}: {text} ({values})" if values else
                                     f"{where}: {text}")

    def _value_of(self, name, p) -> float:
        if name in self.p_names:
            return float(p[self.p_names.index(name)])
        if name not in self.calculated:
            return float("nan")
        return float(ca.Function("v", [self.p], [self.calculated[name][0]])(p))

    def time_event_times(self, p: np.ndarray) -> np.ndarray:
        """The switch times of a run at one parameter vector.

        Parameters
        ----------
        p : numpy.ndarray
            One parameter vector (len(p)).

        Returns
        -------
        numpy.ndarray
            The time events, s, sorted (non-finite ones left out).
        """
        n = self.time_events.numel()
        if not n:
            return np.zeros(0)
        f = self.__dict__.setdefault("_functions", {}).get("time_events")
        if f is None:
            f = self.__dict__["_functions"]["time_events"] = ca.Function(
                "time_events", [self.p], [self.time_events])
        v = np.array(f(np.asarray(p, float)), dtype=float).ravel()
        return np.sort(v[np.isfinite(v)])

    def cached(self, name: str, make: Callable[[], Any]) -> Any:
        """A CasADi object made of this DAE (a function, a rootfinder) on the
        first request, kept with its own functions (``function``), never pickled.

        Parameters
        ----------
        name : str
            The key it is kept under.
        make : callable
            Makes it (called with no arguments, the first time only).

        Returns
        -------
        object
            What ``make()`` returned.
        """
        cache = self.__dict__.setdefault("_functions", {})
        f = cache.get(name)
        if f is None:
            f = cache.setdefault(name, make())
        return f

    def __post_init__(self):
        #: what the layers above keep of this DAE, each under its own class as the
        #: key (pdbfs.simulation's RigState: its Simulator, compiled library, ...;
        #: the rig's output checks): made by them when first needed, it lives as
        #: long as the DAE. A rig that changes compiles a new DAE, which starts
        #: with none: what was made of the old one goes with it. Never pickled;
        #: the DAE never looks inside.
        self.companions = {}

    def __getstate__(self):
        """Pickle the model, not its caches (functions, integrators, compiled
        libraries are rebuilt where it is unpickled; needs CasADi's pickle
        context for the symbols)."""
        return {k: v for k, v in self.__dict__.items()
                if not k.startswith("_") and k != "companions"}

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.companions = {}

    # -- names ---------------------------------------------------------------
    @property
    def x_names(self) -> list[str]:
        """The states' names, in the DAE's order."""
        return [v.name for v in self.x_info]

    @property
    def z_names(self) -> list[str]:
        """The algebraic variables' names (none for an ODE rig)."""
        return [v.name for v in self.z_info]

    @property
    def p_names(self) -> list[str]:
        """The free parameters' names, in the DAE's order."""
        return [p.name for p in self.params]

    @property
    def y_names(self) -> list[str]:
        """The names of every variable a Result holds (the outputs), in the DAE's order."""
        return [v.name for v in self.y_info]

    @property
    def is_ode(self) -> bool:
        """True when no algebraic variable is left (CVODES, or the compiled backend, can run it)."""
        return self.z.numel() == 0

    @property
    def input_names(self) -> list[str]:
        """The rig's inputs' names (its Input components' paths), in p's order."""
        return [u.name for u in self.__dict__.get("inputs", ())]

    def input_rows(self) -> tuple[int, int, int] | None:
        """(the row of the first input's value in p, of its slope, of t_ref);
        None for a rig without inputs."""
        n, m = len(self.params), len(self.__dict__.get("inputs", ()))
        return (n, n + m, n + 2 * m) if m else None

    def p_row(self, name: str) -> int | None:
        """The row in ``p`` of a parameter, or of an input's value.

        Parameters
        ----------
        name : str
            A parameter's dotted name, or an input's name.

        Returns
        -------
        int or None
            The row, or None if the rig has no such parameter or input.
        """
        names = self.p_names
        if name in names:
            return names.index(name)
        if name in self.input_names:
            return len(names) + self.input_names.index(name)
        return None

    def p_default(self) -> np.ndarray:
        """The parameters' defaults, then (a rig with inputs) each input held
        at its start: values, slopes 0, t_ref 0."""
        inputs = self.__dict__.get("inputs", ())
        values = [p.value for p in self.params]
        if inputs:
            values += [u.start for u in inputs] + [0.0] * (len(inputs) + 1)
        return np.array(values, dtype=float)

    @property
    def limits(self) -> list[tuple[VarInfo, str, float]]:
        """The ranges the rig's variables are declared valid in (Variable's
        ``min``, ``max``): (the variable, "min" or "max", the bound), in the
        order of :meth:`limits_expr`."""
        return [(v, k, b) for v in self.y_info
                for k, b in (("min", getattr(v, "min", None)), ("max", getattr(v, "max", None)))
                if b is not None]

    def limits_expr(self) -> ca.SX:
        """Each of :attr:`limits` as an expression of (t, x, z, p), >= 0
        inside it."""
        at = {n: i for i, n in enumerate(self.y_names)}
        return ca.vertcat(*[self.y[at[v.name]] - b if k == "min" else b - self.y[at[v.name]]
                            for v, k, b in self.limits]) if self.limits else ca.SX(0, 1)

    # -- CasADi functions (cheap to build, cached) ----------------------------
    def function(self, which: str) -> ca.Function:
        """One of the DAE's expressions as a CasADi Function (built once, kept).

        Parameters
        ----------
        which : str
            "ode", "alg", "out", "events", "limits" (of t, x, z, p) or "start" (of p).

        Returns
        -------
        casadi.Function
            The function (its inputs and output named).
        """
        cache = self.__dict__.setdefault("_functions", {})
        if which not in cache:
            args = [self.t, self.x, self.z, self.p]
            names = ["t", "x", "z", "p"]
            if which == "start":
                f = ca.Function("start", [self.p], [self.x0], ["p"], ["x0"])
            else:
                expr = self.limits_expr() if which == "limits" else \
                    {"ode": self.ode, "alg": self.alg, "out": self.y, "events": self.events}[which]
                f = ca.Function(which, args, [expr], names, [which])
            cache[which] = f
        return cache[which]

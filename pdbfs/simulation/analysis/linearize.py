"""Linearization and modes: the rig's DAE differentiated (CasADi, exact) at an
operating point, with the algebraic variables eliminated:

    der(dx) = A dx + B du,   dy = C dx + D du
    A = f_x - f_z g_z^-1 g_x   (and alike for B, C, D)

for a semi-explicit DAE der(x) = f(t, x, z, p), 0 = g(t, x, z, p),
y = h(t, x, z, p); the inputs u are the rig's inputs (held at their start
values) or parameters, chosen by name. The
operating point is the start (``at="start"``), the state at rest
(``"steady"``, solved as in initialize.py) or the state of a run at a time
(``at=0.004``). Modes are A's eigenvalues: omega = |lambda| (rad/s),
damping ratio -Re(lambda)/|lambda|, shape the eigenvector by state name.
A one-sided law exactly at its kink there (the paper rig's oil column at
its start) is linearized on one side: ``Linearization.kinks`` names it and
the side (kinks.py).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np

from pdbfs.errors import ParameterError, require_extra

from ..setup.input_traces import refuse_differentiated
from .kinks import input_sides, kinks_at
from ..setup.settings import MIN_SPACING, name_list

if TYPE_CHECKING:
    import control

    from pdbfs.modelling import DAE, Component


@dataclass
class Linearization:
    """The state-space matrices at one operating point, with their names:
    ``der(dx) = A dx + B du``, ``dy = C dx + D du`` for small changes about
    the point. Made by ``Rig.linearize`` (``pdbfs.simulation.linearize``).

    Attributes
    ----------
    A, B, C, D : numpy.ndarray
        The matrices, SI units (rows and columns named by the lists below).
    states : list of str
        The states: the rows and columns of A, the columns of C.
    inputs : list of str
        The inputs and parameters linearized for: the columns of B and D.
    outputs : list of str
        The variables: the rows of C and D.
    t : float
        The time of the operating point, s.
    point : dict
        The operating point: state name -> value.
    units : dict
        State name -> unit.
    kinks : list
        The one-sided laws (contacts, oil columns) exactly at their kink at
        the point, each with the side it is linearized on.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: list
    inputs: list
    outputs: list
    t: float = 0.0
    point: dict = field(default_factory=dict)     # the operating point, state -> value
    units: dict = field(default_factory=dict)     # state -> unit
    #: the one-sided laws (contacts, oil columns) exactly at their kink at the
    #: point, each with the side it is linearized on (kinks.Kink)
    kinks: list = field(default_factory=list)

    def __str__(self) -> str:
        lines = [f"Linearization of {len(self.states)} states at t = {self.t:g} s"
                 f" ({len(self.inputs)} inputs, {len(self.outputs)} outputs)"]
        if self.kinks:
            lines.append("one-sided laws exactly at their kink here:")
            lines += [f"  {k}" for k in self.kinks]
        return "\n".join(lines)

    def to_control(self) -> control.StateSpace:
        """A python-control StateSpace (pdbfs's extra ``[control]``:
        ``pip install "pdbfs[control]"``); its signal names have '_' for '.',
        which python-control refuses.

        Raises
        ------
        pdbfs.errors.MissingExtraError
            python-control is not installed (the message names the extra).
        """
        require_extra("control", "Linearization.to_control()")
        import control
        safe = lambda names: [n.replace(".", "_") for n in names]   # noqa: E731 ('.' refused)
        return control.ss(self.A, self.B, self.C, self.D, states=safe(self.states),
                          inputs=safe(self.inputs), outputs=safe(self.outputs))

    def modes(self) -> list:
        """The modes of A, slowest first.

        Returns
        -------
        list of Mode
            One per eigenvalue (one per complex pair): ``omega`` (rad/s),
            ``frequency`` (Hz), ``damping`` (ratio; None for a zero
            eigenvalue), ``shape`` (state -> amplitude, the largest of each
            unit 1) and ``eigenvalue`` (1/s).
        """
        return modes_of(self.A, self.states, self.units)


@dataclass
class Mode:
    """One mode of a linearized rig: an eigenvalue of A (one per complex pair)."""

    omega: float          # rad/s, |lambda| (the undamped natural frequency of a pair)
    frequency: float      # Hz, omega / (2 pi)
    damping: float | None  # ratio, -Re(lambda)/|lambda|; None for lambda = 0
    shape: dict           # state -> amplitude (largest of each unit 1, signs against it)
    eigenvalue: complex

    def to_dict(self) -> dict:
        """The mode as plain JSON-ready data (the eigenvalue as [re, im])."""
        return {"omega": self.omega, "frequency": self.frequency, "damping": self.damping,
                "eigenvalue": [self.eigenvalue.real, self.eigenvalue.imag],
                "shape": dict(self.shape)}


def modes_frame(modes):
    """Modes as a pandas DataFrame: omega, frequency, damping, shape."""
    import pandas as pd
    return pd.DataFrame({"omega": [m.omega for m in modes],
                         "frequency": [m.frequency for m in modes],
                         "damping": [np.nan if m.damping is None else m.damping for m in modes],
                         "shape": [m.shape for m in modes],
                         "eigenvalue": [m.eigenvalue for m in modes]})


def modes_of(A, states, units=None) -> list:
    """The Modes of the state matrix ``A`` (states named ``states``), slowest first."""
    if A.size == 0:
        return []
    lam, V = np.linalg.eig(A)
    units = units or {}
    out = []
    tiny = 1e-12 * max(1.0, np.max(np.abs(lam)))
    for k in np.argsort(np.abs(lam), kind="stable"):
        lk = lam[k]
        if lk.imag < -tiny:          # one row per complex pair
            continue
        omega = float(abs(lk))
        damping = None if omega <= tiny else float(-lk.real / omega) + 0.0   # never -0
        # a zero eigenvalue (a body free to drift) is defective: its vector is
        # only good to about sqrt(eps), so units below 1e-4 of it are noise
        out.append(Mode(omega, omega / (2 * np.pi), damping,
                        _shape(V[:, k], states, units, 1e-4 if damping is None else 1e-13),
                        complex(lk)))
    return out


def _shape(v, states, units, floor=1e-13):
    """Amplitudes by state, normalised within each unit (positions against
    positions, velocities against velocities, pressures against pressures:
    their sizes are not comparable), the largest of each unit +1 and the
    signs relative to it; a unit that takes no part (below ``floor`` times
    the largest entry) is 0."""
    mag = np.abs(v)
    top = mag.max() if mag.max() > 0 else 1.0
    ref = {}
    for i, n in enumerate(states):
        u = units.get(n, "")
        if u not in ref or mag[i] > mag[ref[u]]:
            ref[u] = i
    out = {}
    for i, n in enumerate(states):
        r = ref[units.get(n, "")]
        if mag[r] <= floor * top or mag[i] <= 1e-13 * mag[r]:
            out[n] = 0.0
            continue
        sign = -1.0 if (v[i] * np.conj(v[r])).real < 0 else 1.0
        out[n] = float(sign * mag[i] / mag[r])
    return out


def linearize(model: Component | DAE, at: str | float = "start",
              inputs: str | Sequence[str] | None = None, outputs: str | Sequence[str] | None = None,
              params: Mapping[str, float] | None = None, start: Mapping[str, float] | None = None,
              initial: str | Sequence[str] | None = None, rtol: float = 1e-10,
              atol: float = 1e-12) -> Linearization:
    """State-space matrices of a rig at ``at`` ("start", "steady" or a time
    in s of a run from the start, the rig's inputs held at their start
    values).

    Parameters
    ----------
    model : Component or DAE
        The rig.
    at : str or float
        "start", "steady" or a time in s.
    inputs : str or sequence of str, optional
        The columns of B and D: names of the rig's inputs and of its
        parameters, each once. A one-sided law exactly at its kink in one
        of them (a valve commanded to its closed stop) is taken on the side
        where the input acts and listed in ``Linearization.kinks``; where
        both sides act differently the linearization is refused.
    outputs : str or sequence of str, optional
        The rows of C and D, variable names, each once (default: the rig's
        outputs).
    params, start, initial
        As in simulate().
    rtol, atol : float
        The tolerances of the run to a time ``at``.

    Returns
    -------
    Linearization

    Raises
    ------
    ParameterError
        An unknown or repeated name, an input the rig differentiates, a
        kink in an input whose sides differ, a singular or non-finite
        result.
    """
    from ..run.simulator import Simulator
    sim = Simulator.of(model)
    dae = sim.dae
    if isinstance(at, (bool, np.bool_)):       # True is no time (float(True) is 1 s)
        raise ParameterError(f"at={at!r}: give 'start', 'steady' or a time in s")
    inputs = name_list(inputs, "inputs", "'oil.k'") if inputs is not None else []
    outputs = name_list(outputs, "outputs") if outputs is not None else \
        [v.name for v in dae.y_info if v.output]
    for n in inputs:
        if dae.p_row(n) is None:
            raise ParameterError(f"linearize: input {n!r} is not a parameter of rig {dae.name} "
                                 "nor one of its inputs; `pdbfs params` lists them")
    refuse_differentiated(dae, inputs)
    for n in outputs:
        if n not in dae.y_names:
            raise ParameterError(f"linearize: output {n!r} is not a variable of rig {dae.name}")
    p = sim.param_vector(params)
    x, t = operating_point(sim, at, p, start, initial, rtol, atol)
    F = _jacobians(sim, tuple(inputs), tuple(outputs))
    A, B, C, D = _matrices(sim, F, t, x, p)
    cols = [dae.p_row(n) for n in inputs]
    one_sided, input_kinks = input_sides(sim, t, np.asarray(x, float), p, inputs, cols,
                                         lambda q: _matrices(sim, F, t, x, q)[1::2])
    if one_sided is not None:
        B, D = one_sided
    for name, M in (("A", A), ("B", B), ("C", C), ("D", D)):
        if not np.all(np.isfinite(M)):
            raise ParameterError(f"linearize: {name} of rig {dae.name} is not finite at "
                                 f"t = {t:g} s (a power law at zero?)")
    units = {v.name: v.unit for v in dae.x_info}
    z = sim.consistent_start(t, x, p)[0] if not dae.is_ode else np.zeros(0)
    return Linearization(A, B, C, D, dae.x_names, inputs, outputs, float(t),
                         dict(zip(dae.x_names, np.asarray(x, float).tolist())), units,
                         kinks_at(sim, t, np.asarray(x, float), z, p) + input_kinks)


def _matrices(sim, F, t, x, p):
    """(A, B, C, D) at (t, x, p), the algebraic variables solved for x and
    eliminated; ``F`` the rig's Jacobians (_jacobians)."""
    dae = sim.dae
    z = sim.consistent_start(t, x, p)[0] if not dae.is_ode else np.zeros(0)
    fx, fz, fu, gx, gz, gu, hx, hz, hu = (m.full() for m in F(t, x, z, p))
    if not dae.z.numel():
        return fx, fu, hx, hu
    try:
        Sx, Su = np.linalg.solve(gz, gx), np.linalg.solve(gz, gu)
    except np.linalg.LinAlgError:
        raise ParameterError(f"linearize: the algebraic equations of rig {dae.name} are "
                             f"singular at t = {t:g} s (index above 1 there)") from None
    return fx - fz @ Sx, fu - fz @ Su, hx - hz @ Sx, hu - hz @ Su


def operating_point(sim, at, p, start, initial, rtol, atol):
    """(x, t) of ``at``."""
    from ..setup.initialize import solve_start
    x_guess = sim.start_vector(p, start)
    if isinstance(at, str):
        if at not in ("start", "steady"):
            raise ParameterError(f"at={at!r}: give 'start', 'steady' or a time in s")
        x, _ = solve_start(sim, p, x_guess, "steady" if at == "steady" else initial)
        return x, 0.0
    try:
        t = float(at)
    except (TypeError, ValueError):
        raise ParameterError(f"at={at!r}: give 'start', 'steady' or a time in s") from None
    if not (np.isfinite(t) and t >= 0):
        raise ParameterError(f"at={at!r}: a time must be finite and >= 0 s")
    x, _ = solve_start(sim, p, x_guess, initial)
    if t == 0:
        return x, 0.0
    if t < MIN_SPACING:             # the run to it would be refused naming its t_end
        raise ParameterError(f"at={at!r}: a time must be 0 or at least {MIN_SPACING:g} s (the "
                             "integrators' resolution)")
    # from the solved start (given as the guess, it is solved again in one step)
    res = sim.run(t, 2, params=dict(zip(sim.dae.p_names, p)), rtol=rtol, atol=atol,
                  start=dict(zip(sim.dae.x_names, x)), initial=initial)
    return res._X[:, -1], t


def _jacobians(sim, inputs, outputs):
    key = ("linearize", inputs, outputs)
    F = sim._cache.get(key)
    if F is None:
        dae = sim.dae
        cols = [dae.p_row(n) for n in inputs]     # a rig's input: its value
        u = ca.vertcat(*[dae.p[i] for i in cols]) if cols else ca.SX(0, 1)
        h = ca.vertcat(*[dae.y[dae.y_names.index(n)] for n in outputs]) if outputs else \
            ca.SX(0, 1)
        f, g, x, z = dae.ode, dae.alg, dae.x, dae.z
        jac = [ca.jacobian(e, v) for e in (f, g, h) for v in (x, z, u)]
        F = ca.Function("lin", [dae.t, x, z, dae.p], jac)
        sim._cache[key] = F
    return F

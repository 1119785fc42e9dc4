"""The heat between blows: a rig's thermal network alone (its class attribute
``thermal_network``, the same components under the same names and
parameters) as the linear system it is,

    C der(T) = heat flows,   der(T) = A T + b,   lost = g T + h,

with ``lost`` the heat flow leaving through its boundaries (the fixed and
prescribed temperatures take it; a heat flow source gives it, counted
negative). A pause of ``tau`` seconds is then closed form: the matrix
exponential of the augmented system ``[[A, b], [0, 0]]`` carries the
temperatures, and the block beside it (Van Loan's) integrates the lost heat
flow over the pause, so that the heat a pause loses is found from the
boundaries' conductances, not from the change of the stored heat: the two
agree when the network keeps its energy, which a campaign's heat balance checks.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.components.thermal import (FixedHeatFlow, FixedTemperature, HeatCapacitor,
                                      PrescribedHeatFlow, PrescribedTemperature)
from pdbfs.errors import ModelError

if TYPE_CHECKING:
    from pdbfs.rig import Rig

#: the components a network's heat leaves or enters through
BOUNDARIES = (FixedTemperature, PrescribedTemperature, FixedHeatFlow, PrescribedHeatFlow)
#: K: the second point the network's linearity is checked at, above the first
LINEARITY_STEP = 10.0
#: relative agreement of the network's matrices at the two points
LINEAR_TOL = 1e-9


def capacitors(rig: Rig) -> list[str]:
    """The paths of the heat capacitors of ``rig`` (each a state ``PATH.T``)."""
    return [c.path() for c in rig.walk() if isinstance(c, HeatCapacitor)]


@dataclass
class HeatNetwork:
    """A rig's thermal network, linear, between blows.

    Attributes
    ----------
    states : list of str
        The capacitors' temperatures (``NAME.T``, K), the order of every vector here.
    capacities : numpy.ndarray
        Their heat capacities, J/K.
    A, b : numpy.ndarray
        ``der(T) = A T + b`` (1/s, K/s).
    g, h : numpy.ndarray and float
        The heat flow leaving through the boundaries, ``g T + h`` (W/K, W).
    parameters : list of str
        The network's parameters (the rig's, under the same names).
    """

    states: list
    capacities: np.ndarray
    A: np.ndarray
    b: np.ndarray
    g: np.ndarray
    h: float
    parameters: list

    @classmethod
    def of(cls, rig: Rig, params: Mapping[str, float]) -> "HeatNetwork | None":
        """The network of ``rig`` at its parameter values ``params`` (every
        rig parameter by name), or None for a rig without heat capacitors.

        Parameters
        ----------
        rig : Rig
            The rig.
        params : mapping of str to float
            Every rig parameter's value by name, SI units.

        Returns
        -------
        HeatNetwork or None

        Raises
        ------
        pdbfs.ModelError
            For a rig with heat capacitors but no ``thermal_network``, a
            network whose capacitors are not the rig's, one with inputs, or
            one that is not linear.
        """
        own = capacitors(rig)
        make = getattr(rig, "thermal_network", None)
        name = rig.compile().name
        if make is None:
            if own:
                raise ModelError(f"rig {name} has heat capacitors ({', '.join(own)}) but no "
                                 "thermal network (its class attribute thermal_network) to "
                                 "carry their heat from one blow to the next")
            return None
        net = make() if isinstance(make, type) else make
        caps = capacitors(net)
        if sorted(caps) != sorted(own):
            raise ModelError(f"rig {name}: the heat capacitors of its thermal network "
                             f"({', '.join(caps) or 'none'}) are not the rig's "
                             f"({', '.join(own) or 'none'})")
        if net.inputs():
            raise ModelError(f"rig {name}: its thermal network has inputs "
                             f"({', '.join(i.name for i in net.inputs())}); a campaign "
                             "carries heat between blows through a network of constants")
        dae = net.compile()
        states = list(dae.x_names)
        if sorted(states) != sorted(f"{c}.T" for c in caps):
            raise ModelError(f"rig {name}: its thermal network has states other than its "
                             f"capacitors' temperatures ({', '.join(states)})")
        values = {n: float(params[n]) for n in dae.p_names if n in params}
        every = {**{p.name: p.value for p in dae.params}, **values}
        caps = [s[:-2] for s in states]
        C = np.array([every[f"{c}.C"] for c in caps], dtype=float)
        T0 = np.array([every[f"{c}.T0"] for c in caps], dtype=float)
        lost = [f"{c.path()}.port.Q_flow" for c in net.walk() if isinstance(c, BOUNDARIES)]
        first = _affine(net, states, lost, values, T0)
        second = _affine(net, states, lost, values, T0 + LINEARITY_STEP)
        for M, N, what in ((first[0], second[0], "its temperatures' rates"),
                           (first[2], second[2], "its boundaries' heat flows")):
            if not np.allclose(M, N, rtol=LINEAR_TOL, atol=LINEAR_TOL * np.max(np.abs(M))):
                raise ModelError(f"rig {name}: its thermal network is not linear ({what} "
                                 "change with the temperatures); a campaign carries heat "
                                 "between blows through a linear network")
        A, b, g, h = first
        return cls(states, C, A, b, g, h, list(dae.p_names))

    def pause(self, tau: float) -> "Pause":
        """The closed form of a pause.

        Parameters
        ----------
        tau : float
            The pause, s (at least 0).

        Returns
        -------
        Pause
            The temperatures after it as a linear map of those before, and the
            heat lost through the boundaries over it.
        """
        from scipy.linalg import expm
        n = len(self.states)
        M = np.zeros((2 * (n + 1), 2 * (n + 1)))
        M[:n, :n], M[:n, n] = self.A, self.b             # d/dt [T; 1] = [[A, b], [0, 0]] [T; 1]
        M[:n + 1, n + 1:] = np.eye(n + 1)                # Van Loan: its integral beside it
        E = expm(M * tau)
        step, integral = E[:n + 1, :n + 1], E[:n + 1, n + 1:]
        lost = np.append(self.g, self.h) @ integral      # J per unit of [T; 1]
        return Pause(float(tau), step[:n], lost)

    def stored(self, T: np.ndarray) -> float:
        """The heat stored above 0 K (differences matter).

        Parameters
        ----------
        T : numpy.ndarray
            The capacitors' temperatures, K (``states``' order).

        Returns
        -------
        float
            J.
        """
        return float(self.capacities @ T)

    def lost_rate(self, T: np.ndarray) -> float:
        """The heat flow leaving through the boundaries.

        Parameters
        ----------
        T : numpy.ndarray
            The capacitors' temperatures, K (``states``' order).

        Returns
        -------
        float
            W.
        """
        return float(self.g @ T + self.h)


@dataclass
class Pause:
    """A pause of ``tau`` seconds of a HeatNetwork: ``T_after = step @ [T; 1]``,
    the heat lost through the boundaries over it ``lost @ [T; 1]`` (J)."""

    tau: float
    step: np.ndarray
    lost: np.ndarray

    def __call__(self, T: np.ndarray) -> tuple[np.ndarray, float]:
        """(the temperatures after the pause, K; the heat lost over it, J) from ``T``."""
        n = len(T)
        return self.step[:, :n] @ T + self.step[:, n], float(self.lost[:n] @ T + self.lost[n])


def _affine(net, states, lost, values, T):
    """(A, b, g, h) of the network linearized at the temperatures ``T``:
    der(T) = A T + b and the lost heat flow g T + h there."""
    start = dict(zip(states, T.tolist()))
    lin = net.linearize(params=values, start=start, outputs=[f"{s[:-2]}.port.Q_flow"
                                                             for s in states] + lost)
    n = len(states)
    res = net.simulate(1.0, n_out=2, params=values, start=start, backend="casadi")
    y = np.array([res[o][0] for o in lin.outputs])
    C = np.array([res.params[f"{s[:-2]}.C"] for s in states])
    rate = y[:n] / C                                     # C der(T) = port.Q_flow
    A = lin.A
    b = rate - A @ T
    g = lin.C[n:].sum(axis=0) if lost else np.zeros(n)
    h = float(y[n:].sum() - g @ T) if lost else 0.0
    return A, b, g, h

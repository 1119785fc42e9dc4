"""Connectors: the ports through which components exchange variables.

A translational ``Flange`` carries the position ``s`` (across, m) and the cut
force ``f`` (through, N); ``f`` acts on the component the flange belongs to,
as in Modelica. A ``HydraulicPort`` carries the pressure ``p`` (across, Pa)
and the volume flow ``q`` (through, m3/s), positive into the component (as
in Modelica's fluid libraries). A ``HeatPort`` carries the temperature ``T``
(across, K) and the heat flow ``Q_flow`` (through, W, positive into the
component), as Modelica.Thermal.HeatTransfer. Connectors of different domains never meet
(``connect()`` refuses them). Signal connectors carry one value, no flow,
in a unit: ``connect()`` joins signals of one unit only ("1" for a plain
number, the same as none), the rule an SSP of FMUs is checked by too.

A physical connector names its ``across`` and ``through`` attributes; the
compiler makes equal across variables and a zero sum of through variables
per connection set, whatever the domain.
"""
from __future__ import annotations

import math

import casadi as ca

from pdbfs.errors import ModelError


class Connector:
    """Base of every connector. ``kind`` decides which connectors may meet."""

    kind = "connector"

    def __init__(self, description: str = ""):
        self.description = description
        self.owner = None   # the component holding this connector
        self.name = None    # attribute name in the owner

    # set by Component.__setattr__
    def _attach(self, owner, name):
        if self.owner is not None:
            raise ValueError(f"connector {self.path()} is already part of a component")
        self.owner = owner
        self.name = name
        self._make_symbols()

    def _make_symbols(self):
        raise NotImplementedError

    def variables(self) -> list[tuple]:
        """(local name, symbol, unit, description, is_flow) of each variable."""
        raise NotImplementedError

    def path(self) -> str:
        """The dotted path of this connector in its rig (``piston.flange_a``)."""
        owner = self.owner.path() if self.owner is not None else "?"
        return f"{owner}.{self.name}" if owner else str(self.name)

    def __repr__(self):
        return f"<{type(self).__name__} {self.path()}>"


class Flange(Connector):
    """1-D translational flange: position ``s`` (m), cut force ``f`` (N).
    Left unconnected, a flange takes no force (a free end).

    Parameters
    ----------
    description : str
        What the flange is (shown with its variables).
    """

    kind = "translational"
    across, through = "s", "f"

    def _make_symbols(self):
        self.s = ca.SX.sym(f"{self.name}.s")
        self.f = ca.SX.sym(f"{self.name}.f")

    def variables(self):
        return [("s", self.s, "m", "Absolute position of the flange (positive down)", False),
                ("f", self.f, "N", "Cut force acting on the component at the flange", True)]


class HydraulicPort(Connector):
    """Hydraulic port: pressure ``p`` (Pa, absolute), volume flow ``q``
    (m3/s, positive into the component).

    Left unconnected, a port is closed: zero flow, as in Modelica. That is
    meaningful only where the component stays determined with no flow
    through the port (a chamber with a plugged port, a tank); a component
    declares it with ``closable=True``, and an unconnected port that is not
    closable is refused by the compiler (a ConnectError naming it), since a
    closed orifice, piston or sensor port is almost always a forgotten
    connection.

    Parameters
    ----------
    description : str
        What the port is (shown with its variables).
    closable : bool
        Whether the port may be left unconnected (closed: zero flow).
    """

    kind = "hydraulic"
    across, through = "p", "q"

    def __init__(self, description: str = "", *, closable: bool = False):
        super().__init__(description)
        self.closable = closable

    def _make_symbols(self):
        self.p = ca.SX.sym(f"{self.name}.p")
        self.q = ca.SX.sym(f"{self.name}.q")

    def variables(self):
        return [("p", self.p, "Pa", "Absolute pressure at the port", False),
                ("q", self.q, "m3/s", "Volume flow through the port, positive into the component",
                 True)]


def signal_unit(unit) -> str:
    """A signal's unit as connections compare it: "" (none given) is "1"."""
    return (unit or "").strip() or "1"


class HeatPort(Connector):
    """Thermal port: temperature ``T`` (K), heat flow ``Q_flow`` (W,
    positive into the component).

    Left unconnected, a port is insulated: zero heat flow, as in Modelica.
    That keeps the component determined only where its port's temperature
    follows from its own equations (a heat capacitor, a conductor's far
    end, a fixed temperature); a component declares it with
    ``insulable=True``, and an unconnected port that is not is refused by
    the compiler (a ConnectError naming it): a dissipating component's heat
    would have nowhere to go, a sensor would read nothing.

    Parameters
    ----------
    description : str
        What the port is (shown with its variables).
    insulable : bool
        Whether the port may be left unconnected (insulated: zero heat flow).
    """

    kind = "thermal"
    across, through = "T", "Q_flow"

    def __init__(self, description: str = "", *, insulable: bool = False):
        super().__init__(description)
        self.insulable = insulable

    def _make_symbols(self):
        self.T = ca.SX.sym(f"{self.name}.T")
        self.Q_flow = ca.SX.sym(f"{self.name}.Q_flow")

    def variables(self):
        return [("T", self.T, "K", "Temperature at the port", False),
                ("Q_flow", self.Q_flow, "W", "Heat flow through the port, positive into the "
                 "component", True)]


class _Signal(Connector):
    kind = "signal"
    is_output = False

    def __init__(self, unit: str = "1", description: str = ""):
        super().__init__(description)
        self.unit = unit

    def _make_symbols(self):
        self.value = ca.SX.sym(self.name)

    def variables(self):
        return [("", self.value, self.unit, self.description or "Signal", False)]


class SignalInput(_Signal):
    """A real-valued input signal; must be connected to a SignalOutput.

    Parameters
    ----------
    unit : str
        The signal's SI unit ("1": dimensionless); only signals of one unit
        connect.
    description : str
        What the signal is.
    min, max : float, optional
        The range the component uses the value in (in ``unit``), where it
        clamps the value beyond.
    nominal : float, optional
        The value's typical magnitude (> 0). An FMU input that drives this
        signal declares ``min``, ``max`` and ``nominal``, and says in its log
        when a value set is clamped.

    Raises
    ------
    pdbfs.ModelError
        For a range or nominal that is not a finite number, ``min`` not below
        ``max``, or a nominal not above 0.
    """

    def __init__(self, unit: str = "1", description: str = "", *, min: float | None = None,
                 max: float | None = None, nominal: float | None = None):
        super().__init__(unit, description)
        for what, v in (("min", min), ("max", max), ("nominal", nominal)):
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)):
                raise ModelError(f"SignalInput {description!r}: {what} = {v!r} must be a finite number")
        if min is not None and max is not None and not min < max:
            raise ModelError(f"SignalInput {description!r}: min = {min!r} must be below max = {max!r}")
        if nominal is not None and not nominal > 0:
            raise ModelError(f"SignalInput {description!r}: nominal = {nominal!r} must be > 0")
        self.span = tuple(None if v is None else float(v) for v in (min, max, nominal))


class SignalOutput(_Signal):
    """A real-valued output signal, computed by its component.

    Parameters
    ----------
    unit : str
        The signal's SI unit ("1": dimensionless); only signals of one unit
        connect.
    description : str
        What the signal is.
    """

    is_output = True

"""Connectors: the ports through which components exchange variables.

A translational ``Flange`` carries the position ``s`` (across, m) and the cut
force ``f`` (through, N); ``f`` acts on the component the flange belongs to,
as in Modelica. Signal connectors carry one value, no flow.
"""
from __future__ import annotations

import casadi as ca


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

    def variables(self):
        """(local name, symbol, unit, description, is_flow) of each variable."""
        raise NotImplementedError

    def path(self) -> str:
        owner = self.owner.path() if self.owner is not None else "?"
        return f"{owner}.{self.name}" if owner else str(self.name)

    def __repr__(self):
        return f"<{type(self).__name__} {self.path()}>"


class Flange(Connector):
    """1-D translational flange: position ``s`` (m), cut force ``f`` (N)."""

    kind = "translational"

    def _make_symbols(self):
        self.s = ca.SX.sym(f"{self.name}.s")
        self.f = ca.SX.sym(f"{self.name}.f")

    def variables(self):
        return [("s", self.s, "m", "Absolute position of the flange (positive down)", False),
                ("f", self.f, "N", "Cut force acting on the component at the flange", True)]


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
    """A real-valued input signal; must be connected to a SignalOutput."""


class SignalOutput(_Signal):
    """A real-valued output signal, computed by its component."""

    is_output = True

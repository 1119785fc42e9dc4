"""Signals and blocks (after Modelica.Blocks and ModelingToolkitStandardLibrary's
Blocks): one small component per concept, joined by signal connectors
(pdbfs.modelling's SignalInput and SignalOutput). Every block's input is
``u`` (``u1 .. un`` for several) and its output ``y``; ``unit`` (a
constructor argument) labels its signals.

    interfaces     Block, and the partial bases SO (output y), SISO (u -> y),
                   MISO (u1 .. un -> y)
    inputs         Input: an input of the rig, named by its component
    sources        Constant, Step, Ramp, Sine, Pulse (switches as time events)
    table          Table: values at times, linear or held, breakpoints as time events
    math           Gain, Add (weighted, with signs), Product, Limiter, DeadZone
    continuous     Integrator, FirstOrder, SecondOrder, Derivative (filtered)
    pid            PID: P, PI, PD or PID, output limits, anti-windup by back-calculation

The blocks that join signals to the physical domains are with those
domains: SignalForce and SignalPosition in pdbfs.components (translational),
CommandedValve and SignalPressure in pdbfs.components.hydraulic; the
sensors there give their reading as the signal ``y``.

May import: pdbfs.errors and pdbfs.modelling.
"""
from .continuous import Derivative, FirstOrder, Integrator, SecondOrder
from .inputs import Input
from .interfaces import MISO, SISO, SO, Block
from .math import Add, DeadZone, Gain, Limiter, PartialBounds, Product
from .pid import KINDS as PID_KINDS
from .pid import PID
from .sources import Constant, PartialSource, Pulse, Ramp, Sine, Step
from .table import INTERPOLATIONS, Table, table_expression

__all__ = ["Derivative", "FirstOrder", "Integrator", "SecondOrder", "Input", "MISO", "SISO", "SO",
           "Block", "Add", "DeadZone", "Gain", "Limiter", "PartialBounds", "Product", "PID_KINDS",
           "PID", "Constant", "PartialSource", "Pulse", "Ramp", "Sine", "Step", "INTERPOLATIONS",
           "Table", "table_expression"]

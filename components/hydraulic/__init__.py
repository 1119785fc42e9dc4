"""Hydraulic components: pressure ``p`` (Pa, absolute) across, volume flow
``q`` (m3/s, positive into the component) through (pdbfs.modelling's
HydraulicPort), after Modelica's fluid libraries and
ModelingToolkitStandardLibrary's hydraulics.

    interfaces      PartialOnePort, PartialTwoPort (PartialOrifice in resistances,
                    PartialPressureValve in valves, PartialSource in sources)
    laws            bulk-modulus laws, regularised root, smooth clamp and step
    volume          Volume: compressibility, cavitation, swept walls
    piston          Piston (flange + port), Cylinder (a piston over its chamber)
    resistances     Orifice (turbulent), LaminarLeak, on PartialDissipativeTwoPort
                    (heat_port=True: their power dp*q leaves as heat)
    valves          CheckValve, ReliefValve, TimedValve, PulseValve, and
                    CommandedValve (its opening a signal input)
    sources         Tank, PressureSource, FlowSource, and SignalPressure (a
                    pressure given by a signal input)
    accumulator     Accumulator (gas-charged, polytropic)
    sensors         PressureSensor, FlowSensor (each also as the signal output y)

An unconnected port is closed (zero flow), allowed only on components where
that means something (Volume, Cylinder, Accumulator, sources and tanks);
elsewhere the compiler refuses it.

May import: pdbfs.errors, pdbfs.modelling and pdbfs.components.thermal's interfaces.
"""
from .accumulator import Accumulator
from .interfaces import PartialOnePort, PartialTwoPort
from .laws import (ATMOSPHERE, bulk_modulus_air, bulk_modulus_constant, bulk_modulus_linear,
                   regularised_root, smooth_ramp, smooth_step)
from .piston import Cylinder, Piston
from .resistances import LaminarLeak, Orifice, PartialDissipativeTwoPort, PartialOrifice
from .sensors import FlowSensor, PressureSensor
from .sources import FlowSource, PartialSource, PressureSource, SignalPressure, Tank
from .valves import (CheckValve, CommandedValve, PartialPressureValve, PulseValve, ReliefValve,
                     TimedValve)
from .volume import BULK_MODULUS_LAWS, Volume

__all__ = ["Accumulator", "PartialOnePort", "PartialTwoPort", "ATMOSPHERE", "bulk_modulus_air",
           "bulk_modulus_constant", "bulk_modulus_linear", "regularised_root", "smooth_ramp",
           "smooth_step", "Cylinder", "Piston", "LaminarLeak", "Orifice", "PartialDissipativeTwoPort", "PartialOrifice",
           "FlowSensor", "PressureSensor", "FlowSource", "PartialSource", "PressureSource",
           "SignalPressure", "Tank", "CheckValve", "CommandedValve", "PartialPressureValve", "PulseValve",
           "ReliefValve", "TimedValve", "BULK_MODULUS_LAWS", "Volume"]

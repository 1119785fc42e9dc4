"""Translational mechanics, one direction (x down, after Modelica's
Mechanics.Translational): flanges carry a position (across) and a force
(through).

    interfaces     the shared partial bases (one flange, two flanges, compliant, compression)
    mass           Mass, Fixed          springs      Spring, Damper
    contact        Hertz contact and hysteresis damping (the paper's eq. 1-6)
    friction       the loading piston's seal      oil      the oil column (compression only)
    sources        Force, Position, Gravity, and SignalForce, SignalPosition (driven by a signal)
    sensors        position, speed, force, pressure (each also as the signal output y)
    chain          masses joined by springs; bar: an elastic bar built from it
    constraints    ideal kinematic constraints (a cam)

Dissipating components (Damper, HuntCrossleyDamper, ImpactContact, SealFriction)
take ``heat_port=True``; the oil column and the seal take temperature laws
(pdbfs.components.thermal).

May import: pdbfs.errors, pdbfs.modelling and pdbfs.components' laws, functions
and thermal interfaces and laws.
"""
from .bar import BarResolutionWarning, ElasticBar, check_bar_resolution
from .chain import MassChain
from .constraints import Cam
from .contact import HertzContact, HuntCrossleyDamper, ImpactContact
from .friction import SealFriction
from .interfaces import (PartialCompliant, PartialCompliantWithVelocity, PartialCompression,
                         PartialOneFlange, PartialTwoFlanges)
from .mass import Fixed, Mass
from .oil import OilColumn
from .sensors import ForceSensor, PositionSensor, PressureSensor, SpeedSensor
from .sources import Force, Gravity, Position, SignalForce, SignalPosition
from .springs import Damper, Spring

__all__ = ["BarResolutionWarning", "ElasticBar", "check_bar_resolution", "MassChain", "Cam",
           "HertzContact", "HuntCrossleyDamper", "ImpactContact", "SealFriction",
           "PartialCompliant", "PartialCompliantWithVelocity", "PartialCompression",
           "PartialOneFlange", "PartialTwoFlanges", "Fixed", "Mass", "OilColumn", "ForceSensor",
           "PositionSensor", "PressureSensor", "SpeedSensor", "Force", "Gravity", "Position",
           "SignalForce", "SignalPosition", "Damper", "Spring"]

"""The component library: translational mechanics for impact test rigs.

One small component per concept, each a class declaring parameters,
variables and equations (after Modelica's Mechanics.Translational):
interfaces.py has the shared partial bases, laws.py the paper's formulas
(Hertz stiffness, damping laws, restitution from a force history) as plain
functions; constraints.py ideal kinematic constraints (a cam).

May import: pdbfs.errors and pdbfs.modelling.
"""
from .bar import BarResolutionWarning, ElasticBar, check_bar_resolution
from .chain import MassChain
from .constraints import Cam
from .contact import HertzContact, HuntCrossleyDamper, ImpactContact
from .friction import SealFriction
from .interfaces import (PartialCompliant, PartialCompliantWithVelocity, PartialCompression,
                         PartialOneFlange, PartialTwoFlanges)
from .laws import (DAMPING_LAWS, damping_flores, damping_hunt_crossley,
                   damping_lankarani_nikravesh, hertz_stiffness, impact_velocity)
from .mass import Fixed, Mass
from .oil import OilColumn
from .sensors import ForceSensor, PositionSensor, PressureSensor, SpeedSensor
from .sources import Force, Gravity, Position
from .springs import Damper, Spring

__all__ = ["Cam", "MassChain", "HertzContact", "HuntCrossleyDamper", "ImpactContact", "SealFriction",
           "PartialCompliant", "PartialCompliantWithVelocity", "PartialCompression",
           "PartialOneFlange", "PartialTwoFlanges", "DAMPING_LAWS", "damping_flores",
           "damping_hunt_crossley", "damping_lankarani_nikravesh", "hertz_stiffness",
           "impact_velocity", "Fixed", "Mass", "OilColumn",
           "ForceSensor", "PositionSensor", "PressureSensor", "SpeedSensor", "Force",
           "Gravity", "Position", "Damper", "Spring", "ElasticBar", "BarResolutionWarning",
           "check_bar_resolution"]

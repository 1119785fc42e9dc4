"""The component library: one small component per concept, each a class
declaring parameters, variables and equations on shared partial bases.

    translational/  mechanics in one direction (after Modelica's
                    Mechanics.Translational): masses, springs, contacts, the
                    seal, the oil column, sources, sensors, chains and bars, a cam
    hydraulic/      pdbfs.components.hydraulic: volumes, pistons, orifices,
                    valves, sources, accumulators, sensors
    thermal/        pdbfs.components.thermal: heat capacitors, conductors,
                    convection, sources, sensors, temperature laws; the heat
                    ports of the dissipating components
    blocks/         pdbfs.components.blocks: signals and blocks (inputs of the
                    rig, sources, tables, math, linear dynamics, PID); the
                    translational SignalForce and SignalPosition (here) and the
                    hydraulic CommandedValve and SignalPressure join them to
                    the physical domains
    laws            the paper's formulas as plain functions (Hertz stiffness,
                    damping laws, impact velocity)
    functions       powers with finite derivatives everywhere, for the force laws

May import: pdbfs.errors and pdbfs.modelling.
"""
from .laws import (DAMPING_LAWS, damping_flores, damping_hunt_crossley,
                   damping_lankarani_nikravesh, hertz_stiffness, impact_velocity)
from .translational import (BarResolutionWarning, Cam, Damper, ElasticBar, Fixed, Force,
                            ForceSensor, Gravity, HertzContact, HuntCrossleyDamper,
                            ImpactContact, Mass, MassChain, OilColumn, PartialCompliant,
                            PartialCompliantWithVelocity, PartialCompression, PartialOneFlange,
                            PartialTwoFlanges, Position, PositionSensor, PressureSensor,
                            SealFriction, SignalForce, SignalPosition, SpeedSensor, Spring,
                            check_bar_resolution)

__all__ = ["Cam", "MassChain", "HertzContact", "HuntCrossleyDamper", "ImpactContact", "SealFriction",
           "PartialCompliant", "PartialCompliantWithVelocity", "PartialCompression",
           "PartialOneFlange", "PartialTwoFlanges", "DAMPING_LAWS", "damping_flores",
           "damping_hunt_crossley", "damping_lankarani_nikravesh", "hertz_stiffness",
           "impact_velocity", "Fixed", "Mass", "OilColumn",
           "ForceSensor", "PositionSensor", "PressureSensor", "SpeedSensor", "Force",
           "Gravity", "Position", "SignalForce", "SignalPosition", "Damper", "Spring", "ElasticBar",
           "BarResolutionWarning", "check_bar_resolution"]

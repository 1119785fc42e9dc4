"""Heat transfer (after Modelica.Thermal.HeatTransfer): a HeatPort carries the
temperature ``T`` (K, across) and the heat flow ``Q_flow`` (W, through,
positive into the component).

    interfaces     PartialElement1D (two ports, no storage) and
                   PartialConditionalHeatPort: the heat port a dissipating
                   component takes with ``heat_port=True``
    elements       HeatCapacitor, ThermalConductor, Convection
    sources        FixedTemperature, PrescribedTemperature, FixedHeatFlow,
                   PrescribedHeatFlow
    sensors        TemperatureSensor, HeatFlowSensor (signal output y)
    laws           temperature laws (linear, exponential, Andrade's viscosity)
                   and the data of water-glycol and steel

An unconnected heat port is insulated (zero heat flow), allowed where the
component stays determined (capacitors, conductors, fixed temperatures);
elsewhere (a dissipating component's heat port, sensors, heat flow
sources) the compiler refuses it.

May import: pdbfs.errors and pdbfs.modelling.
"""
from .elements import Convection, HeatCapacitor, ThermalConductor
from .interfaces import T_ROOM, PartialConditionalHeatPort, PartialElement1D
from .laws import (STEEL_SPECIFIC_HEAT, STIFFNESS_LAWS, VISCOSITY_LAWS, WATER_GLYCOL_ANDRADE_B,
                   WATER_GLYCOL_BULK_MODULUS, WATER_GLYCOL_DENSITY, WATER_GLYCOL_MODULUS_FALL,
                   WATER_GLYCOL_SPECIFIC_HEAT, WATER_GLYCOL_VISCOSITY, andrade_constant,
                   andrade_factor, exponential_factor, linear_factor)
from .sensors import HeatFlowSensor, TemperatureSensor
from .sources import FixedHeatFlow, FixedTemperature, PrescribedHeatFlow, PrescribedTemperature

__all__ = ["Convection", "HeatCapacitor", "ThermalConductor", "T_ROOM",
           "PartialConditionalHeatPort", "PartialElement1D", "STEEL_SPECIFIC_HEAT",
           "STIFFNESS_LAWS", "VISCOSITY_LAWS", "WATER_GLYCOL_ANDRADE_B",
           "WATER_GLYCOL_BULK_MODULUS", "WATER_GLYCOL_DENSITY", "WATER_GLYCOL_MODULUS_FALL",
           "WATER_GLYCOL_SPECIFIC_HEAT", "WATER_GLYCOL_VISCOSITY", "andrade_constant",
           "andrade_factor", "exponential_factor", "linear_factor", "HeatFlowSensor",
           "TemperatureSensor", "FixedHeatFlow", "FixedTemperature", "PrescribedHeatFlow",
           "PrescribedTemperature"]

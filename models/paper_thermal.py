"""The paper rig with its heat: the seal's friction and the contact's
hysteresis dissipate into the oil and the piston, the oil column's
stiffness and the seal's friction follow the oil's temperature, and the
piston, the oil and the breech exchange heat and lose it to the room.

    contact --heat--> piston_heat --oil_piston-- oil_heat --oil_breech-- breech_heat
    seal    --heat--> oil_heat (its temperature also sets oil.k_T, seal.c_T)
    piston_heat --piston_room--> room <--breech_room-- breech_heat

The network alone (``PaperThermalNetwork``: the same components, names and
parameters, without the mechanics) is what carries the heat between blows.
"""
from __future__ import annotations

from typing import Any

from pdbfs.components.thermal import (Convection, FixedTemperature, HeatCapacitor,
                                      ThermalConductor)
from pdbfs.modelling import Component
from pdbfs.rig import Rig

from .paper import PAPER_SIGNALS, PaperRig

#: the summary's signals: those of the paper rig
PAPER_THERMAL_SIGNALS = dict(PAPER_SIGNALS)
#: the heat capacitors of the network, each a state ``NAME.T`` (K)
PAPER_THERMAL_CAPACITORS = ("oil_heat", "piston_heat", "breech_heat")


def declare_paper_network(rig: Component) -> None:
    """Declare the thermal network of paper-thermal in ``rig``: three heat
    capacitors at the room's temperature, the conductors between them and
    the convection to the room (the values and their sources: the thermal
    domain's documentation page).

    Parameters
    ----------
    rig : Component
        The rig being declared (inside its ``declare()``).
    """
    rig.room = FixedTemperature(T=293.15)
    # the oil column: A*L = 7.9e-3 m3 of water-glycol (L = K*A/k2 with K = 3.4 GPa),
    # 8.5 kg at 1080 kg/m3 and 3300 J/(kg.K)
    rig.oil_heat = HeatCapacitor(C=2.80e4, T0=293.15)
    # steel at 460 J/(kg.K): the piston and seal assembly (241.7 kg), the breech (500 kg)
    rig.piston_heat = HeatCapacitor(C=1.112e5, T0=293.15)
    rig.breech_heat = HeatCapacitor(C=2.30e5, T0=293.15)
    # film coefficients of the oil on steel (about 200 W/(m2.K)) on the piston's face and
    # on the bore around the column; still air on the outer surfaces (about 10 W/(m2.K))
    rig.oil_piston = ThermalConductor(G=5.0)
    rig.oil_breech = ThermalConductor(G=40.0)
    rig.piston_room = Convection(Gc=5.0)
    rig.breech_room = Convection(Gc=20.0)
    rig.connect(rig.piston_heat.port, rig.oil_piston.port_a, rig.piston_room.solid)
    rig.connect(rig.oil_heat.port, rig.oil_piston.port_b, rig.oil_breech.port_a)
    rig.connect(rig.breech_heat.port, rig.oil_breech.port_b, rig.breech_room.solid)
    rig.connect(rig.room.port, rig.piston_room.fluid, rig.breech_room.fluid)


class PaperThermalNetwork(Rig):
    """The thermal network of paper-thermal alone: its heat capacitors,
    conductors and convection to the room, under the same names and
    parameters, to carry the heat of one blow to the next."""

    name = "pdbfs_paper_thermal_network"

    def declare(self):
        declare_paper_network(self)


class PaperThermalRig(PaperRig):
    """The paper rig with its heat: the seal and the contact dissipate into
    the oil and the piston, which exchange heat with the breech and lose it
    to the room; the oil column's stiffness and the seal's friction follow
    the oil's temperature. At the room's temperature it starts as the paper
    rig, and a blow gives the paper rig's pulse.

    Parameters
    ----------
    law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        The contact's damping law (ImpactContact's ``law``); None: the
        paper's damping factor ``contact.D``.
    """

    name = "pdbfs_paper_thermal"
    summary_signals = PAPER_THERMAL_SIGNALS
    #: the rig's thermal network alone (the same component names and parameters)
    thermal_network = PaperThermalNetwork

    def options(self, name: str) -> dict[str, Any]:
        return {"contact": {"heat_port": True},
                "seal": {"heat_port": True, "viscosity_law": "andrade"},
                "oil": {"heat_port": True, "stiffness_law": "exponential"}}.get(name, {})

    def declare(self):
        super().declare()
        declare_paper_network(self)
        self.connect(self.contact.heat_port, self.piston_heat.port)
        self.connect(self.seal.heat_port, self.oil.heat_port, self.oil_heat.port)


def paper_thermal_rig(**kw: Any) -> PaperThermalRig:
    """The paper rig with its heat (paper-thermal); ``law=`` picks a damping
    law for the contact, as for the paper rig."""
    return PaperThermalRig(**kw)

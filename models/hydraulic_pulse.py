"""The conventional alternative to the drop hammer (the paper's
introduction): the breech is fatigue-tested by pressurising its chamber
with oil through a fast valve, which opens, stays open and closes again,
from a gas-charged accumulator (or an ideal pressure source); a drain
orifice lets the chamber down to the tank.

    supply (Accumulator | PressureSource)
      --valve: PulseValve (opens over T_open from t_open, closes from t_close)-->
    chamber: Volume (the breech's bore)  --drain: Orifice-->  tank

The defaults give a pulse like the gun's (and the paper rig's): 95 MPa
peak at 5.5 ms, 14 ms above 1 % of the peak (accumulator supply).

``line=True`` (``--rig hydraulic-pulse-line``): a hose (an orifice) and a
line volume between the supply and the valve; the line starts at the supply
pressure, solved at initialization (``Volume(steady_start=True)``: no flow
through the hose at t = 0).

The orifices round their square-root law below 0.1 MPa (``dp_t``; the
flow is then within 0.25 % of the turbulent law from 1 MPa up): with the
components' default of 1 kPa the draining chamber is stiff at the end of
the pulse, and the parameter sensitivities that design and calibration
integrate (Adams) took 50 times longer.
"""
from __future__ import annotations

from typing import Any

from pdbfs.components.hydraulic import Accumulator, Orifice, PressureSource, PulseValve, Tank, \
    Volume
from pdbfs.errors import ParameterError
from pdbfs.rig import Rig

PULSE_SIGNALS = {"pressure": "chamber.p"}
SUPPLIES = ("accumulator", "pressure")


class HydraulicPulseRig(Rig):
    """A breech chamber pressurised through a fast valve: a gun-like pulse
    without a hammer. ``supply``: ``"accumulator"`` (default) or
    ``"pressure"`` (an ideal source).

    Parameters
    ----------
    supply : {"accumulator", "pressure"}
        A gas-charged accumulator, or an ideal pressure source.
    line : bool
        A hose and a line between the supply and the valve (the line's start
        pressure solved in equilibrium).

    Raises
    ------
    pdbfs.ParameterError
        For an unknown supply.
    """

    name = "pdbfs_hydraulic_pulse"
    summary_signals = PULSE_SIGNALS
    #: what the workbench page (pdbfs app) offers first: the chamber's
    #: bulk modulus to calibrate, the valve's area to design, a map of the
    #: valve's and the drain's areas
    page_defaults = {"calibrate": ("chamber.K",), "design": ("valve.A",),
                     "map_x": ("valve.A", 2e-5, 2e-4), "map_y": ("drain.A", 1e-5, 1e-4)}
    #: the parameters that matter most: the supply's pressure, the areas
    #: the oil flows in and out through, and the chamber's stiffness
    key_parameters = ("supply.p0", "valve.A", "drain.A", "chamber.K")

    def __init__(self, supply: str = "accumulator", line: bool = False, **params: float):
        if supply not in SUPPLIES:
            raise ParameterError(f"HydraulicPulseRig: unknown supply {supply!r}; choose one of "
                                 + ", ".join(SUPPLIES))
        self._supply, self._line = supply, bool(line)
        if supply == "pressure":           # an ideal source: its pressure, not a start value
            self.key_parameters = ("supply.p",) + self.key_parameters[1:]
        if self._line:
            self.name = "pdbfs_hydraulic_pulse_line"
        super().__init__(**params)

    def declare(self):
        if self._supply == "accumulator":
            self.supply = Accumulator(V0=4e-3, p_pre=60e6, p0=200e6, n=1.4)
        else:
            self.supply = PressureSource(p=175e6)
        self.valve = PulseValve(Cd=0.7, A=8e-5, t_open=0.0, T_open=4e-3, t_close=4.5e-3,
                                T_close=2e-3, dp_t=1e5)
        self.chamber = Volume(V=1e-3, K=1.5e9)
        self.drain = Orifice(Cd=0.7, A=4e-5, dp_t=1e5)
        self.tank = Tank()
        if self._line:   # hose and line: the line's start pressure is solved
            self.hose = Orifice(Cd=0.7, A=2e-4, dp_t=1e5)
            self.line = Volume(V=0.5e-3, K=1.5e9, steady_start=True)
            self.connect(self.supply.port, self.hose.port_a)
            self.connect(self.hose.port_b, self.line.port, self.valve.port_a)
        else:
            self.connect(self.supply.port, self.valve.port_a)
        self.connect(self.valve.port_b, self.chamber.port, self.drain.port_a)
        self.connect(self.drain.port_b, self.tank.port)


def hydraulic_pulse_rig(**kw: Any) -> HydraulicPulseRig:
    """The valve-driven pulse rig; ``supply`` and ``line`` as in HydraulicPulseRig."""
    return HydraulicPulseRig(**kw)

"""The valve-driven pulse rig under closed-loop control: a PID controller
opens the valve (a CommandedValve) so that the chamber's measured pressure
follows a target pulse.

    target (Table) --+--> error = target - measured --> pid (PID, 0..1) --> valve.opening
    sensor.y --------+
    supply (Accumulator) --valve--> chamber (Volume) --drain: Orifice--> tank

Three rigs share these parts:

    HydraulicPulsePIDRig  the whole loop in one rig (``--rig hydraulic-pulse-pid``)
    PulsePlantRig         the plant alone: its input ``opening`` commands the
                          valve, its output ``sensor.y`` is the measured pressure
    PulseControllerRig    the controller alone, made of blocks only: its input
                          ``measured`` is the pressure, its output ``pid.y`` the
                          valve's command

Exported as FMUs and connected (``sensor.y`` -> ``measured``, ``pid.y`` ->
``opening``), plant and controller co-simulate the loop the first rig
integrates at once: ``pdbfs export-ssp`` writes that system as an SSP file.

The target rises from the start pressure to 90 MPa over 3 ms, holds 2 ms and
falls back over 10 ms; the drain alone lets the chamber down more slowly
than that at low pressure, so the controller closes the valve (its lower
limit) and its integral part is held there by the anti-windup.
"""
from __future__ import annotations

from pdbfs.components import blocks as B
from pdbfs.components.hydraulic import ATMOSPHERE, Accumulator, CommandedValve, Orifice, \
    PressureSensor, Tank, Volume
from pdbfs.rig import Rig

#: the target pulse: times (s) and pressures (Pa, absolute)
TARGET = ((0.0, 1e-3, 4e-3, 6e-3, 16e-3), (ATMOSPHERE, ATMOSPHERE, 90e6, 90e6, ATMOSPHERE))
#: what the rigs' summaries take as the pulse
PID_SIGNALS = {"pressure": "chamber.p"}
#: the plant's and the controller's connection: (output, input) pairs, as
#: ``pdbfs export-ssp --connect`` takes them
LOOP = (("plant.sensor.y", "controller.measured"), ("controller.pid.y", "plant.opening"))


def _declare_plant(rig: Rig) -> None:
    """The supply, the valve, the chamber with its pressure sensor, the drain (as hydraulic-pulse)."""
    rig.supply = Accumulator(V0=4e-3, p_pre=60e6, p0=200e6, n=1.4)
    rig.valve = CommandedValve(Cd=0.7, A=8e-5, dp_t=1e5)
    rig.chamber = Volume(V=1e-3, K=1.5e9)
    rig.sensor = PressureSensor()
    rig.drain = Orifice(Cd=0.7, A=4e-5, dp_t=1e5)
    rig.tank = Tank()
    rig.connect(rig.supply.port, rig.valve.port_a)
    rig.connect(rig.valve.port_b, rig.chamber.port, rig.drain.port_a, rig.sensor.port)
    rig.connect(rig.drain.port_b, rig.tank.port)


def _declare_controller(rig: Rig) -> None:
    """The target, the control error and the PI(D) controller limited to 0..1."""
    rig.target = B.Table(*TARGET, unit="Pa")
    rig.error = B.Add(k2=-1.0, unit="Pa")
    # gain 8e-8 per Pa: 1/8 open per MPa of error; integral time 0.5 ms
    rig.pid = B.PID(kind="PI", limited=True, k=8e-8, Ti=5e-4, yMin=0.0, yMax=1.0, Ni=0.5,
                    input_unit="Pa")
    rig.connect(rig.target.y, rig.error.u1)
    rig.connect(rig.error.y, rig.pid.u)


class HydraulicPulsePIDRig(Rig):
    """The valve-driven pulse rig whose valve a PI controller (output limits
    0..1, anti-windup) opens so that the chamber's pressure follows a target
    pulse (90 MPa, rising over 3 ms): plant and controller in one rig."""

    name = "pdbfs_hydraulic_pulse_pid"
    summary_signals = PID_SIGNALS
    page_defaults = {"calibrate": ("chamber.K",), "design": ("pid.k",),
                     "map_x": ("pid.k", 4e-8, 1.6e-7), "map_y": ("pid.Ti", 2.5e-4, 1e-3)}
    #: the controller's gain and integral time, then the plant's areas and stiffness
    key_parameters = ("pid.k", "pid.Ti", "valve.A", "drain.A", "chamber.K")

    def declare(self):
        _declare_plant(self)
        _declare_controller(self)
        self.connect(self.sensor.y, self.error.u2)
        self.connect(self.pid.y, self.valve.opening)


class PulsePlantRig(Rig):
    """The plant of the closed-loop pulse rig: the valve's opening is the
    rig's input ``opening`` (0 closed to 1 open), the chamber's pressure the
    sensor's output ``sensor.y``."""

    name = "pdbfs_pulse_plant"
    summary_signals = PID_SIGNALS
    key_parameters = ("valve.A", "drain.A", "chamber.K")

    def declare(self):
        _declare_plant(self)
        self.opening = B.Input("1", start=0.0, description="Commanded valve opening, 0 closed to 1 open")
        self.connect(self.opening.y, self.valve.opening)


class PulseControllerRig(Rig):
    """The controller of the closed-loop pulse rig, of blocks only: the
    measured pressure is the rig's input ``measured`` (Pa), the valve's
    command the PI controller's output ``pid.y`` (0..1)."""

    name = "pdbfs_pulse_controller"
    key_parameters = ("pid.k", "pid.Ti")

    def declare(self):
        _declare_controller(self)
        self.measured = B.Input("Pa", start=ATMOSPHERE, description="Measured chamber pressure")
        self.connect(self.measured.y, self.error.u2)


def hydraulic_pulse_pid_rig() -> HydraulicPulsePIDRig:
    """The closed-loop pulse rig: a PI controller opens the valve to follow a target pulse."""
    return HydraulicPulsePIDRig()


def pulse_plant_rig() -> PulsePlantRig:
    """The closed-loop pulse rig's plant: input ``opening``, output ``sensor.y``."""
    return PulsePlantRig()


def pulse_controller_rig() -> PulseControllerRig:
    """The closed-loop pulse rig's controller: input ``measured``, output ``pid.y``."""
    return PulseControllerRig()

"""Rigs built from the component library. ``RIGS`` maps the names the
command line accepts (``--rig NAME``) to functions that build them;
``rig_from`` builds one of them, or a user's own rig named as
``FILE.py:NAME`` or ``MODULE:NAME``.

May import: pdbfs.errors, pdbfs.modelling, pdbfs.components and pdbfs.rig.
"""
from pdbfs.rig import Rig

from .bar_piston import BAR_SIGNALS, BarPistonRig, bar_piston_rig
from .drop import DROP_SIGNALS, DropRestRig, DropRig, drop_rig
from .hydraulic_pulse import PULSE_SIGNALS, HydraulicPulseRig, hydraulic_pulse_rig
from .loading import first_paragraph, user_rig
from .paper import PAPER_SIGNALS, PaperRig, paper_rig
from .paper_hydraulic import PAPER_HYDRAULIC_SIGNALS, PaperHydraulicRig, paper_hydraulic_rig
from .paper_thermal import (PAPER_THERMAL_SIGNALS, PaperThermalNetwork, PaperThermalRig,
                            declare_paper_network, paper_thermal_rig)
from .pulse_control import (LOOP, PID_SIGNALS, TARGET, HydraulicPulsePIDRig, PulseControllerRig,
                            PulsePlantRig, hydraulic_pulse_pid_rig, pulse_controller_rig,
                            pulse_plant_rig)
from .split_piston import SplitPiston, SplitPistonRig, SplitSeal, split_piston_rig

#: contact damping laws offered beside Table 1's D, with the rig-name suffix
LAW_RIGS = {"ln": "lankarani-nikravesh", "hc": "hunt-crossley", "flores": "flores"}


def _paper_with_law(suffix):
    def build():
        rig = paper_rig(law=LAW_RIGS[suffix])
        rig.name = f"pdbfs_{suffix}"
        # the law is tuned to the impact velocity the rig is run at
        rig.contact.bind("v_impact", rig.hammer.v0)
        return rig
    build.__name__ = f"paper_{suffix}_rig"
    build.__doc__ = (f"The paper's rig with the {LAW_RIGS[suffix]} damping law: D computed "
                     "from contact.e and the impact velocity hammer.v0.")
    return build


def paper_hydraulic_oil_rig():
    """paper-hydraulic with a bulk modulus growing with pressure (K + 7.5 p,
    K at p = 0 the paper's k2*L/A) in a column that shrinks with the stroke."""
    rig = paper_hydraulic_rig(law="linear", swept=True)
    rig.name = "pdbfs_hydraulic_oil"
    return rig


RIGS = {
    "paper": paper_rig,
    **{f"paper-{s}": _paper_with_law(s) for s in LAW_RIGS},
    # the paper's conclusion: piston and seal split into several masses
    "split-piston": lambda: split_piston_rig(n=4),
    # the piston as an elastic steel bar (issue 10)
    "bar-piston": bar_piston_rig,
    # gravity and a drop height: repeated blows
    "drop": drop_rig,
    # ... the hammer resting on the piston: the start solved at static equilibrium
    "drop-rest": lambda: drop_rig(rest=True),
    # the oil column from hydraulic components (issue 17): the paper's k2 as oil
    "paper-hydraulic": paper_hydraulic_rig,
    # ... with oil whose bulk modulus grows with pressure, in a chamber that shrinks
    "paper-hydraulic-oil": paper_hydraulic_oil_rig,
    # the conventional alternative: a chamber pressurised through a fast valve
    "hydraulic-pulse": hydraulic_pulse_rig,
    # ... with a hose and a line that start at the supply pressure (solved)
    "hydraulic-pulse-line": lambda: hydraulic_pulse_rig(line=True),
    # ... whose valve a PI controller opens to follow a target pulse (closed loop)
    "hydraulic-pulse-pid": hydraulic_pulse_pid_rig,
    # the paper rig with its heat: dissipation into oil, piston and breech, temperature laws
    "paper-thermal": paper_thermal_rig,
    # ... its plant alone: the valve's opening is an input (--input opening=FILE.csv)
    "hydraulic-pulse-plant": pulse_plant_rig,
}

#: each rig in a line, as `pdbfs rigs` lists them (a rig without one: its docstring's first lines)
DESCRIPTIONS = {
    "paper": "the paper's rig (Table 1): hammer, piston on an oil column, breech on its mount",
    "paper-ln": "paper with the Lankarani-Nikravesh contact damping (D from contact.e and hammer.v0)",
    "paper-hc": "paper with the Hunt-Crossley contact damping (D from contact.e and hammer.v0)",
    "paper-flores": "paper with the Flores contact damping (D from contact.e and hammer.v0)",
    "split-piston": "paper with the piston and its seal split into 4 masses",
    "bar-piston": "paper with the piston an elastic steel bar of 30 segments",
    "drop": "paper with gravity: the hammer dropped from hammer.h, striking again and again",
    "drop-rest": "drop with the hammer resting on the piston: the start solved at static equilibrium",
    "paper-hydraulic": "paper with its oil column made of hydraulic components (a piston and a volume)",
    "paper-hydraulic-oil": "paper-hydraulic with a bulk modulus growing with pressure, in a "
                           "chamber that shrinks with the stroke",
    "hydraulic-pulse": "a breech chamber filled through a fast valve from an accumulator: a pulse "
                       "without a hammer",
    "hydraulic-pulse-line": "hydraulic-pulse with a hose and a line that start at the supply "
                            "pressure (solved)",
    "hydraulic-pulse-pid": "hydraulic-pulse whose valve a PI controller opens so that the pressure "
                           "follows a 90 MPa target pulse",
    "hydraulic-pulse-plant": "the plant of hydraulic-pulse-pid alone: its input opening commands "
                             "the valve, sensor.y is the measured pressure",
}

def rig_from(spec: str, where: str = "rig") -> Rig:
    """A new rig: ``RIGS[spec]()``, or the user's rig ``spec`` names.

    Parameters
    ----------
    spec : str
        A name of :data:`RIGS` (``"paper"``), or a user's rig:
        ``"path/to/file.py:NAME"`` (the file is imported as a module, its
        folder first on ``sys.path`` so that it can import its neighbours;
        ``:NAME`` may be left out where the file defines one Rig class) or
        ``"package.module:NAME"`` (imported as Python does, the current
        folder included). NAME is a Rig subclass or a function returning a
        rig; a dotted NAME (``factories.small``) is followed attribute by
        attribute.
    where : str
        How messages name what gave ``spec`` (``"--rig"`` on the command line).

    Returns
    -------
    Rig
        A new rig.

    Raises
    ------
    ParameterError
        An unknown name, a file or module that is missing or fails to import,
        a NAME it does not define, something that is not a rig, a builder
        that raises: one line naming which.

    Examples
    --------
    >>> from pdbfs.models import rig_from
    >>> rig_from("hydraulic-pulse-plant").inputs()[0].name
    'opening'
    """
    if isinstance(spec, str) and spec in RIGS:
        return RIGS[spec]()
    return user_rig(spec, where, list(RIGS))


def rig_description(name: str, rig: Rig | None = None) -> str:
    """A rig's description in one line: :data:`DESCRIPTIONS`'s, else the
    first paragraph of its builder's docstring, else of its class's.

    Parameters
    ----------
    name : str
        The rig's name in :data:`RIGS`, or a user's rig as :func:`rig_from` takes it.
    rig : Rig, optional
        The rig (built here when not given and needed).

    Returns
    -------
    str
        The description, one line.
    """
    if name in DESCRIPTIONS:
        return DESCRIPTIONS[name]
    return first_paragraph(RIGS.get(name), rig if rig is not None else rig_from(name))


__all__ = ["PaperRig", "paper_rig", "PAPER_SIGNALS", "RIGS", "LAW_RIGS", "SplitPiston",
           "SplitSeal", "SplitPistonRig", "split_piston_rig", "DropRig", "DropRestRig", "drop_rig",
           "DROP_SIGNALS", "BarPistonRig", "bar_piston_rig", "BAR_SIGNALS", "PaperHydraulicRig",
           "paper_hydraulic_rig", "PAPER_HYDRAULIC_SIGNALS", "HydraulicPulseRig",
           "hydraulic_pulse_rig", "PULSE_SIGNALS", "HydraulicPulsePIDRig", "PulsePlantRig",
           "PulseControllerRig", "hydraulic_pulse_pid_rig", "pulse_plant_rig", "pulse_controller_rig",
           "PaperThermalRig", "PaperThermalNetwork", "paper_thermal_rig", "declare_paper_network",
           "PAPER_THERMAL_SIGNALS",
           "PID_SIGNALS", "TARGET", "LOOP", "rig_from", "rig_description", "DESCRIPTIONS"]

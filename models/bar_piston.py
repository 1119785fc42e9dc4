"""The paper's rig with the loading piston as an elastic steel bar
(ElasticBar): the piston's axial waves from its material and geometry,
rather than a stiffness guessed for a split piston.

    hammer --contact--> piston.seg1 --link1-- ... -- piston.segN --oil--> breech
                            |seal.part1               |seal.partN          |mount
                          frame                     frame                frame

Default piston: steel, E = 2.1e11 Pa, rho = 7850 kg/m^3, the paper's area
A = 2.27e-2 m^2 and the length L = 241.7 kg / (rho*A) = 1.356 m that gives
the paper's m2 (an estimate of the geometry, not a paper value). The seal
friction c2 is spread evenly over the segments (SplitSeal), as the seal
runs along the piston. The piston (E*A/L = 3.5e9 N/m) is about 16 times
stiffer than the oil column (2.228e8 N/m), so the pressure is close to the
rigid-piston rig's; what the bar adds is the stress wave through the piston
(transit time L/c = 0.26 ms).
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pdbfs.components import ElasticBar, check_bar_resolution
from pdbfs.components.translational.bar import BarResolution

from .split_piston import SPLIT_SIGNALS, SplitPistonRig

#: the paper's piston and seal mass m2, kg, and the piston area, m^2
PISTON_MASS = 241.7
PISTON_AREA = 2.270e-2
STEEL_E = 2.1e11       # Pa
STEEL_RHO = 7850.0     # kg/m^3
#: length of a steel bar of the piston's area and mass, m
PISTON_LENGTH = PISTON_MASS / (STEEL_RHO * PISTON_AREA)

BAR_SIGNALS = dict(SPLIT_SIGNALS)


class BarPistonRig(SplitPistonRig):
    """The paper's rig (Table 1 values) with the piston an ElasticBar of
    ``n`` segments (``piston.L``, ``piston.A``, ``piston.E``,
    ``piston.rho``) and the seal friction ``seal.c`` spread over them; the
    rest of the rig is SplitPistonRig's.

    Parameters
    ----------
    n : int
        The number of the bar's segments (>= 1).
    law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        The contact's damping law (ImpactContact's ``law``); None: the
        paper's damping factor ``contact.D``.

    Raises
    ------
    pdbfs.ParameterError
        For n that is not a whole number >= 1.
    """

    summary_signals = BAR_SIGNALS
    name_prefix, builder = "pdbfs_bar", "bar_piston_rig"
    #: the parameters that matter most: PaperRig's and the bar's stiffness
    key_parameters = ("hammer.v0", "oil.k", "seal.c", "piston.E")

    def __init__(self, n: int = 30, law: str | None = None, **params: float):
        super().__init__(n=n, law=law, **params)

    def make_piston(self, n: int) -> ElasticBar:
        return ElasticBar(n=n, sides=True, L=PISTON_LENGTH, A=PISTON_AREA, E=STEEL_E,
                          rho=STEEL_RHO)

    def check_resolution(self, dt_out: float, params: Mapping[str, float] | None = None
                         ) -> BarResolution:
        """Warn (BarResolutionWarning) if an output interval is finer than
        the piston's segments resolve.

        Parameters
        ----------
        dt_out : float
            The output interval, s.
        params : mapping of str to float, optional
            Parameter values as ``simulate`` takes them (``piston.L``,
            ``piston.E``, ... override the defaults).

        Returns
        -------
        BarResolution
            As ``check_bar_resolution`` gives it.
        """
        mine = {k.split(".", 1)[1]: v for k, v in (params or {}).items()
                if k.startswith("piston.")}
        values = self.piston.values(mine)
        return check_bar_resolution(values, dt_out, name=self.piston.path(), stacklevel=3)


def bar_piston_rig(n: int = 30, **kw: Any) -> BarPistonRig:
    """The paper's rig with the piston an elastic steel bar.

    Parameters
    ----------
    n : int
        The bar's segments (30 by default: a segment's transit time, 8.7
        us, is then within the default output interval of 10 us).
    **kw
        ``law=``, as BarPistonRig takes it.

    Returns
    -------
    BarPistonRig
        The rig.
    """
    return BarPistonRig(n=n, **kw)

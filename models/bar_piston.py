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

from pdbfs.components import (ElasticBar, Fixed, ImpactContact, Mass, OilColumn, Spring,
                              check_bar_resolution)
from pdbfs.rig import Rig

from .split_piston import SPLIT_SIGNALS, SplitSeal, _check_n

#: the paper's piston and seal mass m2, kg, and the piston area, m^2
PISTON_MASS = 241.7
PISTON_AREA = 2.270e-2
STEEL_E = 2.1e11       # Pa
STEEL_RHO = 7850.0     # kg/m^3
#: length of a steel bar of the piston's area and mass, m
PISTON_LENGTH = PISTON_MASS / (STEEL_RHO * PISTON_AREA)

BAR_SIGNALS = dict(SPLIT_SIGNALS)


class BarPistonRig(Rig):
    """The paper's rig (Table 1 values) with the piston an ElasticBar of
    ``n`` segments (``piston.L``, ``piston.A``, ``piston.E``,
    ``piston.rho``) and the seal friction ``seal.c`` spread over them."""

    summary_signals = BAR_SIGNALS

    def __init__(self, n: int = 30, law=None, **params):
        _check_n(n, "bar_piston_rig")
        self._n = n
        self._law = law
        self.name = f"pdbfs_bar{n}"
        super().__init__(**params)

    def declare(self):
        n = self._n
        self.frame = Fixed()
        self.hammer = Mass(m=2948.4, v0=2.73)
        self.piston = ElasticBar(n=n, sides=True, L=PISTON_LENGTH, A=PISTON_AREA,
                                 E=STEEL_E, rho=STEEL_RHO)
        self.breech = Mass(m=500.0)
        self.contact = ImpactContact(law=self._law, k=5.958e10, n=1.5, D=1.595e6)
        self.oil = OilColumn(k=2.228e8, n=1.0, A=PISTON_AREA)
        self.seal = SplitSeal(n=n, c=2.556e4)
        self.mount = Spring(k=2.5e10, n=1.0)
        self.connect(self.hammer.flange_b, self.contact.flange_a)
        self.connect(self.contact.flange_b, self.piston.flange_a)
        for i in range(1, n + 1):
            self.connect(getattr(self.piston, f"side{i}"), getattr(self.seal, f"flange{i}"))
        self.connect(self.piston.flange_b, self.oil.flange_a)
        self.connect(self.oil.flange_b, self.breech.flange_a)
        self.connect(self.breech.flange_b, self.mount.flange_a)
        self.connect(self.frame.flange, self.mount.flange_b, self.seal.frame)

    @property
    def n(self) -> int:
        return self._n

    def check_resolution(self, dt_out: float, params=None):
        """Warn (BarResolutionWarning) if output every ``dt_out`` s is finer
        than the piston's segments resolve; ``params`` as in simulate
        (``piston.L`` etc. override the defaults). Returns the
        BarResolution."""
        mine = {k.split(".", 1)[1]: v for k, v in (params or {}).items()
                if k.startswith("piston.")}
        values = self.piston.values(mine)
        return check_bar_resolution(values, dt_out, name=self.piston.path(), stacklevel=3)

    def force_chain(self, res) -> list:
        """Compressive forces through the piston, top to bottom: contact,
        links 1..n-1 (springs report tension, so negated), oil; a list of
        (label, array) from a Result."""
        out = [("contact", res["contact.fc"])]
        out += [(f"link {i}", -res[f"piston.link{i}.f"]) for i in range(1, self._n)]
        return out + [("oil", res["oil.fc"])]


def bar_piston_rig(n: int = 30, **kw) -> BarPistonRig:
    """The paper's rig with the piston an elastic steel bar of ``n``
    segments (30 by default: a segment's transit time, 8.7 us, is then
    within the default output interval of 10 us); ``law=`` as in paper_rig."""
    return BarPistonRig(n=n, **kw)

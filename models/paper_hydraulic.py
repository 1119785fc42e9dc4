"""The paper's rig with its oil column built from hydraulic components: the
loading piston pushes a Piston (its housing is the breech) into a Volume of
oil, in place of the lumped spring k2.

    hammer --contact--> piston --column: Piston(A), housing = breech--> breech
                                          |port                          |mount
                                        oil: Volume(V = A*L, K)        frame
                                          |seal leak (optional): to a tank

With a constant bulk modulus ``K = k2*L/A`` (the default: 1.963 GPa for the
paper's k2, A and L = 0.2 m) and the compliance referred to the start volume
(``swept=False``, what a lumped spring is), the column is exactly the
paper's linear k2 spring, slack included: the oil starts unloaded at its
vapour pressure (``p0 = p_vap = 0``; pressures in this rig are the paper's,
above that of the unloaded column), so the pressure cannot fall below it and
a retracting piston leaves a vapour gap, as the paper's compression-only k2
does. ``swept=True`` lets the oil's volume shrink with the stroke (the
tangent modulus referred to the volume now); ``law="linear"`` makes the
modulus grow with pressure (components.hydraulic.Volume). The entrained-air
law is refused here: it needs absolute pressures, which this rig does not
use.

``leak="laminar"`` or ``"orifice"`` adds a seal leak from the oil to a tank
at 0 Pa (off by default).
"""
from __future__ import annotations

from typing import Any

from pdbfs.components.hydraulic import LaminarLeak, Orifice, Piston, Tank, Volume
from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter

from .paper import PaperRig

PAPER_HYDRAULIC_SIGNALS = {"pressure": "oil.p", "contact_force": "contact.fc",
                           "piston_displacement": "piston.s", "striker_velocity": "hammer.v"}

LEAKS = {"laminar": LaminarLeak, "orifice": Orifice}


class PaperHydraulicRig(PaperRig):
    """The paper's rig (Table 1 values) with a hydraulic oil column.
    ``law`` is the oil's bulk-modulus law (Volume), ``contact_law`` the
    contact's damping law (PaperRig's ``law``).

    Parameters
    ----------
    law : {"constant", "linear"}
        The oil's bulk-modulus law (Volume's; "air" needs absolute pressures
        and is refused here).
    swept : bool
        The oil's volume shrinks with the stroke (Volume's ``swept``).
    leak : {None, "laminar", "orifice"}
        A leak of the oil to a tank (a LaminarLeak or an Orifice); None: none.
    contact_law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        The contact's damping law (PaperRig's ``law``).
    **params : float
        The rig's own parameter: ``L``, the oil column's length, m.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown leak, or the law "air".
    """

    name = "pdbfs_hydraulic"
    summary_signals = PAPER_HYDRAULIC_SIGNALS
    page_defaults = {"calibrate": ("oil.K",), "design": ("hammer.h",),
                     "map_x": ("hammer.h", 0.1, 1.5), "map_y": ("oil.K", 1e9, 1e10)}
    #: as PaperRig's, the oil's bulk modulus standing for its stiffness
    key_parameters = ("hammer.v0", "oil.K", "seal.c")

    L = Parameter(0.2, "m", "Length of the oil column (its volume is column.A * L; at most "
                  "10 m, longer than any drop-hammer rig's)", positive=True, max=10.0,
                  tunable=False)

    def __init__(self, law: str = "constant", swept: bool = False, leak: str | None = None,
                 contact_law: str | None = None, **params: float):
        if leak is not None and leak not in LEAKS:
            raise ParameterError(f"PaperHydraulicRig: unknown seal leak {leak!r}; choose one of "
                                 + ", ".join(LEAKS) + " (or None)")
        if law == "air":
            raise ParameterError(
                "PaperHydraulicRig: law 'air' needs absolute pressures, and this rig's are the "
                "paper's, above the unloaded column; build the column with a Volume(law='air', "
                "p0=..., p_vap=...) of your own rig")
        self._modulus, self._swept, self._leak = law, swept, leak
        super().__init__(law=contact_law, **params)

    def declare_oil(self):
        self.column = Piston(support=True, A=2.270e-2)
        # K = k2*L/A with the paper's k2 = 2.228e8 N/m
        self.oil = Volume(law=self._modulus, swept=self._swept, K=2.228e8 * 0.2 / 2.270e-2,
                          p0=0.0, p_vap=0.0, dp_cav=1.0)
        self.oil.bind("V", self.column.A * self.L)
        if self._leak is not None:
            self.leak = LEAKS[self._leak]()
            self.tank = Tank(p=0.0)

    def connect_oil(self):
        self.connect(self.piston.flange_b, self.column.flange)
        self.connect(self.column.support, self.breech.flange_a)
        self.connect(self.column.port, self.oil.port)
        if self._swept:
            self.connect(self.column.q_swept, self.oil.q_swept)
        if self._leak is not None:
            self.connect(self.oil.port, self.leak.port_a)
            self.connect(self.leak.port_b, self.tank.port)


def paper_hydraulic_rig(**kw: Any) -> PaperHydraulicRig:
    """The paper's rig with its oil column as a Piston and a Volume; ``law``,
    ``swept``, ``leak`` as in PaperHydraulicRig."""
    return PaperHydraulicRig(**kw)

"""The PDBFS rig of the paper (Cho & Cha 2010, Fig. 3, Table 1): hammer,
loading piston and breech assembly, built only from the component library.

    hammer  --contact (Hertz + hysteresis)-->  piston  --oil-->  breech
                                               |seal              |mount
                                              frame              frame
"""
from __future__ import annotations

from typing import Any

from pdbfs.components import Fixed, ImpactContact, Mass, OilColumn, SealFriction, Spring
from pdbfs.rig import Rig

#: Which variable of a rig plays which role in the summary (pdbfs simulate).
PAPER_SIGNALS = {"pressure": "oil.pressure", "contact_force": "contact.fc",
                 "piston_displacement": "piston.s", "striker_velocity": "hammer.v"}


class PaperRig(Rig):
    """Pile-driver breech fatigue testing system, 3 degrees of freedom, with
    the paper's Table 1 values. Linear oil column and mount by default; set
    ``oil.n = 1.5`` (and ``mount.n``) for the other reading of Table 1.

    Parameters
    ----------
    law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        The contact's damping law (ImpactContact's ``law``); None: the
        paper's damping factor ``contact.D``.
    """

    name = "pdbfs_paper"
    summary_signals = PAPER_SIGNALS
    #: what the workbench page (pdbfs app) offers first: the parameters to
    #: calibrate and to design, and the design map's axes (name, from, to);
    #: ``hammer.h`` is the page's drop height standing for hammer.v0
    page_defaults = {"calibrate": ("oil.k",), "design": ("hammer.h",),
                     "map_x": ("hammer.h", 0.1, 1.5), "map_y": ("oil.k", 1e8, 1e9)}
    #: the parameters that matter most, as the paper found: the impact speed
    #: sets the peak, the seal's friction the duration, the oil's stiffness
    #: both (the workbench lists them first)
    key_parameters = ("hammer.v0", "oil.k", "seal.c")

    def __init__(self, law: str | None = None, **params: float):
        self._law = law
        super().__init__(**params)

    def declare(self):
        self.frame = Fixed()
        self.hammer = Mass(m=2948.4, v0=2.73)
        self.piston = Mass(m=241.7)
        self.breech = Mass(m=500.0)
        self.contact = ImpactContact(law=self._law, k=5.958e10, n=1.5, D=1.595e6,
                                     **self.options("contact"))
        self.declare_oil()
        self.seal = SealFriction(c=2.556e4, **self.options("seal"))
        self.mount = Spring(k=2.5e10, n=1.0)
        self.connect(self.hammer.flange_b, self.contact.flange_a)
        self.connect(self.contact.flange_b, self.piston.flange_a, self.seal.flange_b)
        self.connect_oil()
        self.connect(self.breech.flange_b, self.mount.flange_a)
        self.connect(self.frame.flange, self.mount.flange_b, self.seal.flange_a)

    def options(self, name: str) -> dict[str, Any]:
        """Constructor options of the component ``name`` (``"contact"``,
        ``"seal"``, ``"oil"``) besides the paper's values: none here; a
        subclass gives heat ports and temperature laws (paper-thermal).

        Parameters
        ----------
        name : str
            The component's name in the rig.

        Returns
        -------
        dict
            Keyword arguments for its constructor.
        """
        return {}

    # the oil column between piston and breech: a subclass may build it otherwise
    def declare_oil(self) -> None:
        """Declare the oil column ``oil`` (here an OilColumn: the paper's spring k2)."""
        self.oil = OilColumn(k=2.228e8, n=1.0, A=2.270e-2, **self.options("oil"))

    def connect_oil(self) -> None:
        """Connect ``oil`` between the piston's lower face and the breech."""
        self.connect(self.piston.flange_b, self.oil.flange_a)
        self.connect(self.oil.flange_b, self.breech.flange_a)


def paper_rig(**kw: Any) -> PaperRig:
    """The paper's rig; ``law=`` picks a damping law for the contact."""
    return PaperRig(**kw)

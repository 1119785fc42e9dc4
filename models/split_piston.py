"""The paper's rig with the loading piston and seal assembly split into N
masses (the paper's conclusion: "m2 needs to be split into several separated
masses in order to obtain more detailed information about transferring
process of impact force").

    hammer --contact--> piston.p1 --link1-- piston.p2 -- ... -- piston.pN --oil--> breech
                            |seal.part1        |seal.part2          |seal.partN       |mount
                          frame              frame                frame             frame

The N pieces share the mass ``piston.m`` equally and the seal friction
``seal.c`` equally (the seal runs along the piston); neighbours are joined by
linear springs ``piston.k_link = N * piston.k_axial`` (a bar of axial stiffness
EA/L cut into N pieces of length L/N, joined centre to centre).

The default ``piston.k_axial`` = 3.5e9 N/m is that of a steel bar
(E = 2.1e11 Pa) of the piston's area 2.27e-2 m^2 and the length that gives
241.7 kg at 7850 kg/m^3 (about 1.36 m): an estimate, not a paper value.

With N = 1 there is no link and the rig is the paper's 3-DOF rig, equation
for equation (its pressure agrees with the paper rig's to 1e-9).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pdbfs.components import (Fixed, ImpactContact, Mass, MassChain, OilColumn, SealFriction,
                              Spring)
from pdbfs.errors import ParameterError
from pdbfs.modelling import Component, Flange, Parameter
from pdbfs.rig import Rig

if TYPE_CHECKING:
    import casadi as ca
    import numpy as np

    import pdbfs

#: Axial stiffness EA/L of the whole piston, N/m (steel, see module docstring).
K_AXIAL = 3.5e9


def _check_n(n, who):
    # no upper limit: structural analysis is near-linear in n (thousands are fine);
    # what the compilers cannot take is refused where they run, with its size
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ParameterError(f"{who}: n = {n!r} must be a whole number of piston pieces >= 1")


class SplitPiston(MassChain):
    """A piston of mass ``m`` cut into ``n`` equal rigid pieces ``p{i}``
    joined by linear springs ``link{i}`` (a MassChain). ``flange_a`` is the
    struck face (piece 1), ``flange_b`` the face on the oil (piece n);
    ``side{i}`` is a flange on piece i (1-based) for side forces such as
    seal friction. The variable ``s`` is the position of the centre of mass.

    Parameters
    ----------
    n : int
        The number of pieces (>= 1).
    **params : float or casadi.SX
        Values of its declared parameters (``m``, ``k_axial``), SI units.

    Raises
    ------
    pdbfs.ParameterError
        For ``n`` that is not a whole number >= 1.
    """

    m = Parameter(241.7, "kg", "Total mass of the piston and seal assembly (the paper's m2)",
                  positive=True, tunable=False)
    k_axial = Parameter(K_AXIAL, "N/m", "Axial stiffness EA/L of the whole piston; each of "
                        "the n-1 links has n*k_axial", positive=True)
    piece_prefix, body = "p", "piston"

    def __init__(self, n: int = 4, **params: float | ca.SX):
        _check_n(n, "SplitPiston")
        super().__init__(n, sides=True, **params)

    def total_mass(self) -> ca.SX:
        return self.m

    def total_stiffness(self) -> ca.SX:
        return self.k_axial


class SplitSeal(Component):
    """Seal friction ``c`` spread equally over ``n`` pieces: ``part{i}`` acts
    between ``frame`` and ``flange{i}``.

    Connectors: ``frame`` and ``flange1`` .. ``flange{n}``.

    Parameters
    ----------
    n : int
        The number of parts (>= 1).
    **params : float or casadi.SX
        Values of its declared parameters (``c``), SI units.

    Raises
    ------
    pdbfs.ParameterError
        For ``n`` that is not a whole number >= 1.
    """

    c = Parameter(2.556e4, "N.s/m", "Total viscous friction of the seal (the paper's c2)",
                  min=0.0)

    def __init__(self, n: int = 4, **params: float | ca.SX):
        _check_n(n, "SplitSeal")
        self._n = n
        super().__init__(**params)

    def declare(self):
        n = self._n
        self.frame = Flange()
        for i in range(1, n + 1):
            setattr(self, f"flange{i}", Flange())
            part = SealFriction(c=self.c / n if n > 1 else self.c)
            setattr(self, f"part{i}", part)
            self.connect(self.frame, part.flange_a)
            self.connect(part.flange_b, getattr(self, f"flange{i}"))


SPLIT_SIGNALS = {"pressure": "oil.pressure", "contact_force": "contact.fc",
                 "piston_displacement": "piston.s", "striker_velocity": "hammer.v"}


class SplitPistonRig(Rig):
    """The paper's rig (Table 1 values) with the piston and seal split into
    ``n`` masses. Parameters as in PaperRig, plus ``piston.k_axial``.

    Parameters
    ----------
    n : int
        The number of pieces (>= 1; 1 is the paper's rig).
    law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        The contact's damping law (ImpactContact's ``law``); None: the
        paper's damping factor ``contact.D``.

    Raises
    ------
    pdbfs.ParameterError
        For n that is not a whole number >= 1.
    """

    summary_signals = SPLIT_SIGNALS
    #: what the workbench page (pdbfs app) offers first, as PaperRig's
    page_defaults = {"calibrate": ("oil.k",), "design": ("hammer.h",),
                     "map_x": ("hammer.h", 0.1, 1.5), "map_y": ("oil.k", 1e8, 1e9)}
    #: the parameters that matter most: PaperRig's and the piston's stiffness
    key_parameters = ("hammer.v0", "oil.k", "seal.c", "piston.k_axial")
    #: the rig's name is this prefix and n; who checks n in error messages
    name_prefix, builder = "pdbfs_split", "split_piston_rig"

    def __init__(self, n: int = 4, law: str | None = None, **params: float):
        _check_n(n, self.builder)
        self._n = n
        self._law = law
        self.name = f"{self.name_prefix}{n}"
        super().__init__(**params)

    def make_piston(self, n: int) -> Component:
        """The piston: flanges flange_a (struck), flange_b (on the oil) and
        side1..side{n} (the seal's). Subclasses put another piston here.

        Parameters
        ----------
        n : int
            The number of pieces.

        Returns
        -------
        Component
            The piston (here a SplitPiston).
        """
        return SplitPiston(n=n)

    def declare(self):
        n = self._n
        self.frame = Fixed()
        self.hammer = Mass(m=2948.4, v0=2.73)
        self.piston = self.make_piston(n)
        self.breech = Mass(m=500.0)
        self.contact = ImpactContact(law=self._law, k=5.958e10, n=1.5, D=1.595e6)
        self.oil = OilColumn(k=2.228e8, n=1.0, A=2.270e-2)
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
        """The number of pieces the piston and seal are split into."""
        return self._n

    def force_chain(self, res: pdbfs.Result) -> list[tuple[str, np.ndarray]]:
        """The compressive forces through the piston, top to bottom: the
        contact, the links 1 .. n-1 (springs report tension, so negated), the oil.

        Parameters
        ----------
        res : Result
            A run of this rig.

        Returns
        -------
        list of tuple
            (label, force in N on the run's output grid), top to bottom.
        """
        out = [("contact", res["contact.fc"])]
        out += [(f"link {i}", -res[f"piston.link{i}.f"]) for i in range(1, self._n)]
        return out + [("oil", res["oil.fc"])]


def split_piston_rig(n: int = 4, **kw: Any) -> SplitPistonRig:
    """The paper's rig with piston and seal split into masses joined by
    stiff springs.

    Parameters
    ----------
    n : int
        The number of pieces (1: the paper's rig).
    **kw
        ``law=``, as SplitPistonRig takes it.

    Returns
    -------
    SplitPistonRig
        The rig.
    """
    return SplitPistonRig(n=n, **kw)

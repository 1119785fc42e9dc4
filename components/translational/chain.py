"""MassChain: the shared part of a body cut into a row of masses (a split
piston, an elastic bar): n equal rigid pieces joined by n-1 linear springs,
composed from Mass and Spring (and a Damper beside each Spring for a body
with material damping). A subclass says what the whole body weighs, how
stiff it is and how it damps; the chain does the rest."""
from __future__ import annotations

from typing import TYPE_CHECKING

from pdbfs.modelling import Component, Flange, Variable, eq

from .mass import Mass
from .springs import Damper, Spring

if TYPE_CHECKING:
    import casadi as ca


class MassChain(Component):
    """``n`` pieces ``{piece_prefix}{i}`` (i = 1..n, 1 at ``flange_a``), each
    a Mass ``m = total_mass()/n``, joined by Springs ``link{i}`` of
    ``k = n*total_stiffness()`` (a body of axial stiffness EA/L cut into pieces
    of length L/n, joined centre to centre), each with a Damper ``damper{i}``
    of ``c = n*total_damping()`` beside it where the body damps (Kelvin-Voigt:
    the damping proportional to the stiffness). ``flange_b`` is on piece n;
    with ``sides`` a flange ``side{i}`` on each piece takes side forces
    (seal friction). ``s`` is the position of the centre of mass.

    A base: a subclass says what the whole body weighs (``total_mass``), how
    stiff it is (``total_stiffness``) and, if it damps, how much
    (``total_damping``).

    Connectors: ``flange_a`` (on piece 1), ``flange_b`` (on piece n), and
    ``side1`` .. ``side{n}`` with ``sides``.

    Parameters
    ----------
    n : int
        The number of pieces (1 or more).
    sides : bool
        Give each piece a side flange.
    **params : float or casadi.SX
        Values of the subclass's declared parameters, SI units.
    """

    #: attribute prefix of the pieces, and what ``s`` is the centre of
    piece_prefix = "p"
    body = "body"

    def __init__(self, n: int, sides: bool = True, **params: float | ca.SX):
        self._n = n
        self._sides = bool(sides)
        super().__init__(**params)

    @property
    def n(self) -> int:
        """The number of pieces."""
        return self._n

    def total_mass(self) -> ca.SX:
        """Mass of the whole body (an expression of the parameters), kg."""
        raise NotImplementedError

    def total_stiffness(self) -> ca.SX:
        """Axial stiffness EA/L of the whole body, N/m."""
        raise NotImplementedError

    def total_damping(self) -> ca.SX | None:
        """Axial damping coefficient of the whole body (the viscous force per
        unit rate of its stretch, N.s/m), or None for a body without material
        damping (no dampers: the default)."""
        return None

    def declare(self):
        n = self._n
        self.flange_a = Flange()
        self.flange_b = Flange()
        self.s = Variable("m", f"Position of the {self.body}'s centre of mass (positive down)",
                          output=True)
        mass = self.total_mass()
        for i in range(1, n + 1):
            setattr(self, f"{self.piece_prefix}{i}", Mass(m=mass / n if n > 1 else mass))
            if self._sides:
                setattr(self, f"side{i}", Flange())
        for i in range(1, n):
            setattr(self, f"link{i}", Spring(k=self.total_stiffness() * n, n=1.0))
        damping = self.total_damping()
        if damping is not None:
            for i in range(1, n):
                setattr(self, f"damper{i}", Damper(c=damping * n))
        for i in range(1, n + 1):
            above = [self.flange_a] if i == 1 else self._joint_ends(i - 1, "flange_b")
            sides = [getattr(self, f"side{i}")] if self._sides else []
            self.connect(*above, self.piece(i).flange_a, *sides)
            below = [self.flange_b] if i == n else self._joint_ends(i, "flange_a")
            self.connect(self.piece(i).flange_b, *below)

    def _joint_ends(self, i: int, end: str) -> list:
        """The ``end`` flanges of the joint between pieces i and i + 1: its
        spring's, and its damper's where the body damps."""
        damper = self.damper(i)
        return [getattr(self.link(i), end)] + ([getattr(damper, end)] if damper else [])

    def piece(self, i: int) -> Mass:
        """One of the pieces.

        Parameters
        ----------
        i : int
            Its number, 1 .. n (1 at flange_a).

        Returns
        -------
        Mass
            The piece.
        """
        return getattr(self, f"{self.piece_prefix}{i}")

    def link(self, i: int) -> Spring:
        """One of the springs that join the pieces.

        Parameters
        ----------
        i : int
            Its number, 1 .. n - 1: the spring between pieces i and i + 1.

        Returns
        -------
        Spring
            The spring.
        """
        return getattr(self, f"link{i}")

    def damper(self, i: int) -> Damper | None:
        """One of the dampers beside the springs, where the body damps.

        Parameters
        ----------
        i : int
            Its number, 1 .. n - 1: the damper between pieces i and i + 1.

        Returns
        -------
        Damper or None
            The damper; None for a body without material damping.
        """
        return getattr(self, f"damper{i}", None)

    def equations(self):
        n = self._n
        return [eq(self.s, sum(self.piece(i).s for i in range(1, n + 1)) / n)]

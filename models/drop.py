"""The paper's rig with gravity and a drop height: the hammer is released at
rest a height ``h`` above the piston, falls, strikes, rebounds and strikes
again (PHYSICS.md: "a rig variant with gravity and a drop height").

    hammer (released at rest, h above the piston face)
      | free fall under gravity, then contact (Hertz + hysteresis)
    piston --oil--> breech --mount--> frame
      |seal
    frame

Gravity acts on every body. The piston and the breech start in static
equilibrium under their weights (the oil column carries the piston, the mount
carries piston and breech, wherever the frame and the mount's unstretched
length put them), so nothing moves before the hammer arrives at
``t = sqrt(2 h / g)`` with ``v = sqrt(2 g h)`` (paper §4.1.1). ``h`` is the
distance the hammer falls before the contact closes: with a clearance
``contact.gap`` (the contact closes when the hammer passes the piston by
``gap``) the hammer starts at ``s_piston + gap - h``.

The default ``h = 0.38 m`` gives Table 1's 2.73 m/s (the paper's test
section quotes h = 0.254 m, which would give 2.23 m/s; the two do not agree).

Rig-level parameters: ``h`` (drop height) and ``g`` (gravity, shared by all
bodies). With ``law=`` the contact's ``v_impact`` is bound to
``sqrt(2 g h)``, so the damping factor is tuned to the first blow.

Every blow is reported by the summary: ``impact_count``, ``impact_times``,
``impact_peak_pressures`` (the summary role ``impact_indentation``).

``DropRestRig`` (``drop_rig(rest=True)``, ``--rig drop-rest``): the hammer
rests on the piston instead, and the whole stack starts in static
equilibrium under gravity, solved at initialization (every state free,
``der(x) = 0`` as the rig's initial equations; the contact carries the
hammer's weight with the indentation ``(m g / k)^(1/n)``). It has no drop
height, and its bodies' start velocities are 0 (solved, not set).
"""
from __future__ import annotations

from typing import Any

import casadi as ca

from pdbfs.components import Gravity
from pdbfs.components.laws import STANDARD_GRAVITY
from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter, der

from .paper import PAPER_SIGNALS, PaperRig

DROP_SIGNALS = {**PAPER_SIGNALS, "impact_indentation": "contact.d"}


#: gravity, a parameter of both rigs (declared in each: h comes first in the drop rig's list)
GRAVITY = Parameter(STANDARD_GRAVITY, "m/s2", "Gravitational acceleration on every body",
                    min=0.0, tunable=False)


class _GravityRig(PaperRig):
    """The paper's rig with the weight of every body (a subclass declares
    ``g = GRAVITY``); the piston and the breech start at rest in static
    equilibrium (``stack()``)."""

    summary_signals = DROP_SIGNALS
    #: what ``pdbfs simulate --rig drop`` runs unless told otherwise: three blows
    default_t_end = 1.5
    default_n_out = 30001

    def declare(self):
        super().declare()   # the paper's rig ...
        g = self.g
        # ... with the weight of every body
        self.hammer_weight = Gravity(m=self.hammer.m, g=g)
        self.piston_weight = Gravity(m=self.piston.m, g=g)
        self.breech_weight = Gravity(m=self.breech.m, g=g)
        self.connect(self.hammer_weight.flange, self.hammer.flange_a)
        self.connect(self.piston_weight.flange, self.piston.flange_a)
        self.connect(self.breech_weight.flange, self.breech.flange_a)

    def stack(self, load):
        """The positions of the breech and the piston in static equilibrium,
        which become their start positions: the mount compressed by
        everything above it from its unstretched position ``frame.s0 -
        mount.s_rel0``, the oil column by what the piston carries (n-th
        roots for exponents n != 1).

        Parameters
        ----------
        load : float or casadi.SX
            The force on the piston besides the weights, N (an expression of
            the parameters: the hammer's weight when it rests there).

        Returns
        -------
        tuple of casadi.SX
            (the breech's position, the piston's), m.
        """
        g = self.g
        w2 = self.piston.m * g + load
        w23 = w2 + self.breech.m * g
        s3 = self.frame.s0 - self.mount.s_rel0 + (w23 / self.mount.k) ** (1.0 / self.mount.n)
        s2 = s3 + (w2 / self.oil.k) ** (1.0 / self.oil.n)
        self.breech.bind("s0", s3)
        self.piston.bind("s0", s2)
        return s3, s2


class DropRig(_GravityRig):
    """PDBFS with gravity, the hammer dropped from height ``h``; Table 1
    values otherwise. Simulate it over about a second to see the blows.

    Parameters
    ----------
    law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        The contact's damping law (ImpactContact's ``law``); None: the
        paper's damping factor ``contact.D``.
    **params : float
        The rig's own parameter: h, the drop height, m.

    Raises
    ------
    pdbfs.ParameterError
        For rest=: the hammer resting on the piston is DropRestRig.
    """

    name = "pdbfs_drop"
    page_defaults = {"calibrate": ("oil.k",), "design": ("h",),
                     "map_x": ("h", 0.1, 1.5), "map_y": ("oil.k", 1e8, 1e9)}
    #: as PaperRig's, the drop height standing for the impact speed
    key_parameters = ("h", "oil.k", "seal.c")

    h = Parameter(0.38, "m", "Drop height: the distance the hammer falls from its release "
                  "(at rest) to the contact", positive=True, tunable=False)
    g = GRAVITY

    def __init__(self, law: str | None = None, **params: float):
        if "rest" in params:
            raise ParameterError("DropRig: the hammer resting on the piston is its own rig, "
                                 "DropRestRig (drop_rig(rest=True)), which has no drop height")
        super().__init__(law=law, **params)

    def declare(self):
        super().declare()
        _, s2 = self.stack(0.0)
        # released at rest: the contact closes at hammer.s = piston.s + gap,
        # a fall of h from here
        self.hammer.bind("v0", 0.0)
        self.hammer.bind("s0", s2 + self.contact.gap - self.h)
        if self._law is not None:
            self.contact.bind("v_impact", ca.sqrt(2.0 * self.g * self.h))


class DropRestRig(_GravityRig):
    """The drop rig with the hammer resting on the piston: the whole stack
    starts in static equilibrium under gravity, solved at initialization.

    Parameters
    ----------
    law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        The contact's damping law (ImpactContact's ``law``); None: the
        paper's damping factor ``contact.D``.
    """

    name = "pdbfs_drop_rest"
    page_defaults = {"calibrate": ("oil.k",), "design": ("hammer.m",),
                     "map_x": ("hammer.m", 1000.0, 5000.0), "map_y": ("oil.k", 1e8, 1e9)}
    key_parameters = ("hammer.m", "oil.k", "seal.c")     # no drop height at rest

    g = GRAVITY

    def declare(self):
        super().declare()
        g = self.g
        # the guess is the equilibrium of these laws: the contact indented by
        # the hammer's weight, the piston and the mount carrying it too
        _, s2 = self.stack(self.hammer.m * g)
        sink = (self.hammer.m * g / self.contact.k) ** (1.0 / self.contact.n)
        self.hammer.bind("s0", s2 + self.contact.gap + sink)
        for body in (self.hammer, self.piston, self.breech):
            body.free("s", "v")
            # at rest, solved (der(s) = v = 0): not a setting (0 * g is the number 0,
            # computed, so that setting it is refused rather than ignored)
            body.bind("v0", 0.0 * g)

    def initial_equations(self):
        return [der(x) for body in (self.hammer, self.piston, self.breech)
                for x in (body.s, body.v)]


def drop_rig(rest: bool = False, **kw: Any) -> DropRig | DropRestRig:
    """The rig with gravity, the hammer dropped from ``h`` (a parameter,
    default 0.38 m: 2.73 m/s at impact).

    Parameters
    ----------
    rest : bool
        The hammer rests on the piston instead, the start solved at
        equilibrium (DropRestRig, no ``h``).
    **kw
        ``law=``, and for the dropped hammer ``h=``, as the rig takes them.

    Returns
    -------
    DropRig or DropRestRig
        The rig.
    """
    return DropRestRig(**kw) if rest else DropRig(**kw)

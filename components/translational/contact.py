"""Impact contact: Hertz elasticity plus Hunt-Crossley hysteresis damping."""
from __future__ import annotations

import casadi as ca

from pdbfs.errors import ParameterError
from pdbfs.modelling import HeatPort, Parameter, Variable, eq

from ..functions import positive_power
from ..thermal.interfaces import PartialConditionalHeatPort, _flag
from .interfaces import PartialCompression, PartialCompliantWithVelocity
from ..laws import DAMPING_LAWS


class HertzContact(PartialCompression):
    """Hertz contact ``fc = k*d^n`` for indentation ``d = -s_rel - gap > 0``,
    zero otherwise. flange_a is the striking (upper) body.

    Connectors: ``flange_a`` (the striking body), ``flange_b`` (the struck one).
    """

    k = Parameter(5.958e10, "N/m^1.5", "Contact stiffness (unit N/m^n)", positive=True)
    n = Parameter(1.5, "1", "Hertz exponent (1.5 for spheres)", min=1.0,
                  tunable=False)
    gap = Parameter(0.0, "m", "Clearance: contact starts when flange_a passes flange_b by gap",
                    tunable=False)

    def equations(self):
        return super().equations() + [
            eq(self.d, -self.s_rel - self.gap),
            eq(self.fc, self.k * positive_power(self.d, self.n))]

    def events(self):
        return [(self.d, "indentation", "contact onset or separation")]


class HuntCrossleyDamper(PartialConditionalHeatPort, PartialCompliantWithVelocity):
    """The dissipative part of an impact, ``fc = D*d^n*der(d)`` while in
    contact. Beside a HertzContact of stiffness ``k`` it is clamped at
    ``-k*d^n`` so that the combined force never pulls.

    Give ``D`` directly, or ``law=`` one of 'lankarani-nikravesh',
    'hunt-crossley', 'flores' with parameters ``e`` (restitution) and
    ``v_impact``: ``D`` is then computed from them and ``k``.

    ``heat_port=True``: the power it dissipates, ``fc*der(d)`` (the
    hysteresis loop's energy, and while the force is limited the elastic
    energy it then takes), leaves through ``heat_port``.

    Connectors: ``flange_a`` (the striking body), ``flange_b`` (the struck
    one); ``heat_port`` with ``heat_port=True``.

    Parameters
    ----------
    law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        Compute ``D`` from ``k``, the restitution ``e`` and the impact speed
        ``v_impact`` (two more parameters); None: ``D`` is given.
    heat_port : bool
        Give the component a heat port that takes its dissipated power.
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown law.
    """

    D = Parameter(1.595e6, "N.s/m^2.5", "Hysteresis damping factor (unit N.s/m^(n+1))", min=0.0)
    k = Parameter(0.0, "N/m^1.5", "Stiffness of the elastic part beside it, for the "
                  "no-pull clamp (0: the damper alone never pulls)", min=0.0)
    n = Parameter(1.5, "1", "Indentation exponent", min=1.0, tunable=False)
    gap = Parameter(0.0, "m", "Clearance, as in HertzContact", tunable=False)

    def __init__(self, law: str | None = None, heat_port: bool = False,
                 **params: float | ca.SX):
        if law is not None and law not in DAMPING_LAWS:
            raise ParameterError(f"HuntCrossleyDamper: unknown damping law {law!r}; "
                                 f"choose one of {', '.join(DAMPING_LAWS)}")
        self._law = law
        super().__init__(heat_port=heat_port, **params)

    def declare(self):
        super().declare()
        self.d = Variable("m", "Indentation")
        self.fc = Variable("N", "Compressive damping force", output=True)
        if self._law is not None:
            self.e = Parameter(0.95, "1", "Coefficient of restitution", min=0.0, max=1.0,
                               positive=True)
            self.v_impact = Parameter(2.73, "m/s", "Impact velocity the law is tuned for",
                                      positive=True)
            self.bind("D", DAMPING_LAWS[self._law](self.k, self.e, self.v_impact))

    def dissipated_power(self):
        return self.f * self.v_rel

    def equations(self):
        dn = positive_power(self.d, self.n)
        return super().equations() + [
            eq(self.d, -self.s_rel - self.gap),
            eq(self.fc, ca.fmax(self.D * dn * (-self.v_rel), -self.k * dn)),
            eq(self.fc, -self.f)]

    def events(self):
        return [(self.k - self.D * self.v_rel, "force_sign",
                 "the damping force reaches -k*d^n (the contact would pull): the force is limited "
                 "from here")]


class ImpactContact(PartialCompression):
    """Contact = HertzContact + HuntCrossleyDamper in parallel; the combined
    force ``fc`` never pulls. ``law`` as in HuntCrossleyDamper: with the
    default, ``fc = k*d^n + D*d^n*der(d)`` while in contact, at least 0.

    ``heat_port=True``: the damping's dissipated power, ``loss_power``,
    leaves through ``heat_port`` (the Hertz part stores and returns its
    energy).

    Connectors: ``flange_a`` (the striking body), ``flange_b`` (the struck
    one); ``heat_port`` with ``heat_port=True``.

    Parameters
    ----------
    law : {None, "lankarani-nikravesh", "hunt-crossley", "flores"}
        Compute ``D`` from ``k``, the restitution ``e`` and the impact speed
        ``v_impact`` (two more parameters); None: ``D`` is given.
    heat_port : bool
        Give the contact a heat port that takes the damping's dissipated power.
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    k = HertzContact.k
    n = HertzContact.n
    gap = HertzContact.gap
    D = HuntCrossleyDamper.D

    def __init__(self, law: str | None = None, heat_port: bool = False,
                 **params: float | ca.SX):
        self._law = law
        self._heat_port = _flag("ImpactContact", "heat_port", heat_port)
        super().__init__(**params)

    def declare(self):
        super().declare()
        self.hertz = HertzContact(k=self.k, n=self.n, gap=self.gap)
        self.damping = HuntCrossleyDamper(law=self._law, k=self.k, n=self.n, gap=self.gap,
                                          D=self.D, heat_port=self._heat_port)
        if self._heat_port:
            self.heat_port = HeatPort("Where the damping's dissipated power leaves the contact")
            self.loss_power = Variable("W", "Power dissipated, leaving through heat_port",
                                       output=True)
        if self._law is not None:
            # expose e and v_impact here; D becomes a calculated parameter
            self.e = Parameter(0.95, "1", "Coefficient of restitution", min=0.0, max=1.0,
                               positive=True)
            self.v_impact = Parameter(2.73, "m/s", "Impact velocity the law is tuned for",
                                      positive=True)
            self.damping.bind("e", self.e)
            self.damping.bind("v_impact", self.v_impact)
            self.bind("D", self.damping.D)
        self.connect(self.flange_a, self.hertz.flange_a, self.damping.flange_a)
        self.connect(self.flange_b, self.hertz.flange_b, self.damping.flange_b)
        if self._heat_port:
            self.connect(self.heat_port, self.damping.heat_port)

    def equations(self):
        # the composite's own flange forces come from the connections
        eqs = [eq(self.s_rel, self.flange_b.s - self.flange_a.s),
               eq(self.f, self.hertz.f + self.damping.f),
               eq(self.fc, -self.f),
               eq(self.d, self.hertz.d)]
        return eqs + ([eq(self.loss_power, self.damping.loss_power)] if self._heat_port else [])

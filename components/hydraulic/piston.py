"""Where the domains meet: a piston turns pressure into force and motion
into flow."""
from pdbfs.errors import ParameterError
from pdbfs.modelling import Component, Flange, HydraulicPort, Parameter, SignalOutput, \
    Variable, der, eq

from .volume import Volume


class Piston(Component):
    """A massless piston of area ``A``: flange ``flange`` (the rod), port
    ``port`` (its chamber), and with ``support=True`` a flange ``support``
    (the housing, which the oil pushes the other way); without it the housing
    is fixed.

    The chamber lies on the +x side of the piston face: moving the flange
    by +x relative to the housing sweeps ``A*v`` into the chamber (``port.q
    = -A*v``), and the oil pushes the flange back with ``f = p*A``. The
    output ``q_swept = A*v`` tells a Volume with ``swept=True`` that its
    walls move (connect ``piston.q_swept`` to ``volume.q_swept``, or use a
    Cylinder).

    Connectors: ``flange``, ``port``, the signal output ``q_swept``, and
    ``support`` with ``support=True``.

    Parameters
    ----------
    support : bool
        Give the housing a flange of its own (else it is fixed).
    **params : float or casadi.SX
        Values of its declared parameters (``A``), SI units.
    """

    A = Parameter(2.270e-2, "m2", "Piston area", positive=True, tunable=False)

    def __init__(self, support: bool = False, **params):
        self._support = support
        super().__init__(**params)

    def declare(self):
        self.flange = Flange()
        self.port = HydraulicPort()
        if self._support:
            self.support = Flange()
        self.q_swept = SignalOutput("m3/s", "Volume swept into the chamber per second")
        self.v = Variable("m/s", "Velocity of the piston into its chamber, relative to the "
                          "housing")
        self.f = Variable("N", "Force of the oil on the piston, pushing it out of the chamber",
                          output=True)

    def equations(self):
        v = der(self.flange.s) - (der(self.support.s) if self._support else 0.0)
        eqs = [eq(self.v, v),
               eq(self.port.q, -self.A * self.v),
               eq(self.f, self.port.p * self.A),
               eq(self.flange.f, self.f),
               eq(self.q_swept.value, self.A * self.v)]
        if self._support:
            eqs.append(eq(self.support.f, -self.f))
        return eqs


class Cylinder(Component):
    """A Piston over its own chamber (a Volume with ``swept=True``): the
    chamber's volume ``V`` (at the start) shrinks as the piston moves in,
    ``der(chamber.Vc) = -A*piston.v`` (the piston's speed into it).
    Flange ``flange``, port ``port`` (closable: unconnected, the chamber is
    sealed), ``support`` with ``support=True``; ``law`` as in Volume. The
    chamber's other parameters (``p_vap``, ``dp_cav``, the law's own such as
    ``K1``) may be given here too; they stay on ``chamber``.

    Connectors: ``flange``, ``port``, and ``support`` with ``support=True``.

    Parameters
    ----------
    law : {"constant", "linear", "air"}
        The chamber's bulk-modulus law, as in Volume.
    support : bool
        Give the housing a flange of its own (else it is fixed).
    **params : float or casadi.SX
        Values of its declared parameters (``A``, ``V``, ``K``, ``p0``) and
        of the chamber's others, SI units.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown law or a parameter the chamber does not take.
    """

    A = Piston.A
    V = Volume.V
    K = Volume.K
    p0 = Volume.p0

    def __init__(self, law: str = "constant", support: bool = False, **params):
        self._law, self._support = law, support
        own = {"A", "V", "K", "p0"}
        self._chamber_params = {n: params.pop(n) for n in list(params) if n not in own}
        super().__init__(**params)

    def declare(self):
        self.flange = Flange()
        self.port = HydraulicPort(closable=True)
        self.piston = Piston(support=self._support, A=self.A)
        try:
            self.chamber = Volume(law=self._law, swept=True, V=self.V, K=self.K, p0=self.p0,
                                  **self._chamber_params)
        except ParameterError as e:
            raise ParameterError(f"Cylinder: {e}") from None
        self.connect(self.flange, self.piston.flange)
        self.connect(self.port, self.piston.port, self.chamber.port)
        self.connect(self.piston.q_swept, self.chamber.q_swept)
        if self._support:
            self.support = Flange()
            self.connect(self.support, self.piston.support)

"""A chamber of oil: compressibility, cavitation, and walls that move."""
from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter, SignalInput, State, Variable, der, eq

from .interfaces import PartialOnePort
from .laws import ATMOSPHERE, bulk_modulus_air, bulk_modulus_linear, smooth_ramp

#: bulk-modulus laws a Volume offers (``law=``)
BULK_MODULUS_LAWS = ("constant", "linear", "air")
#: the parameters each law adds (declared in declare(), settable in the constructor)
LAW_PARAMETERS = {"constant": (), "linear": ("K1",), "air": ("alpha", "n_air", "p_air")}


class Volume(PartialOnePort):
    """Oil in a chamber of volume ``V`` with bulk modulus ``K``, start
    pressure ``p0``; one port ``port`` (closable: left unconnected, the
    chamber is sealed). Its pressure is ``p``.

    Mass balance with a tangent bulk modulus ``K(p) = rho dp/drho``:

        (Vc / K(p)) * der(p_law) = port.q

    where ``Vc`` is the chamber's volume now and ``port.q`` counts the oil
    entering and the volume pushed in by pistons alike (a Piston's port
    delivers ``A*v``). ``Vc`` is ``V`` unless ``swept=True``: then the input
    ``q_swept`` (m3/s, the rate at which walls sweep volume into the
    chamber, a Piston's output of the same name) makes it a state,
    ``der(Vc) = -q_swept``. Without it the compliance is referred to the
    start volume ``V``, the linear spring ``k = K*A^2/V`` of a lumped model
    such as the paper's k2.

    ``law``: ``"constant"`` K; ``"linear"`` ``K + K1*p``; ``"air"``
    entrained air (laws.bulk_modulus_air: Merritt 1967, as compared by
    Gholizadeh, Burton & Schoenau 2012), parameters ``alpha``, ``n_air``,
    ``p_air``.

    Cavitation: ``p_law`` is the pressure the compression law gives; when it
    falls below the vapour pressure ``p_vap``, the missing volume is vapour
    and the pressure stays at ``p_vap``: ``p = p_vap + smooth_ramp(p_law -
    p_vap, dp_cav)``, exact outside ``p_vap +- dp_cav``, at most
    ``dp_cav/4`` off inside, never below ``p_vap >= 0`` (no negative absolute
    pressure); oil returning first fills the vapour volume. Below the clamp
    the vapour volume is ``(Vc/K(p_vap))*(p_vap - p_law)``; with moving walls
    the rate gains ``q_swept*(p_law - p)`` (zero above the clamp), so that the
    oil's mass balance is exact there too, while oil flows and walls move.
    ``cavitation=False`` drops the clamp (``p = p_law``, which may go negative): two such
    volumes joined directly become one (their pressures are aliases, an ODE
    for every back end). ``steady_start=True``: the start pressure is solved
    at initialization so that no oil flows in (``p0`` is then a guess): a
    line in equilibrium with its supply. Joined cavitating volumes are a constraint between
    states that the compiler reduces by one differentiation: all but one of
    their ``p_law`` become algebraic (their start values are then only
    guesses), the rig needs IDAS (backend "casadi"), and the reduction
    breaks down where both cavitate (their vapour volumes are then not
    determined).

    Connectors: ``port`` (closable); with ``swept=True`` the signal input
    ``q_swept``.

    Parameters
    ----------
    law : {"constant", "linear", "air"}
        The bulk-modulus law (``"linear"`` adds ``K1``; ``"air"`` adds
        ``alpha``, ``n_air`` and ``p_air``).
    swept : bool
        Walls sweep volume into the chamber at the rate of the input
        ``q_swept``: the chamber's volume is a state.
    cavitation : bool
        Clamp the pressure at the vapour pressure (False: no clamp).
    steady_start : bool
        Solve the start pressure so that no oil flows in at t = 0 (``p0`` is
        then a guess).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them, and the law's), SI units.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown law, or a parameter of another law.
    """

    pressure_bound = {"stores": ("p",)}    # its start pressure (modelling.pressure_bound)

    closable = True
    V = Parameter(1e-3, "m3", "Chamber volume (at the start, if pistons sweep it)",
                  positive=True, tunable=False)
    K = Parameter(1.5e9, "Pa", "Bulk modulus of the oil (at p = 0 for law 'linear', of the "
                  "air-free liquid for law 'air')", positive=True)
    p0 = Parameter(ATMOSPHERE, "Pa", "Start pressure (absolute)", min=0.0, tunable=False)
    p_vap = Parameter(2e3, "Pa", "Vapour (cavitation) pressure of the oil, absolute", min=0.0,
                      tunable=False)
    dp_cav = Parameter(1e3, "Pa", "Half-width of the smooth cavitation clamp above and below "
                       "p_vap (0: a sharp clamp)", min=0.0, tunable=False)

    def __init__(self, law: str = "constant", swept: bool = False, cavitation: bool = True,
                 steady_start: bool = False, **params):
        if law not in BULK_MODULUS_LAWS:
            raise ParameterError(f"Volume: unknown bulk-modulus law {law!r}; choose one of "
                                 + ", ".join(BULK_MODULUS_LAWS))
        for other, names in LAW_PARAMETERS.items():
            wrong = sorted(set(names) & set(params)) if other != law else []
            if wrong:
                raise ParameterError(f"Volume: {', '.join(wrong)} belong(s) to law={other!r}, "
                                     f"not to this Volume's law={law!r}")
        self._law, self._swept, self._cavitation = law, swept, cavitation
        # steady_start: the start pressure is solved (p0 only a guess) so that no
        # oil flows in at t = 0, i.e. in equilibrium with what feeds the chamber
        self._steady_start = steady_start
        super().__init__(**params)

    def declare(self):
        super().declare()
        self.p = Variable("Pa", "Oil pressure (absolute)", output=True)
        self.p_law = State("Pa", "Pressure of the compression law before the cavitation clamp "
                           "(below p_vap: the vapour volume, in pressure units)", start=self.p0,
                           output=False, fixed=not self._steady_start)
        if self._law == "linear":
            self.K1 = Parameter(7.5, "1", "Growth of the bulk modulus with pressure, dK/dp",
                                min=0.0)
        elif self._law == "air":
            self.alpha = Parameter(0.01, "1", "Volume of entrained air per volume of oil at "
                                   "p_air", min=0.0, max=1.0)
            self.n_air = Parameter(1.0, "1", "Polytropic exponent of the air (1 isothermal, "
                                   "1.4 adiabatic)", min=1.0, max=1.67, tunable=False)
            self.p_air = Parameter(ATMOSPHERE, "Pa", "Pressure at which alpha is given",
                                   positive=True, tunable=False)
        if self._swept:
            self.q_swept = SignalInput("m3/s", "Rate at which moving walls sweep volume into "
                                       "the chamber (from a Piston)")
            self.Vc = State("m3", "Chamber volume now", start=self.V, min=0.0,
                            beyond="the moving walls have swept the chamber empty (a piston at "
                            "its bottom); give the rig an end stop there, or a larger V")

    def modulus(self, p):
        """The tangent bulk modulus under this volume's law.

        Parameters
        ----------
        p : float or casadi.SX
            Pressure, Pa (absolute).

        Returns
        -------
        float or casadi.SX
            The bulk modulus, Pa, in the volume's parameters.
        """
        if self._law == "linear":
            return bulk_modulus_linear(p, self.K, self.K1)
        if self._law == "air":
            return bulk_modulus_air(p, self.K, self.alpha, self.n_air, self.p_air)
        return self.K

    def equations(self):
        Vc = self.Vc if self._swept else self.V
        clamp = (self.p_vap + smooth_ramp(self.p_law - self.p_vap, self.dp_cav)
                 if self._cavitation else self.p_law)
        rate = self.modulus(self.p) * self.port.q
        if self._swept and self._cavitation:
            # below the clamp the vapour volume is (Vc/K)*(p_vap - p_law): moving
            # walls change it by what they sweep, not in proportion, so the oil's
            # mass balance stays exact (zero above the clamp, where p = p_law)
            rate = rate + self.q_swept.value * (self.p_law - self.p)
        eqs = [eq(self.p, clamp),
               eq(self.port.p, self.p),
               eq(Vc * der(self.p_law), rate)]
        if self._swept:
            eqs.append(eq(der(self.Vc), -self.q_swept.value))
        return eqs

    def initial_equations(self):
        return [der(self.p_law)] if self._steady_start else []

    def conditions(self):
        return [(self.p0 - self.p_vap, "the oil would start as vapour (the start pressure "
                 "must be at least the vapour pressure)", ["p_vap", "p0"])] \
            if self._cavitation else []

    def events(self):
        # the clamp switches where its parabola meets its lines, p_law = p_vap -+ dp_cav (at
        # p_law = p_vap it is smooth, and a column starting at its vapour pressure sits there)
        if not self._cavitation:
            return []
        x = self.p_law - self.p_vap
        return [(x + self.dp_cav, "cavitation",
                 "cavitation: the pressure reaches the vapour pressure (p_law = p_vap - dp_cav, "
                 "where the cavitation clamp holds it)"),
                (x - self.dp_cav, "cavitation_end",
                 "cavitation ends: the oil is liquid again above p_vap + dp_cav (the clamp's "
                 "upper end)")]

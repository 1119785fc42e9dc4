"""A 1-D elastic bar carrying axial (longitudinal) waves, lumped into masses
and springs from the library's Mass and Spring, and the check that a chosen
segment count resolves the waves at the output rate a user asks for."""
from __future__ import annotations

import math
import operator
import warnings
from collections.abc import Mapping
from typing import NamedTuple

import casadi as ca

from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter

from .chain import MassChain
from .mass import Mass


class BarResolutionWarning(UserWarning):
    """The output interval asked for is finer than the bar's segments can
    carry a wave: the output would show the chain, not the bar."""


class ElasticBar(MassChain):
    """A uniform elastic bar of length ``L``, area ``A``, Young's modulus
    ``E`` and density ``rho``, moving along x (positive down): ``n`` Masses
    ``m = rho*A*L/n`` joined by Springs ``k = n*E*A/L``.

    Discretisation (cell-centred, as SplitPiston): ``n`` equal segments of
    length h = L/n, each a rigid Mass ``seg{i}`` of rho*A*L/n at its centre;
    neighbouring centres are joined by linear Springs ``link{i}`` (i = 1..n-1)
    of stiffness E*A/h = n*E*A/L. ``flange_a`` (the struck end) is on
    segment 1, ``flange_b`` on segment n; ``sides=True`` adds a flange
    ``side{i}`` on each segment for forces along the bar (seal friction).
    ``s`` is the position of the centre of mass.

    Why not half masses at the ends (n+1 nodes, n springs)? Both lumpings
    have the same free-free spectrum, omega_j = (2*c/h)*sin(j*pi/(2n)),
    approximating the bar's j*pi*c/L; the cell-centred one has one mass
    fewer, spreads a side load evenly, and for n = 1 is exactly the rigid
    body. Its price: the end flanges sit half a segment inside the ends, so
    a front takes (n-1)*h/c, not L/c, from flange_a to flange_b.

    Waves: speed c = sqrt(E/rho), transit time L/c, impedance
    Z = A*sqrt(E*rho). The chain is dispersive: omega = (2c/h)*sin(k*h/2),
    group velocity c*cos(k*h/2); nothing above omega_max = 2*c*n/L rad/s
    propagates. A segment's transit time tau = L/(n*c) is the shortest time
    scale the chain represents: its front advances one segment per tau, its
    cut-off period is pi*tau. Output every dt_out asks for features as short
    as dt_out, so it shows the bar, not the chain's steps and ringing, when
    tau <= dt_out, i.e. n >= L/(c*dt_out) (check_bar_resolution warns
    otherwise). A front of rise time t_r is carried faithfully when tau << t_r.
    Dispersion also spreads a step front: after i segments its 10-90 % rise
    is about 1.1*tau*i^(1/3) (the Airy front of a discrete chain), so over
    the whole length 1.1*(L/c)*n^(-2/3); to keep a pulse of rise time t_r
    sharp after one transit, n >= (1.1*L/(c*t_r))^(3/2).

    Material damping (Kelvin-Voigt, stress ``E*strain + eta*strain rate``):
    a Damper ``damper{i}`` of ``c = n*eta*A/L`` beside each link. The damping
    is proportional to the stiffness, so the chain keeps its mode shapes and
    mode j has the damping ratio ``zeta_j = eta*omega_j/(2*E)``: the highest
    mode most (``zeta_max = eta/(E*tau)``), the slow ones that carry a pulse
    least. ``eta = zeta_max*E*tau`` damps the highest mode by ``zeta_max``
    (a numerical remedy for the chain's ringing: a metal's own internal
    damping is much smaller). ``eta = 0`` (the default) is the undamped bar.

    Connectors: ``flange_a`` (the struck end), ``flange_b``, and ``side1`` ..
    ``side{n}`` with ``sides=True``.

    Parameters
    ----------
    n : int
        The number of segments (1 or more).
    sides : bool
        Give each segment a side flange.
    **params : float or casadi.SX
        Values of its declared parameters (``L``, ``A``, ``E``, ``rho``,
        ``eta``), SI units.

    Raises
    ------
    pdbfs.ParameterError
        For ``n`` that is not a whole number >= 1.
    """

    L = Parameter(1.3564, "m", "Length of the bar", positive=True, tunable=False)
    A = Parameter(2.270e-2, "m2", "Cross-section area of the bar", positive=True,
                  tunable=False)
    E = Parameter(2.1e11, "Pa", "Young's modulus of the bar (steel: 2.1e11 Pa)", positive=True)
    rho = Parameter(7850.0, "kg/m3", "Density of the bar (steel: 7850 kg/m3)", positive=True,
                    tunable=False)
    eta = Parameter(0.0, "Pa.s", "Viscosity of the material (Kelvin-Voigt: stress E*strain + "
                    "eta*strain rate); 0: undamped", min=0.0)

    piece_prefix, body = "seg", "bar"

    def __init__(self, n: int = 20, sides: bool = False, **params: float | ca.SX):
        super().__init__(_segment_count(n), sides, **params)

    def total_mass(self) -> ca.SX:
        return self.rho * self.A * self.L

    def total_stiffness(self) -> ca.SX:
        return self.E * self.A / self.L

    def total_damping(self) -> ca.SX:
        return self.eta * self.A / self.L

    def segment(self, i: int) -> Mass:
        """One of the segments.

        Parameters
        ----------
        i : int
            Its number, 1 .. n (1 at flange_a).

        Returns
        -------
        Mass
            The segment.
        """
        return self.piece(i)

    def check_output(self, dt_out: float, params: Mapping[str, float] | None = None
                     ) -> BarResolution | None:
        """Warn (BarResolutionWarning) if the segments do not resolve the
        wave at a run's output interval; ``Rig.simulate`` calls it before a
        run.

        Parameters
        ----------
        dt_out : float
            The run's output interval, s.
        params : mapping of str to float, optional
            The run's parameter values by dotted name (the bar's own are used).

        Returns
        -------
        BarResolution or None
            The resolution (wave speed, transit times, the factor and the
            smallest n that resolves the wave), or None where a value is bad
            (the run reports it).
        """
        prefix = self.path() + "."
        mine = {k[len(prefix):]: v for k, v in (params or {}).items() if k.startswith(prefix)}
        try:
            values = self.values(mine)
        except ParameterError:
            return None      # a bad value: simulate() reports it with the rig's names
        return check_bar_resolution(values, dt_out, name=self.path(), stacklevel=5)

    def values(self, overrides: Mapping[str, float] | None = None) -> dict:
        """The bar's numbers: L, A, E, rho and n.

        Parameters
        ----------
        overrides : mapping of str to float, optional
            Values of L, A, E or rho to use in place of the bar's own.

        Returns
        -------
        dict
            ``{"n": ..., "L": ..., "A": ..., "E": ..., "rho": ...}``, SI units.

        Raises
        ------
        pdbfs.ParameterError
            For a value out of its bounds, or one computed from other
            parameters and not given in ``overrides``.
        """
        out = {"n": self._n}
        for name in ("L", "A", "E", "rho"):
            value = (overrides or {}).get(name, self._params[name].value)
            if isinstance(value, ca.SX):
                raise ParameterError(f"ElasticBar '{self.path()}': {name} is computed from "
                                     "other parameters; pass its value in overrides")
            out[name] = self._params[name].decl.check(value, f"ElasticBar.{name}")
        return out


def _segment_count(n) -> int:
    if not isinstance(n, bool):
        try:
            n = operator.index(n)
        except TypeError:
            pass
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ParameterError(f"ElasticBar: n = {n!r} must be a whole number of segments >= 1")
    return n


class BarResolution(NamedTuple):
    """How well a bar of ``n`` segments resolves waves at output interval
    ``dt_out``. ``factor`` = segment_time / dt_out: <= 1 is resolved."""

    c: float              # wave speed, m/s
    transit_time: float   # L/c, s
    segment_time: float   # L/(n*c), s
    factor: float         # segment_time / dt_out
    n_min: int            # smallest n with segment_time <= dt_out

    @property
    def resolved(self) -> bool:
        """Whether a wave crosses a segment within one output interval (factor <= 1)."""
        return self.factor <= 1.0


def bar_resolution(L: float, E: float, rho: float, n: int, dt_out: float) -> BarResolution:
    """Wave speed, transit times and the resolution factor of a bar (SI)."""
    for name, value in (("L", L), ("E", E), ("rho", rho), ("dt_out", dt_out)):
        try:
            ok = math.isfinite(float(value)) and float(value) > 0
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ParameterError(f"bar_resolution: {name} = {value!r} must be a number > 0")
    L, E, rho, dt_out = float(L), float(E), float(rho), float(dt_out)
    n = _segment_count(n)
    c = math.sqrt(E / rho)
    transit = L / c
    tau = transit / n
    # a hair under 1 so that n exactly at the bound is not rounded up
    return BarResolution(c, transit, tau, tau / dt_out, math.ceil(transit / dt_out - 1e-9))


def check_bar_resolution(bar_or_params: ElasticBar | Mapping[str, float], dt_out: float, *,
                         name: str | None = None, stacklevel: int = 2) -> BarResolution:
    """Warn (BarResolutionWarning) when one segment's transit time
    L/(n*c) is longer than an output interval: the output then resolves
    time scales the lumped chain does not carry, and shows its
    discretisation.

    Parameters
    ----------
    bar_or_params : ElasticBar or mapping of str to float
        A bar (its parameter values), or a mapping with ``L`` (m), ``E``
        (Pa), ``rho`` (kg/m3) and ``n``.
    dt_out : float
        The output interval, s.
    name : str, optional
        The bar's name in the warning (default: its path in its rig).
    stacklevel : int
        The warning's stack level (the caller's line by default).

    Returns
    -------
    BarResolution
        Wave speed ``c``, ``transit_time`` and ``segment_time`` (s), the
        ``factor`` segment_time / dt_out (<= 1: resolved) and ``n_min``,
        the smallest n that resolves the wave.

    Raises
    ------
    pdbfs.ParameterError
        For a value missing or not a number > 0.

    Examples
    --------
    A 1.36 m steel bar of 30 segments, output every 10 us (27 would do):

    >>> from pdbfs.components import check_bar_resolution
    >>> r = check_bar_resolution({"L": 1.3564, "E": 2.1e11, "rho": 7850.0, "n": 30}, 1e-5)
    >>> f"{r.c:.4g} m/s", r.resolved, r.n_min
    ('5172 m/s', True, 27)
    """
    if isinstance(bar_or_params, ElasticBar):
        values = bar_or_params.values()
        name = name or bar_or_params.path()
    else:
        values = dict(bar_or_params)
        missing = {"L", "E", "rho", "n"} - set(values)
        if missing:
            raise ParameterError(f"check_bar_resolution: missing {', '.join(sorted(missing))}")
    r = bar_resolution(values["L"], values["E"], values["rho"], values["n"], dt_out)
    if not r.resolved:
        who = f"ElasticBar '{name}'" if name else "ElasticBar"
        warnings.warn(f"{who}: a segment's transit time {r.segment_time:.3g} s is "
                      f"{r.factor:.3g} times the output interval {dt_out:.3g} s; use "
                      f"n >= {r.n_min} segments to resolve the wave at this output rate",
                      BarResolutionWarning, stacklevel=stacklevel)
    return r

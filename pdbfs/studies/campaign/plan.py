"""What a campaign's blows are run with: a schedule of settings per blow,
and an operator's rule that adjusts the next blow from the blows before.

A setting holds until it is changed: the schedule's row of a blow sets its
parameters for that blow, then the rule's answer (made from the blows
before) sets its own; the other parameters keep their values. The striker's
setting is its drop height (a rig's own ``h``) or its impact speed (the
paper rig's ``hammer.v0``); a schedule may give either for a rig of the
other (``drop_height``, m, becomes ``v0 = sqrt(2 g h)``).
"""
from __future__ import annotations

import hashlib
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Union

import numpy as np

from pdbfs.components.laws import STANDARD_GRAVITY
from pdbfs.errors import DataError, ParameterError

from ..blows import height_parameter

if TYPE_CHECKING:
    from pdbfs.modelling import DAE

#: a schedule's column of drop heights (m), for a rig of either kind of striker
DROP_HEIGHT = "drop_height"

#: what a rule is: the blows so far (their records, oldest first) -> the next blow's settings
Rule = Callable[[Sequence[Mapping[str, Any]]], Union[Mapping[str, float], None]]


@dataclass(frozen=True)
class HoldPeak:
    """An operator's rule: a blow whose peak pressure left the band
    ``[low, high]`` has the next blow's striker setting scaled by
    ``(target / peak)^(1 / exponent)``, the peak growing as the setting's
    power ``exponent`` (about 1 for an impact speed, 1/2 for a drop height);
    a peak inside the band changes nothing.

    Parameters
    ----------
    low, high : float
        The band, Pa (0 < low < high).
    target : float, optional
        The peak aimed at, Pa (default the band's middle).
    parameter : str, optional
        The setting adjusted (default: the rig's striker, its drop height
        or its impact speed ``X.v0``).
    exponent : float, optional
        The power of the setting the peak grows as (default: 1/2 for a
        parameter in m, a height; 1 otherwise).

    Examples
    --------
    >>> from pdbfs.studies.campaign import HoldPeak
    >>> rule = HoldPeak(90e6, 92e6, parameter="hammer.v0", exponent=1.0)
    >>> rule([{"hammer.v0": 2.73, "peak_pressure": 91.5e6}]) is None   # in the band
    True
    >>> round(rule([{"hammer.v0": 2.73, "peak_pressure": 93e6}])["hammer.v0"], 4)   # 2 % slower
    2.6713
    """

    low: float
    high: float
    target: float | None = None
    parameter: str | None = None
    exponent: float | None = None

    def __post_init__(self):
        lo, hi = self.low, self.high
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                   for v in (lo, hi)) or not 0 < lo < hi:
            raise ParameterError(f"hold-peak: the band {lo!r}:{hi!r} Pa must be 0 < LOW < HIGH")
        if self.target is not None and not lo <= self.target <= hi:
            raise ParameterError(f"hold-peak: the target {self.target!r} Pa is outside the band "
                                 f"{lo:g}:{hi:g}")
        if self.exponent is not None and not (math.isfinite(self.exponent) and self.exponent > 0):
            raise ParameterError(f"hold-peak: the exponent {self.exponent!r} must be positive")

    def __call__(self, blows: Sequence[Mapping[str, Any]]) -> dict[str, float] | None:
        """The next blow's setting from the last blow's peak (None: unchanged).

        Parameters
        ----------
        blows : sequence of mapping
            The blows so far, each with ``peak_pressure`` (Pa) and the setting's value.

        Returns
        -------
        dict or None
            ``{parameter: value}`` for the next blow, or None.
        """
        if self.parameter is None:
            raise ParameterError("hold-peak: no parameter to adjust (a campaign gives it the "
                                 "rig's striker)")
        last = blows[-1]
        peak = last["peak_pressure"]
        if self.low <= peak <= self.high:
            return None
        exponent = 1.0 if self.exponent is None else self.exponent
        target = 0.5 * (self.low + self.high) if self.target is None else self.target
        return {self.parameter: float(last[self.parameter] * (target / peak) ** (1 / exponent))}

    def bound(self, dae: DAE) -> HoldPeak:
        """This rule with its parameter and exponent given for a rig.

        Parameters
        ----------
        dae : DAE
            The rig's DAE.

        Returns
        -------
        HoldPeak

        Raises
        ------
        pdbfs.ParameterError
            For a rig without a striker (and no parameter given), or an unknown parameter.
        """
        name = self.parameter
        if name is None:
            found = height_parameter(dae)
            if found is None:
                raise ParameterError(f"hold-peak: rig {dae.name} has no drop height and no "
                                     "striker's impact speed (X.v0) to adjust; give its parameter")
            name = found[0]
        if name not in dae.p_names:
            raise ParameterError(f"hold-peak: {name!r} is not a parameter of rig {dae.name}")
        exponent = self.exponent
        if exponent is None:
            exponent = 0.5 if dae.params[dae.p_names.index(name)].unit == "m" else 1.0
        return replace(self, parameter=name, exponent=exponent)

    def spec(self) -> str:
        """The rule as the command line writes it."""
        tail = "" if self.target is None else f":{self.target:.17g}"
        return f"hold-peak:{self.low:.17g}:{self.high:.17g}{tail}"


#: the rules by name, as ``--rule NAME:ARGS`` gives them, each with the form of its text
RULES = {"hold-peak": "hold-peak:LOW:HIGH[:TARGET] (Pa)"}


def rule_of(text: str) -> HoldPeak:
    """The rule a text names: ``hold-peak:LOW:HIGH[:TARGET]`` (Pa).

    Parameters
    ----------
    text : str
        The rule's name and its arguments, separated by colons.

    Returns
    -------
    HoldPeak
        The rule (its parameter given by the campaign).

    Raises
    ------
    pdbfs.ParameterError
        For an unknown rule or arguments that are not its.
    """
    name, _, args = str(text).partition(":")
    if name not in RULES:
        raise ParameterError(f"unknown rule {name!r}; choose {', '.join(RULES.values())}")
    try:
        values = [float(v) for v in args.split(":")] if args else []
    except ValueError:
        values = []
    if len(values) not in (2, 3):
        raise ParameterError(f"rule {text!r}: expected {RULES[name]}")
    return HoldPeak(*values)


def rule_spec(rule: Any) -> str | None:
    """What identifies a rule in a campaign's manifest (None: no rule)."""
    if rule is None:
        return None
    if isinstance(rule, HoldPeak):
        return rule.spec()
    return f"{type(rule).__module__}.{getattr(rule, '__qualname__', type(rule).__qualname__)}"


@dataclass
class Schedule:
    """The settings of each blow: a column of values per rig parameter.

    Attributes
    ----------
    columns : dict of str to numpy.ndarray
        Parameter name -> its value at each blow (at least as many as the blows).
    """

    columns: dict

    @classmethod
    def of(cls, schedule: Any, dae: DAE, blows: int, refused: Mapping[str, str]) -> Schedule | None:
        """The schedule ``schedule`` gives (a mapping or a DataFrame of columns),
        checked for the rig ``dae`` and ``blows`` blows; None for none.

        Parameters
        ----------
        schedule : mapping of str to array_like, pandas.DataFrame or None
            Columns of per-blow values by parameter name, or ``drop_height`` (m).
        dae : DAE
            The rig.
        blows : int
            The campaign's blows: each column has at least as many values.
        refused : mapping of str to str
            Parameters a schedule may not set, with the reason.

        Returns
        -------
        Schedule or None

        Raises
        ------
        pdbfs.ParameterError
            For an unknown or refused name, a column shorter than the
            campaign, or values that are not finite numbers.
        """
        if schedule is None:
            return None
        names = list(schedule.columns) if hasattr(schedule, "columns") else list(schedule)
        if not names:
            raise ParameterError("schedule: it has no columns (give a parameter's values per blow)")
        striker = height_parameter(dae)
        out = {}
        for name in names:
            values = np.asarray(schedule[name], dtype=float).ravel() \
                if _numeric(schedule[name]) else None
            if values is None or not np.all(np.isfinite(values)):
                raise ParameterError(f"schedule: the column {name!r} holds values that are not "
                                "finite numbers")
            if values.size < blows:
                raise ParameterError(f"schedule: the column {name!r} has {values.size} values "
                                     f"for a campaign of {blows} blows")
            target = name
            if name == DROP_HEIGHT:
                if striker is None:
                    raise ParameterError(f"schedule: rig {dae.name} has no drop height and no "
                                         "striker's impact speed for the column drop_height")
                target, speed = striker
                if np.any(values < 0):
                    raise ParameterError("schedule: a drop height is negative")
                if speed:
                    values = np.sqrt(2.0 * STANDARD_GRAVITY * values)
            elif name not in dae.p_names:
                raise ParameterError(f"schedule: {name!r} is not a parameter of rig {dae.name}; "
                                     "`pdbfs params` lists them")
            if target in refused:
                raise ParameterError(f"schedule: {name!r} {refused[target]}")
            if target in out:
                raise ParameterError(f"schedule: {target} is given twice (drop_height sets it too)")
            out[target] = values[:blows]
        return cls(out)

    def row(self, i: int) -> dict[str, float]:
        """The settings of one blow.

        Parameters
        ----------
        i : int
            The blow, from 0.

        Returns
        -------
        dict of str to float
            Parameter name -> value, SI units.
        """
        return {k: float(v[i]) for k, v in self.columns.items()}

    def key(self) -> str:
        """A hash of the values, for a campaign's manifest."""
        h = hashlib.sha256()
        for k in sorted(self.columns):
            h.update(k.encode())
            h.update(np.ascontiguousarray(self.columns[k]).tobytes())
        return h.hexdigest()[:16]


def _numeric(values) -> bool:
    try:
        np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def read_schedule(path: str) -> dict[str, np.ndarray]:
    """A schedule from a CSV file: a header of parameter names (or
    ``drop_height``), one row per blow.

    Parameters
    ----------
    path : str
        The file.

    Returns
    -------
    dict of str to numpy.ndarray
        Its columns.

    Raises
    ------
    pdbfs.DataError
        For a file that cannot be read, or cells that are not numbers.
    """
    import pandas as pd
    try:
        frame = pd.read_csv(path)
    except (OSError, ValueError) as err:
        raise DataError(f"--schedule {path}: cannot be read ({err})") from None
    cols = {}
    for name in frame.columns:
        values = pd.to_numeric(frame[name], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise DataError(f"--schedule {path}: row {bad[0] + 1} of the column {name!r} is not "
                            "a finite number")
        cols[str(name).strip()] = values
    return cols

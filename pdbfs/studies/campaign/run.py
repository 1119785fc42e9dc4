"""A campaign run: blow after blow, each a full simulation of the rig from
the temperatures the blows before left, its heat handed to the thermal
network, which carries it over the pause to the next blow in closed form
(heat.py). The fast blow and the slow heat flow are each solved on their
own time scale: milliseconds of mechanics integrated, minutes of heat
stepped by a matrix exponential.

Blows are saved in chunks to a folder as they finish (the sweeps' Store:
a manifest and one file per chunk, each complete or absent), so that a
campaign that was stopped resumes from its last chunk when run again.
"""
from __future__ import annotations

import math
import os
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from pdbfs.errors import (DataError, ParameterError, PdbfsError, PdbfsWarning,
                          PulseIncompleteWarning, missing_extra, plain)

from ..sweeps.store import Store
from ..sweeps.sweep import _dae_key
from .result import UNITS, CampaignResult
from .plan import HoldPeak
from .records import Blows, columns
from .setup import Setup, prepare, rule_changes

if TYPE_CHECKING:
    import pandas as pd

    from pdbfs.fatigue import Breech
    from pdbfs.rig import Rig

#: blows per chunk file of a saved campaign
CHUNK = 1000
#: blows between two progress reports
REPORT_EVERY = 200
#: the share of a checked blow's damage its peak may leave out before the campaign warns
LEFT_OUT = 0.01


class CampaignStore(Store):
    """A campaign's folder: its manifest and its blows in chunks."""

    WHAT, ORDER, UNIT = "campaign", "blow", "blows"


def campaign(rig: Rig | str, blows: int, period: float, *,
             schedule: Mapping[str, Sequence[float]] | pd.DataFrame | None = None,
             rule: Callable | str | None = None, params: Mapping[str, float] | None = None,
             temperatures: Mapping[str, float] | None = None, breech: Breech | None = None,
             damage: str = "peak", check_every: int = 500, t_blow: float | None = None,
             oil: str | None = None, rtol: float | None = None, atol: float | None = None,
             method: str = "auto", backend: str = "auto", out: str | os.PathLike | None = None,
             format: str | None = None, chunk_size: int = CHUNK, overwrite: bool = False,
             progress: Callable[[int, int], object] | None = None) -> CampaignResult:
    """Run ``blows`` blows of ``rig``, one every ``period`` seconds, each from
    the temperatures the blows before left.

    Each blow is a full simulation of the rig over ``t_blow``; the heat it
    dissipated, left in the rig's heat capacitors, spreads through the rig's
    thermal network and leaves it to the room over the pause before the
    next blow. A blow's damage is read off its peak pressure (one cycle from
    the rest pressure to the peak and back) and checked against the
    rainflow count of its whole pressure history every ``check_every``
    blows (the first and the last too).

    Parameters
    ----------
    rig : pdbfs.Rig or str
        The rig, or a name of ``pdbfs.models.RIGS``; a rig with heat
        capacitors needs its thermal network (``thermal_network``).
    blows : int
        The number of blows (1 or more).
    period : float
        The time from one blow's start to the next, s (longer than ``t_blow``).
    schedule : mapping or pandas.DataFrame, optional
        Per-blow settings: columns of values by parameter name (or
        ``drop_height``, m), at least ``blows`` of each. A setting holds
        until it is changed.
    rule : callable, HoldPeak or str, optional
        An operator's rule, called after each blow with the records of the
        blows so far (a sequence of dicts of the table's columns, oldest
        first, the damage aside: it is reckoned a chunk at a time; a rule
        must depend on them alone, so that a resumed campaign goes on as it
        would have), returning the next blow's settings ``{name: value}``
        or None. Its settings take the place of the schedule's.
        ``"hold-peak:LOW:HIGH"`` (Pa) is :class:`HoldPeak`.
    params : mapping of str to float, optional
        Parameters every blow is given (the thermal network's too).
    temperatures : mapping of str to float, optional
        The heat capacitors' temperatures at the start (``{"oil_heat.T":
        303.15}``, K; default: their declared ``T0``).
    breech : pdbfs.fatigue.Breech, optional
        The breech (default ``Breech()``, an assumed large-calibre breech).
    damage : {"peak", "history"}
        Each blow's damage from its peak (fast), or from the rainflow count
        of its whole pressure history (every blow simulated on its full
        output grid; several times slower).
    check_every : int
        Read the whole history's damage too every this many blows, from the
        first, and at the last (0: at none).
    t_blow : float, optional
        Each blow's simulated time, s (default: the rig's own, 0.02 s for
        the paper rig); its pulse must end inside it.
    oil : str, optional
        The heat capacitor's temperature reported as the oil's (default
        ``oil_heat.T`` where the rig has it).
    rtol, atol, method, backend
        As for :meth:`pdbfs.Rig.simulate`.
    out : str or path-like, optional
        A folder to save the blows in, a chunk of ``chunk_size`` blows at a
        time (``format`` "parquet" or "csv"; default Parquet where pyarrow
        is installed); the same campaign run again resumes from it. A folder
        holding another campaign is refused unless ``overwrite``.
    format : str, optional
        The chunks' file format in ``out``: "parquet" or "csv".
    chunk_size : int
        Blows per chunk file in ``out``.
    overwrite : bool
        Replace a folder that holds another campaign.
    progress : callable, optional
        Called with (blows done, blows in all) as the campaign goes.

    Returns
    -------
    CampaignResult
        The table of blows, the totals, the checked blows.

    Raises
    ------
    pdbfs.ParameterError
        For bad arguments, before any blow is run.
    pdbfs.DataError
        For a blow whose pulse outlasts ``t_blow``, or that has no pulse.
    pdbfs.ModelError
        For a rig whose heat capacitors have no linear thermal network.

    Examples
    --------
    >>> from pdbfs.models import paper_thermal_rig
    >>> from pdbfs.studies.campaign import campaign
    >>> res = campaign(paper_thermal_rig(), blows=50, period=10.0)
    >>> bool(res.table["oil_temperature"].is_monotonic_increasing)    # the oil warms
    True
    >>> abs(res.totals["heat_balance"]) < 1e-9       # dissipated = stored + lost
    True
    """
    s = prepare(rig, blows, period, schedule, rule, params, temperatures, breech, damage,
                check_every, t_blow, oil, rtol, atol, method, backend)
    return run(s, out, format, chunk_size, overwrite, progress)


def run(s: Setup, out: str | os.PathLike | None = None, format: str | None = None,
        chunk_size: int = CHUNK, overwrite: bool = False,
        progress: Callable[[int, int], object] | None = None) -> CampaignResult:
    """The campaign ``s`` (made by :func:`pdbfs.studies.campaign.setup.prepare`,
    its arguments checked) run; the other arguments as for :func:`campaign`.

    Parameters
    ----------
    s : Setup
        The campaign.
    out, format, chunk_size, overwrite, progress
        As for :func:`campaign`.

    Returns
    -------
    CampaignResult
    """
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1:
        raise ParameterError(f"campaign: chunk_size = {plain(chunk_size)} must be a whole "
                             "number >= 1")
    if out is None and (format is not None or overwrite):
        raise ParameterError("campaign: format= and overwrite= are about the files in out=; "
                             "without out= the campaign is held in memory")
    store = None
    if out is not None:
        fmt = format or ("csv" if missing_extra("parquet") else "parquet")
        store = CampaignStore(out, {**s.spec(), "dae": _dae_key(s.sim)}, s.blows, chunk_size,
                              fmt, overwrite)
    return _Run(s, store, chunk_size, progress).go()


class _Run:
    """One campaign's loop: its state between blows and its records."""

    def __init__(self, s: Setup, store, chunk_size: int, progress):
        self.s, self.store, self.chunk, self.progress = s, store, chunk_size, progress
        self.blows = Blows()           # the records so far (a rule reads them)
        self.T = s.T0.copy()
        self.current = dict(s.start)
        self.keys = None               # the summary's numbers kept, fixed by the first blow
        # the blows of the chunk at hand: their peaks, and parameter vectors (their
        # rest pressures are found together) or rest pressures
        self.peaks: list[list] = []
        self.rests: list = []

    def go(self) -> CampaignResult:
        """Every blow not saved yet, run and saved; the campaign's result."""
        s = self.s
        t0 = time.perf_counter()
        first = self._resume() if self.store is not None else 0
        for i in range(first, s.blows):
            if s.schedule is not None:
                self.current.update(s.schedule.row(i))
            if s.rule is not None and len(self.blows):
                self.current.update(rule_changes(s.rule(self.blows), s, i + 1))
            self.blows.add(self._blow(i))
            if len(self.blows.pending) == self.chunk or i == s.blows - 1:
                self._flush(i // self.chunk)
            if self.progress is not None and ((i + 1) % REPORT_EVERY == 0 or i == s.blows - 1):
                self.progress(i + 1, s.blows)
        return self._result(time.perf_counter() - t0, s.blows - first)

    def _blow(self, i: int) -> dict:
        """Blow ``i`` (from 0) from the temperatures self.T: its record (its
        damage from its peak added by _flush); self.T becomes the
        temperatures at the next blow's start."""
        s = self.s
        p = {**s.fixed, **self.current, **dict(zip(s.t0_names, self.T.tolist()))}
        whole = s.damage_from == "history" or s.check_every > 0 and \
            (i % s.check_every == 0 or i == s.blows - 1)
        try:
            res = s.rig.simulate(s.t_blow, n_out=s.n_out if whole else 2, params=p, **s.run)
            with warnings.catch_warnings():        # a pulse cut off is refused below, in one line
                warnings.simplefilter("ignore", PulseIncompleteWarning)
                summary = res.summary()
            if not summary.get("complete", True):
                raise DataError(f"its pulse outlasts the blow's simulated time {s.t_blow:g} s; "
                                "give a longer t_blow (--t-end)")
            d_whole = s.breech.damage(res, signal=s.pressure) if whole else math.nan
        except PdbfsError as err:
            raise type(err)(f"campaign, blow {i + 1}: {err}") from None
        peaks = summary.get("impact_peak_pressures") or [summary.get("peak_pressure")]
        if not peaks or any(v is None or not v > 0 for v in peaks):
            raise DataError(f"campaign, blow {i + 1}: no pressure pulse (its peak pressure is "
                            f"{plain(summary.get('peak_pressure'))})")
        self.peaks.append(peaks)
        self.rests.append(res.p if s.rest is not None else float(res[s.pressure][0]))
        if self.keys is None:
            self.keys = [k for k, v in summary.items() if k != "complete"
                         and not isinstance(v, (bool, list, tuple, dict))]
        rec = {"blow": i + 1, "time": i * s.period, **self.current}
        rec.update((k, math.nan if summary[k] is None else float(summary[k])) for k in self.keys)
        rec["oil_temperature"] = float(self.T[s.oil]) if s.oil is not None else math.nan
        diss = lost = math.nan
        if s.network is not None:
            end = res.final
            T_end = np.array([end[n] for n in s.states])
            net = s.network
            # the heat lost during the blow itself: its rate at the blow's two ends (the
            # temperatures change by a fraction of a kelvin over milliseconds)
            lost_blow = s.t_blow * net.lost_rate(0.5 * (self.T + T_end))
            diss = net.capacities @ (T_end - self.T) + lost_blow
            rec.update(zip(s.states, self.T.tolist()))
            rec.update(zip([n + "_end" for n in s.states], T_end.tolist()))
            self.T, lost_pause = s.pause(T_end)
            lost = lost_blow + lost_pause
        rec.update(energy_dissipated=float(diss), heat_lost=float(lost),
                   damage_history=d_whole)
        return rec

    def _flush(self, chunk: int) -> None:
        """The pending blows' damages from their peaks (in one go), and their chunk saved."""
        s = self.s
        rests = s.rest(np.array(self.rests)) if s.rest is not None else np.array(self.rests)
        counts = [len(p) for p in self.peaks]
        d = s.breech.peak_damage(np.concatenate(self.peaks), np.repeat(rests, counts))
        d = np.add.reduceat(np.atleast_1d(d), np.cumsum([0] + counts[:-1]))
        for rec, dk in zip(self.blows.pending, d.tolist()):
            rec["damage_peak"] = dk
            rec["damage"] = rec["damage_history"] if s.damage_from == "history" else dk
        cols = columns(self.blows.pending)
        if self.store is not None:
            self.store.write(chunk, cols)
        self.blows.seal(cols)
        self.peaks, self.rests = [], []

    def _resume(self) -> int:
        """The blows the folder holds already: their records kept, the state
        after the last of them restored; the number of the next blow."""
        s, store = self.s, self.store
        done = sorted(store.done())
        if not done:
            return 0
        if done != list(range(len(done))):
            raise ParameterError(f"{store.dir} lacks chunk {_gap(done)} of its campaign: it "
                                 "cannot resume; choose another folder, or overwrite it")
        frame = store.read()
        self.blows.seal({c: frame[c].to_numpy(dtype=np.int64 if c == "blow" else float)
                         for c in frame.columns})
        last = self.blows[-1]
        # every setting as the last blow had it (a rule's too: the records hold them)
        names = set(s.sim.dae.p_names)
        self.current.update({k: float(last[k]) for k in frame.columns if k in names})
        if s.network is not None:
            self.T = s.pause(np.array([last[n + "_end"] for n in s.states], dtype=float))[0]
        return len(self.blows)

    def _result(self, elapsed: float, computed: int) -> CampaignResult:
        s = self.s
        table = self.blows.frame()
        settings = list(self.current)
        for k in settings:                     # a setting a rule set late held its value before
            table[k] = table[k].fillna(s.fixed.get(k, _default(s, k)))
        checks = table.loc[np.isfinite(table["damage_history"].to_numpy(dtype=float)),
                           ["blow", "damage_peak", "damage_history"]].reset_index(drop=True)
        if s.damage_from == "peak" and len(checks):
            share = 1.0 - checks["damage_peak"] / checks["damage_history"]
            k = int(np.argmax(share.to_numpy()))
            if share.iloc[k] > LEFT_OUT:
                warnings.warn(PdbfsWarning(
                    f"campaign: blow {checks['blow'].iloc[k]}'s peak leaves out "
                    f"{100 * share.iloc[k]:.3g} % of its damage (its pulse has cycles of its "
                    "own); read each blow's whole history (damage='history', --damage "
                    "history)"), stacklevel=3)
        band = (s.rule.low, s.rule.high) if isinstance(s.rule, HoldPeak) else None
        spec = {"blows": s.blows, "params": s.fixed, "rule": s.spec()["rule"],
                "check_every": s.check_every, "schedule": s.schedule is not None}
        return CampaignResult(s.name, s.period, s.t_blow, table, settings,
                              dict(zip(s.states, s.T0.tolist())),
                              dict(zip(s.states, self.T.tolist())),
                              dict(zip(s.states, (s.network.capacities.tolist()
                                                  if s.network is not None else []))),
                              checks, s.damage_from, band, computed, elapsed,
                              str(self.store.dir) if self.store is not None else None, spec,
                              _units(s, table))


def _units(s: Setup, table) -> dict:
    """The unit of each column of the table."""
    dae = s.sim.dae
    units = {p.name: p.unit for p in dae.params}
    units.update(UNITS)
    units.update({n: "K" for n in s.states})
    units.update({n + "_end": "K" for n in s.states})
    return {c: units.get(c, "") for c in table.columns}


def _default(s: Setup, name: str) -> float:
    dae = s.sim.dae
    return dae.params[dae.p_names.index(name)].value


def _gap(done: list) -> int:
    return next(k for k, c in enumerate(done) if c != k)


def resumed(path: str | os.PathLike) -> int:
    """How many blows of the campaign saved in ``path`` are there (0 if none)."""
    try:
        store = CampaignStore.open(path)
    except ParameterError:
        return 0
    return store.rows()


def saved(path: str | os.PathLike) -> tuple[dict, Any]:
    """(the manifest's specification, the table of blows) of the campaign saved in ``path``."""
    store = CampaignStore.open(path)
    if store.spec.get("kind") != "campaign":
        raise ParameterError(f"{path} holds a {store.spec.get('kind', 'sweep')}, not a campaign")
    return store.spec, store.read()

"""The result of a campaign: a table with one row per blow, its totals (the
damage and the life it predicts, the heat dissipated, stored and lost), the
blows whose damage was also read from their whole pressure history, a plot
and a JSON-ready form."""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from pdbfs.fatigue import campaign_life
from pdbfs.files import save_figure

if TYPE_CHECKING:
    import os

    import pandas as pd
    from matplotlib.figure import Figure

#: the units of a blow's columns (the settings' and the temperatures' are the rig's)
UNITS = {"blow": "1", "time": "s", "peak_pressure": "Pa", "time_of_peak": "s",
         "pulse_duration": "s", "peak_contact_force": "N", "max_piston_displacement": "m",
         "restitution_coefficient": "1", "impact_count": "1", "oil_temperature": "K",
         "energy_dissipated": "J", "heat_lost": "J", "damage_peak": "1", "damage_history": "1",
         "damage": "1"}


@dataclass
class CampaignResult:
    """A campaign of blows: every blow's figures and the campaign's totals.

    Attributes
    ----------
    rig : str
        The rig's name.
    period, t_blow : float
        The time from one blow to the next and each blow's simulated time, s.
    table : pandas.DataFrame
        One row per blow, in order: ``blow`` (from 1), ``time`` (its start, s),
        its settings (the striker's and any a schedule or a rule set), its
        summary (``peak_pressure`` Pa, ``pulse_duration`` s, ...),
        ``oil_temperature`` (K, at its start; NaN for a rig without heat),
        each heat capacitor's temperature at its start (``NAME.T``) and end
        (``NAME.T_end``), K, ``energy_dissipated`` (the heat it gave the
        thermal network, J), ``heat_lost`` (through the network's
        boundaries over the blow and the pause after it, J) and ``damage``.
    settings : list of str
        The setting columns.
    initial, final : dict
        The heat capacitors' temperatures at the campaign's start and at its
        end (a period after the last blow's start), K.
    capacities : dict
        The heat capacitors' heat capacities by temperature name, J/K.
    checks : pandas.DataFrame
        The blows whose damage was also read from their whole history:
        ``blow``, ``damage_peak`` (rest -> peak -> rest) and ``damage_history`` (rainflow).
    damage_from : str
        "peak" or "history": what the ``damage`` column is.
    band : tuple of float or None
        The peak pressure band an operator's rule held, Pa.
    computed, elapsed
        Blows computed by this call (the rest were found saved) and its time, s.
    folder : str or None
        The folder the blows were saved in.
    units : dict
        The unit of each column of the table.
    """

    rig: str
    period: float
    t_blow: float
    table: pd.DataFrame
    settings: list
    initial: dict
    final: dict
    capacities: dict
    checks: pd.DataFrame
    damage_from: str = "peak"
    band: tuple | None = None
    computed: int = 0
    elapsed: float = 0.0
    folder: str | None = None
    spec: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.table)

    @property
    def damages(self) -> np.ndarray:
        """The damage of each blow."""
        return self.table["damage"].to_numpy(dtype=float)

    @property
    def life(self) -> float:
        """The predicted life in blows of a breech that runs this campaign
        again and again (:func:`pdbfs.fatigue.campaign_life`)."""
        return campaign_life(self.damages)

    @property
    def totals(self) -> dict:
        """The campaign's totals: ``blows``, ``duration`` (s), ``damage``,
        ``life_blows``, ``campaigns_to_failure``; the heat ``energy_dissipated``,
        ``heat_stored`` (in the capacitors at the end, against the start) and
        ``heat_lost`` (J), and ``heat_balance``, (dissipated - stored - lost)
        / dissipated; the first, last, lowest and highest peak pressure (Pa)
        and oil temperature (K); ``damage_left_out``, the largest share of a
        checked blow's damage its peak alone leaves out (None if none was
        checked)."""
        t = self.table
        d = float(t["damage"].sum())
        out = {"blows": len(t), "duration": len(t) * self.period, "damage": d,
               "life_blows": self.life, "campaigns_to_failure": 1.0 / d if d > 0 else math.inf}
        if self.capacities:
            diss = float(t["energy_dissipated"].sum())
            stored = float(sum(self.capacities[s] * (self.final[s] - self.initial[s])
                               for s in self.final))
            lost = float(t["heat_lost"].sum())
            out.update(energy_dissipated=diss, heat_stored=stored, heat_lost=lost,
                       heat_balance=(diss - stored - lost) / diss if diss else None)
        else:                               # a rig without heat: nothing to reckon
            out.update(energy_dissipated=None, heat_stored=None, heat_lost=None,
                       heat_balance=None)
        for col in ("peak_pressure", "oil_temperature"):
            v = t[col].to_numpy(dtype=float)
            fine = bool(np.all(np.isfinite(v)))
            for key, f in (("first", lambda a: a[0]), ("last", lambda a: a[-1]),
                           ("min", np.min), ("max", np.max)):
                out[f"{col}_{key}"] = float(f(v)) if fine else None
        c = self.checks
        out["damage_left_out"] = float(np.max(1.0 - c["damage_peak"] / c["damage_history"])) \
            if len(c) else None
        out["temperatures_final"] = dict(self.final)
        return out

    def to_dict(self) -> dict:
        """The campaign as JSON-ready data: ``rig``, ``settings`` (what it
        was run with), ``totals``, ``units`` (of the blows' columns),
        ``blows`` (one record per blow, the table's columns; None where a
        value is undefined), ``checks`` and ``folder``."""
        return {"rig": self.rig, "settings": dict(self.spec, period=self.period,
                                                  t_blow=self.t_blow, damage=self.damage_from),
                "totals": _plain(self.totals), "units": self.units,
                "blows": _records(self.table), "checks": _records(self.checks),
                "folder": self.folder}

    def to_json(self) -> str:
        """:meth:`to_dict` as JSON text (no NaN: undefined values are null)."""
        return json.dumps(self.to_dict(), allow_nan=False)

    def to_csv(self, path: str | os.PathLike) -> None:
        """Write the table to ``path`` as CSV (an undefined value: an empty cell).

        Parameters
        ----------
        path : str or path-like
            The file.
        """
        from pdbfs.files import whole
        with whole(path) as part:
            self.table.to_csv(part, index=False)

    def plot(self, path: str | os.PathLike | None = None, title: str | None = None) -> Figure:
        """The campaign against the blow: its peak pressure (with the rule's
        band), its striker setting, the oil's temperature, the damage summed.

        Parameters
        ----------
        path : str or path-like, optional
            Save the figure there (PNG, SVG, PDF by its suffix).
        title : str, optional
            The figure's title (default: the rig and its blows).

        Returns
        -------
        matplotlib.figure.Figure
        """
        import matplotlib.pyplot as plt
        t = self.table
        n = t["blow"].to_numpy()
        heat = bool(np.all(np.isfinite(t["oil_temperature"].to_numpy(dtype=float))))
        rows = 4 if heat else 3
        fig, axes = plt.subplots(rows, 1, figsize=(7, 2.0 * rows + 0.6), sharex=True)
        ax = axes[0]
        ax.plot(n, t["peak_pressure"] * 1e-6, lw=1.0, color="C0")
        if self.band is not None:
            for level in self.band:
                ax.axhline(level * 1e-6, color="0.5", lw=0.8, ls="--")
        ax.set_ylabel("peak pressure\n(MPa)")
        ax = axes[1]
        for k, name in enumerate(self.settings):
            ax.plot(n, t[name], lw=1.0, color=f"C{k + 1}", label=name)
        if self.settings:
            ax.legend(fontsize=8, loc="best")
        ax.set_ylabel("setting")
        if heat:
            ax = axes[2]
            ax.plot(n, t["oil_temperature"] - 273.15, lw=1.0, color="C3")
            ax.set_ylabel("oil at the blow\n(°C)")
        ax = axes[-1]
        ax.plot(n, np.cumsum(t["damage"].to_numpy(dtype=float)), lw=1.0, color="C4")
        ax.set_ylabel("damage\n(summed)")
        ax.set_xlabel("blow")
        for ax in axes:
            ax.grid(True, alpha=0.3)
        axes[0].set_title(title or f"rig {self.rig}: {len(t)} blows, one every {self.period:g} s")
        fig.tight_layout()
        if path is not None:
            save_figure(fig, path, dpi=130)
        return fig

    def text(self, rows: int = 12) -> str:
        """A plain-text report for the command line.

        Parameters
        ----------
        rows : int
            How many blows the table shows, spread over the campaign.

        Returns
        -------
        str
            The totals and the table.
        """
        t = self.table
        pick = np.unique(np.linspace(0, len(t) - 1, min(rows, len(t))).round().astype(int))
        cols = ["blow", "time", *self.settings, "peak_pressure", "pulse_duration",
                "oil_temperature", "energy_dissipated", "damage"]
        lines = [t.iloc[pick][cols].to_string(index=False, na_rep="n/a",
                                               float_format=lambda v: f"{v:.6g}")]
        o = self.totals
        lines.append(f"damage {o['damage']:.6g} over {o['blows']} blows "
                     f"({o['duration']:.6g} s); predicted life {o['life_blows']:.6g} blows")
        if o["heat_balance"] is not None:
            lines.append(f"heat: dissipated {o['energy_dissipated']:.6g} J = stored "
                         f"{o['heat_stored']:.6g} J + lost {o['heat_lost']:.6g} J (balance "
                         f"{o['heat_balance']:.1e})")
        if o["damage_left_out"] is not None and self.damage_from == "history":
            lines.append(f"damage read from every blow's whole history; its peak alone leaves "
                         f"out at most {100 * o['damage_left_out']:.3g} %")
        elif o["damage_left_out"] is not None:
            lines.append(f"damage read from the peaks; the whole history of {len(self.checks)} "
                         f"blows adds at most {100 * o['damage_left_out']:.3g} %")
        return "\n".join(lines)


def _plain(v: Any) -> Any:
    """``v`` with NaN and infinity as None (JSON has neither) and numpy scalars as numbers."""
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, (float, np.floating)):
        return float(v) if math.isfinite(v) else None
    if isinstance(v, np.integer):
        return int(v)
    return v


def _records(frame) -> list:
    """A DataFrame's rows as plain dicts."""
    cols = list(frame.columns)
    data = [frame[c].tolist() for c in cols]
    return [{c: _plain(x) for c, x in zip(cols, row)} for row in zip(*data)]

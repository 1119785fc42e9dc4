"""A Result's exports (a dict, CSV, pandas, a plot) and how it shows
itself (a readable line, an HTML table for notebooks): mixed into Result."""
from __future__ import annotations

import csv
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import PdbfsError
from pdbfs.files import whole

from ..setup.settings import name_list
from .c_summary import summary_of
from .reprs import number, table

if TYPE_CHECKING:
    import os

    import pandas as pd
    from matplotlib.figure import Figure

#: rows of a CSV formatted at a time (Result.to_csv)
CSV_ROWS = 20000


class ResultExports:
    """What a Result writes and shows; the rest is Result's (result.py)."""

    def _cheap_summary(self) -> dict | None:
        """The summary if it costs nothing now: computed already, or the
        compiled run's own; else None (a repr integrates nothing)."""
        if "_summary" not in self.__dict__ and self._fast is not None:
            d = summary_of(self._sim, self._fast)
            if d is not None:
                self._summary, self._summary_warnings = d, []
        return self.__dict__.get("_summary")

    def _shown(self) -> tuple[str, list[tuple[str, str]]]:
        t = self.__dict__.get("t", self._shared[0])
        st = self.stats
        rows = [("time", f"{t[0]:g} .. {t[-1]:g} s, {len(t)} points"),
                ("solver", f"{st.get('method', '?')} ({st.get('backend', '?')}), "
                 f"{st.get('steps', '?')} steps")]
        s = self._cheap_summary()
        if s is None:
            rows.append(("summary", "not computed yet: .summary()"))
        else:
            from .summary import UNITS as SUMMARY_UNITS
            if "complete" in s:
                rows.append(("pulse", "complete" if s["complete"] else
                             "incomplete (it outlasts the run)"))
            for key in ("peak_pressure", "time_of_peak", "pulse_duration"):
                if key in s and not isinstance(s[key], (list, tuple, dict)):
                    rows.append((key, number(s[key], SUMMARY_UNITS.get(key, ""))))
        return f"Result of rig {self.rig}", rows

    def __repr__(self) -> str:
        title, rows = self._shown()
        return f"<{title}: " + "; ".join(f"{k} {v}" for k, v in rows) + ">"

    def _repr_html_(self) -> str:
        return table(*self._shown())

    def as_dict(self, names: str | Sequence[str] | None = None) -> dict[str, np.ndarray]:
        """Time and variables as numpy arrays.

        Parameters
        ----------
        names : str or sequence of str, optional
            The variables (default: every one).

        Returns
        -------
        dict
            ``{"time": t, name: values, ...}``, SI units.
        """
        names = self.names if names is None else name_list(names, "names", distinct=False)
        return {"time": self.t, **{n: self[n] for n in names}}

    def to_csv(self, path: str | os.PathLike, names: str | Sequence[str] | None = None,
               progress: Callable[[int, int], object] | None = None) -> str | os.PathLike:
        """Write time and variables as CSV, SI units in the header
        (``name [unit]``), written whole or not at all. Written a block of
        rows at a time (the outputs computed for those rows only, unless the
        Result holds them): the memory it takes does not grow with the run.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.
        names : str or sequence of str, optional
            The variables (default: every one).
        progress : callable, optional
            Called with (rows written, rows in all) after each block.

        Returns
        -------
        str or os.PathLike
            ``path``.

        Raises
        ------
        KeyError
            For a name the rig does not have.
        pdbfs.PdbfsError
            For a value that is NaN or infinite; nothing is written.
        """
        names = self.names if names is None else name_list(names, "names", distinct=False)
        for n in names:
            if n not in self:
                self[n]                                  # its KeyError, with suggestions
        idx = [self._index.get(n) for n in names]
        n_rows = len(self.t)
        # few names, or outputs at hand: whole rows (kept on the Result, as before)
        held = self._Y is not None or len(names) <= 8 or None in idx or \
            all(i in self._rows for i in idx)
        row = ",".join(["%r"] * (len(names) + 1))     # what csv.writer writes, a third sooner
        with whole(path) as part, open(part, "w", newline="") as fh:
            csv.writer(fh).writerow(["time [s]"] + [f"{n} [{self.units[n]}]" for n in names])
            for a in range(0, n_rows, CSV_ROWS):
                b = min(n_rows, a + CSV_ROWS)
                cols = [self[n][a:b] for n in names] if held else \
                    self._sim.outputs(self.t[a:b], self._X[:, a:b], self._Z[:, a:b], self.p, idx)
                data = np.vstack([self.t[a:b], *cols]).T
                if not np.all(np.isfinite(data)):
                    raise PdbfsError("refusing to write NaN or infinite values to " + str(path))
                fh.write("".join([row % tuple(r) + "\r\n" for r in data.tolist()]))
                if progress is not None:
                    progress(b, n_rows)
        return path

    def to_pandas(self, names: str | Sequence[str] | None = None) -> pd.DataFrame:
        """The variables as a pandas DataFrame indexed by time (s).

        Parameters
        ----------
        names : str or sequence of str, optional
            The variables, the columns (default: every one).

        Returns
        -------
        pandas.DataFrame
            One column per variable, SI units.
        """
        try:
            import pandas as pd
        except ImportError:
            raise PdbfsError("to_pandas() needs pandas: pip install pandas") from None
        d = self.as_dict(names)
        t = d.pop("time")
        return pd.DataFrame(d, index=pd.Index(t, name="time"))

    def plot(self, names: str | Sequence[str] | None = None, path: str | os.PathLike | None = None,
             title: str | None = None) -> Figure:
        """Plot variables against time in ms, one panel per unit.

        Parameters
        ----------
        names : str or sequence of str, optional
            The variables (default: the rig's pressure and contact force,
            and its bodies' positions; else its states).
        path : str or os.PathLike, optional
            An image file to save the figure to (its format by its suffix:
            .png, .pdf, .svg).
        title : str, optional
            The figure's title (default: the rig, the run's time and the
            parameters set away from their defaults).

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from .plotting import plot_result
        return plot_result(self, names, path, title)

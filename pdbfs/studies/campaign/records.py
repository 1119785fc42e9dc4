"""The records of a campaign's blows, held as columns (a few numbers a blow,
whatever the campaign's length) and read by an operator's rule as a
sequence of dicts, oldest first. The blows of the chunk at hand are dicts
until their chunk is done (their damage is reckoned a chunk at a time)."""
from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import pandas as pd

#: the columns a rule does not see: reckoned a chunk at a time, not yet known for the
#: blows of the chunk at hand
HIDDEN = ("damage_peak", "damage")


class Blows(Sequence):
    """The blows so far, oldest first: ``blows[i]`` is the record of blow
    ``i + 1``, a dict of the table's columns but the damage (``damage_peak``
    and ``damage``)."""

    def __init__(self):
        self._chunks: list[dict] = []       # column name -> numpy array, per chunk done
        self._starts: list[int] = []
        self._done = 0
        self.pending: list[dict] = []       # the chunk at hand

    def __len__(self) -> int:
        return self._done + len(self.pending)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        n = len(self)
        k = i + n if i < 0 else i
        if not 0 <= k < n:
            raise IndexError(f"blow {i} of {n}")
        if k >= self._done:
            return {c: v for c, v in self.pending[k - self._done].items() if c not in HIDDEN}
        j = bisect.bisect_right(self._starts, k) - 1
        cols, row = self._chunks[j], k - self._starts[j]
        return {c: v[row].item() for c, v in cols.items() if c not in HIDDEN}

    def add(self, record: dict) -> None:
        """Blow ``len(self) + 1``'s record."""
        self.pending.append(record)

    def seal(self, columns: dict) -> None:
        """The chunk at hand done, as ``columns`` (columns(self.pending), or a
        chunk read back from a campaign's folder)."""
        self._starts.append(self._done)
        self._chunks.append(columns)
        self._done += len(columns["blow"])
        self.pending = []

    def frame(self) -> pd.DataFrame:
        """Every blow done as one DataFrame (a column a chunk lacks: NaN there)."""
        import pandas as pd
        names = list(dict.fromkeys(c for cols in self._chunks for c in cols))
        return pd.DataFrame({c: np.concatenate([cols[c] if c in cols else
                                                np.full(len(cols["blow"]), math.nan)
                                                for cols in self._chunks]) for c in names})


def columns(records: list[dict]) -> dict:
    """Records as columns (a chunk file's): a setting a rule set late is NaN before."""
    names = list(dict.fromkeys(k for r in records for k in r))
    return {k: np.array([r.get(k, math.nan) for r in records],
                        dtype=np.int64 if k == "blow" else float) for k in names}

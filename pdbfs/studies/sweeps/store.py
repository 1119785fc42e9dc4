"""A sweep on disk: ``manifest.json`` (what sweep this is, and a hash of it)
and one file per chunk of points (Parquet by default, or CSV), each written
to a temporary name and renamed, so a file that exists is complete.

Running the same sweep again into the same folder skips the chunks already
there: a sweep that was killed, or lost a Dask worker, resumes where it
stopped, and nothing is computed twice or lost. A folder that holds another
sweep is refused.
"""
from __future__ import annotations

import hashlib
import json
import time
from pathlib import Path

import numpy as np

from pdbfs.errors import ParameterError, require_extra
from pdbfs.files import whole, write_text

MANIFEST = "manifest.json"
CHUNKS = "chunks"
FORMATS = ("parquet", "csv")


def spec_hash(spec: dict) -> str:
    """A short hash of a sweep's specification (its manifest)."""
    return hashlib.sha256(json.dumps(spec, sort_keys=True, default=str).encode()).hexdigest()[:16]


class Store:
    """A sweep's folder: its manifest (what was asked) and the chunks computed so far."""

    #: what the folder holds, as messages name it, and its rows' order column and unit
    WHAT, ORDER, UNIT = "sweep", "point", "points"

    def __init__(self, path, spec: dict, n_points: int, chunk_size: int, fmt: str = "parquet",
                 overwrite: bool = False):
        if fmt not in FORMATS:
            raise ParameterError(f"unknown {self.WHAT} file format {fmt!r}; choose "
                                 f"{' or '.join(FORMATS)}")
        if fmt == "parquet":
            require_extra("parquet", f"{self.WHAT} files in Parquet (format='parquet', "
                          "--format parquet)")
        self.dir, self.fmt = Path(path), fmt
        self.spec = {**spec, "format": fmt, "chunk_size": int(chunk_size), "n_points": int(n_points)}
        self.hash = spec_hash(self.spec)
        manifest = self.dir / MANIFEST
        if self.dir.exists() and not self.dir.is_dir():
            raise ParameterError(f"{self.WHAT} output {self.dir} is a file, not a folder")
        old = self._read_manifest(manifest)
        if old is not None and old.get("hash") != self.hash:
            if not overwrite:
                raise ParameterError(
                    f"{self.dir} holds another {old.get('spec', {}).get('kind', 'sweep')} (rig "
                    f"{old.get('spec', {}).get('rig', '?')}, "
                    f"{old.get('spec', {}).get('n_points', '?')} {self.UNIT}, started "
                    f"{old.get('started', '?')}); choose another output folder, or overwrite it "
                    "(--overwrite)")
            self._clear()
            old = None
        elif old is None and self.chunk_files():
            if not overwrite:
                raise ParameterError(f"{self.dir} holds chunk files but no {MANIFEST}: not a "
                                     f"{self.WHAT} this can resume; choose another output folder")
            self._clear()
        self.chunk_dir.mkdir(parents=True, exist_ok=True)
        if old is None:
            write_text(manifest, json.dumps(
                {"hash": self.hash, "started": time.strftime("%Y-%m-%d %H:%M:%S"),
                 "spec": self.spec}, indent=1, default=str) + "\n")

    @classmethod
    def open(cls, path) -> "Store":
        """The sweep already in ``path`` (read only: no manifest is written)."""
        self = cls.__new__(cls)
        self.dir = Path(path)
        old = cls._read_manifest(self.dir / MANIFEST)
        if old is None:
            raise ParameterError(f"{self.dir} holds no {cls.WHAT} ({MANIFEST} is missing)")
        self.spec, self.hash, self.fmt = old["spec"], old["hash"], old["spec"].get("format", "parquet")
        return self

    @classmethod
    def _read_manifest(cls, path: Path):
        if not path.is_file():
            return None
        try:
            return json.loads(path.read_text())
        except (OSError, ValueError):
            raise ParameterError(f"{path} is not a readable {cls.WHAT} manifest; choose another "
                                 "output folder") from None

    def _clear(self):
        for f in self.chunk_files():
            f.unlink()
        (self.dir / MANIFEST).unlink(missing_ok=True)

    @property
    def chunk_dir(self) -> Path:
        """The chunk files, alone in their folder: ``pandas.read_parquet`` reads it whole."""
        return self.dir / CHUNKS

    def chunk_files(self) -> list[Path]:
        """The chunk files written so far, in order."""
        if not self.chunk_dir.is_dir():
            return []
        return sorted(p for p in self.chunk_dir.glob("chunk-*.*")
                      if p.suffix in (".parquet", ".csv"))

    def path_of(self, chunk_id: int) -> Path:
        """The file of chunk ``chunk_id``."""
        return self.chunk_dir / f"chunk-{chunk_id:06d}.{self.fmt}"

    def done(self) -> set[int]:
        """The numbers of the chunks written (a resumed sweep skips them)."""
        return {int(p.stem.split("-")[1]) for p in self.chunk_files() if p.suffix == f".{self.fmt}"}

    def write(self, chunk_id: int, columns: dict):
        """Write one chunk (a dict of equal-length columns) atomically."""
        path = self.path_of(chunk_id)
        with whole(path) as part:
            if self.fmt == "parquet":
                import pyarrow as pa
                import pyarrow.parquet as pq
                table = pa.table({k: pa.array(v, from_pandas=True) for k, v in columns.items()})
                pq.write_table(table, part)
            else:
                import pandas as pd
                pd.DataFrame(columns).to_csv(part, index=False)

    def _files(self) -> list[Path]:
        return [p for p in self.chunk_files() if p.suffix == f".{self.fmt}"]

    def _read_one(self, path, columns=None):
        import pandas as pd
        if self.fmt == "parquet":
            return pd.read_parquet(path, columns=columns)
        return pd.read_csv(path, keep_default_na=True, dtype={"error": str}, usecols=columns)

    def failures(self) -> int:
        """How many saved points failed, read a chunk at a time (the error column only)."""
        n = 0
        for p in self._files():
            err = self._read_one(p, ["error"])["error"]
            n += int((err.notna() & (err.astype(str) != "")).sum())
        return n

    def rows(self) -> int:
        """How many points are saved, without reading them whole."""
        n = 0
        for p in self._files():
            if self.fmt == "parquet":
                import pyarrow.parquet as pq
                n += pq.ParquetFile(p).metadata.num_rows
            else:
                n += len(self._read_one(p, [self.ORDER]))
        return n

    def head(self, k: int):
        """The first ``k`` saved points (in point order), from the first chunks only."""
        import pandas as pd
        parts, got = [], 0
        for p in self._files():           # chunk c holds the points from c * chunk_size on
            if got >= k:
                break
            parts.append(self._read_one(p))
            got += len(parts[-1])
        if not parts:
            return pd.DataFrame()
        df = pd.concat(parts, ignore_index=True)
        if "error" in df:
            df["error"] = df["error"].fillna("")
        return df.sort_values(self.ORDER, kind="stable").head(k).reset_index(drop=True)

    def read(self):
        """Every chunk as one pandas DataFrame, in point order."""
        import pandas as pd
        files = [p for p in self.chunk_files() if p.suffix == f".{self.fmt}"]
        if files and self.fmt == "parquet":
            require_extra("parquet", f"reading the Parquet files of the {self.WHAT} in {self.dir}")
        if not files:
            return pd.DataFrame()
        read = pd.read_parquet if self.fmt == "parquet" else \
            (lambda p: pd.read_csv(p, keep_default_na=True, dtype={"error": str}))
        df = pd.concat([read(p) for p in files], ignore_index=True)
        if "error" in df:
            df["error"] = df["error"].fillna("")
        return df.sort_values(self.ORDER, kind="stable").reset_index(drop=True)


def saved_points(path) -> int:
    """How many points of the sweep in ``path`` are saved (0 if none)."""
    try:
        store = Store.open(path)
    except ParameterError:
        return 0
    return store.rows()


def refuse_other_sweep(path, overwrite: bool = False):
    """For results written beside no chunks (a small sweep kept in memory): a
    folder holding a chunked sweep is refused, or cleared with ``overwrite``."""
    path = Path(path)
    if (path / MANIFEST).is_file():
        if not overwrite:
            raise ParameterError(f"{path} holds another sweep ({MANIFEST} and its chunks); "
                                 "choose another output folder, or overwrite it (--overwrite)")
        for f in path.glob("chunk-*.*"):
            f.unlink()
        (path / MANIFEST).unlink()


def chunk_columns(chunk, names, keys) -> dict:
    """A Chunk as the columns of its file: point, parameters, summary, error."""
    cols = {"point": np.asarray(chunk.index, dtype=np.int64)}
    for j, n in enumerate(names):
        cols[n] = chunk.params[:, j]
    for k in keys:
        cols[k] = chunk.summary[k]
    cols["error"] = list(chunk.error)
    return cols


"""The rig's inputs in a sweep: the same for every point (``inputs=``), or
a dimension of the sweep (an input's name in ``values`` with a list of
traces, numbers or functions: each point takes one of them; the sweep's
column of that name holds the number itself where every item is a number,
else the item's place in the list, from 0).

Every trace is checked (and a function sampled, input_function.py) once, before
any point runs, on the sweep's own horizon: a point never meets a bad
trace, and what travels to workers is arrays and numbers only. Where every
input of every point is a number, the inputs are entries of the points'
parameter vectors and the compiled summary driver runs them as it runs
parameters; otherwise each point is a run with inputs (driven.py).
"""
from __future__ import annotations

import hashlib

import numpy as np

from pdbfs.errors import ParameterError
from pdbfs.simulation.setup.input_traces import drive_of, input_trace


class SweepInputs:
    """``fixed`` {name: number or (t, u)} for every point, ``dims`` {name:
    [number or (t, u), ...]} swept (a column of trace numbers)."""

    def __init__(self, dae, fixed: dict, dims: dict):
        self.dae, self.fixed, self.dims = dae, fixed, dims
        self.rows = dae.input_rows()

    @property
    def constant(self) -> bool:
        """Every input of every point a number (no trace)."""
        return all(isinstance(v, float) for v in self.fixed.values()) and \
            all(isinstance(v, float) for vs in self.dims.values() for v in vs)

    def numbers(self, name) -> bool:
        """Whether the dimension ``name`` is numbers (its column holds them)."""
        return all(isinstance(v, float) for v in self.dims[name])

    def of_point(self, names, row) -> dict:
        """The inputs of one point: ``row`` its values of the sweep's ``names``."""
        out = dict(self.fixed)
        for name, values in self.dims.items():
            v = row[names.index(name)]
            out[name] = float(v) if self.numbers(name) else values[int(v)]
        return out

    def set_constants(self, P, names, block):
        """Numbers only (``constant``): each point's inputs written into its
        parameter vector (value, slope 0, t_ref 0) - the rows of P."""
        u0 = self.rows[0]
        index = {n: k for k, n in enumerate(self.dae.input_names)}
        for name, v in self.fixed.items():
            P[:, u0 + index[name]] = v
        for name in self.dims:
            P[:, u0 + index[name]] = block[:, names.index(name)]     # numbers: the column

    def key(self) -> str:
        """A digest of every trace and number (a stored sweep's manifest)."""
        h = hashlib.sha256()
        for name, vs in sorted({**{k: [v] for k, v in self.fixed.items()}, **self.dims}.items()):
            h.update(name.encode() + (b"*" if name in self.dims else b"="))
            for v in vs:
                for part in (v if isinstance(v, tuple) else (np.array([v]),)):
                    h.update(np.ascontiguousarray(part, float).tobytes() + b"|")
        return h.hexdigest()[:16]


def split_inputs(sim, values, inputs, t_end, n_out):
    """(the values of the parameters, SweepInputs or None): the input names
    among ``values`` (a dict) become columns of trace numbers, every trace
    checked now on the sweep's grid."""
    dae = sim.dae
    names = dae.input_names
    grid = sim.grid(t_end, n_out)
    fixed = {}
    if inputs is not None:
        drive_of(dae, inputs, grid)            # the names and the dict, as simulate checks them
        fixed = {n: _checked(dae, n, v, grid) for n, v in inputs.items()}
    dims = {}
    if isinstance(values, dict):
        for name in [n for n in values if n in names]:
            given = values[name]
            if not isinstance(given, (list, tuple)) or not given or \
                    (isinstance(given, tuple) and len(given) == 2 and not callable(given[0])
                     and np.ndim(given[0]) == 1):
                raise ParameterError(f"sweep: input {name} takes a list of traces (t, u), "
                                     "numbers or functions of time, one per point of its "
                                     "dimension")
            if name in fixed:
                raise ParameterError(f"sweep: input {name} is both swept and given in inputs=")
            dims[name] = [_checked(dae, name, v, grid) for v in given]
        values = {n: ([float(x) for x in dims[n]] if all(isinstance(x, float) for x in dims[n])
                      else list(range(len(dims[n])))) if n in dims else v
                  for n, v in values.items()}
    if not fixed and not dims:
        return values, None
    return values, SweepInputs(dae, fixed, dims)


def _checked(dae, name, given, grid):
    """A number (float) or a checked trace (t, u) of arrays."""
    t, u = input_trace(dae, name, given, grid)
    return float(u[0]) if t.size == 1 else (t, u)

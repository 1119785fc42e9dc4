"""What a Simulator evaluates on a whole output grid at once: outputs, their
time derivatives and the event indicators (numpy replay of the CasADi
expressions where it applies, else CasADi's map), cached per Simulator."""
from __future__ import annotations

import casadi as ca
import numpy as np

from ..setup.vectorize import vectorize


def _column(p):
    """p as one column for every point, or (a run with inputs) one per point."""
    return p if p.ndim == 2 else p.reshape(-1, 1)


class OnGrid:
    """Mixed into Simulator (which has ``dae`` and ``_cache``)."""

    def outputs(self, grid, X, Z, p, rows=None) -> np.ndarray:
        """Outputs ``rows`` (indices into dae.y; all if None) on the grid."""
        key = ("out", None if rows is None else tuple(rows))
        f = self._cache.get(key)
        if f is None:
            dae = self.dae
            y = dae.y if rows is None else ca.vertcat(*[dae.y[i] for i in rows])
            fun = ca.Function("out", [dae.t, dae.x, dae.z, dae.p], [y])
            fast = vectorize(fun)
            if fast is not None:
                f = lambda t, X, Z, p: fast(t, X, Z, _column(p))[0]
            else:
                f = lambda t, X, Z, p: fun.map(len(t))(t.reshape(1, -1), X, Z, p).full()
            self._cache[key] = f
        return f(np.asarray(grid, float).reshape(1, -1), X, Z, p)

    def _vectorised(self, key, build):
        """A function of (t, X, Z, p) on whole grids (numpy replay, else map), cached."""
        f = self._cache.get(key)
        if f is None:
            fun = build()
            fast = vectorize(fun)
            if fast is not None:
                f = lambda t, X, Z, p: fast(t, X, Z, _column(p))[0]   # noqa: E731
            else:
                f = lambda t, X, Z, p: fun.map(t.shape[1])(t, X, Z, p).full()   # noqa: E731
            self._cache[key] = f
        return f

    def rates_on(self, grid, X, Z, p, name):
        """d(name)/dt on the grid, from the DAE: (d y/dx) der(x) + d y/dt; None
        for rigs with algebraic variables (their derivatives are not at hand)."""
        dae = self.dae
        if not dae.is_ode:
            return None
        y = dae.y[dae.y_names.index(name)]

        def build():
            rate = ca.jtimes(y, dae.x, dae.ode) + ca.jacobian(y, dae.t)
            return ca.Function("rate", [dae.t, dae.x, dae.z, dae.p], [rate])
        f = self._vectorised(("rate", name), build)
        return f(np.asarray(grid, float).reshape(1, -1), X, Z, p).ravel()

    def events_on(self, grid, X, Z, p):
        """The event indicators on the grid (one row each)."""
        dae = self.dae
        f = self._vectorised(("events",), lambda: ca.Function(
            "ev", [dae.t, dae.x, dae.z, dae.p], [dae.events]))
        return np.atleast_2d(f(np.asarray(grid, float).reshape(1, -1), X, Z, p)) \
            if dae.events.numel() else np.zeros((0, len(grid)))

    def rows_rates_events(self, grid, X, Z, p, names):
        """Outputs ``names``, their time derivatives (None for rigs with
        algebraic variables) and the event indicators on the grid, in one
        pass (what a summary reads: one numpy replay instead of one per row)."""
        dae = self.dae
        rows = [dae.y_names.index(n) for n in names]

        def build():
            ys = [dae.y[i] for i in rows]
            rates = [ca.jtimes(y, dae.x, dae.ode) + ca.jacobian(y, dae.t) for y in ys] \
                if dae.is_ode else []
            return ca.Function("rows", [dae.t, dae.x, dae.z, dae.p],
                               [ca.vertcat(*ys, *rates, dae.events)])
        f = self._vectorised(("rows+rates+events", tuple(rows)), build)
        out = np.atleast_2d(f(np.asarray(grid, float).reshape(1, -1), X, Z, p))
        n = len(rows)
        return out[:n], (out[n:2 * n] if dae.is_ode else None), out[(2 if dae.is_ode else 1) * n:]

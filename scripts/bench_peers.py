"""The paper rig written by hand for the peers of the benchmarks
(bench_simulate.py, bench_sweep.py): numbalsoda's DOP853 with a numba
right-hand side (one run; a numba ``prange`` sweep), diffrax's Dopri8 under
JAX, and the cubic Hermite refinement of the peak pressure they need (the
2001-point grid maximum alone is about 6e-6 low). Each returns None when its
package is not installed."""
import numpy as np

P_NAMES = ("m1", "m2", "m3", "k1", "n", "D", "k2", "k3", "c2", "A")


def _hermite_peak(t, s, v, scale):
    """max of scale * s on the cubic Hermite interpolant of (s, ds/dt = v),
    around the largest sample (s: oil column compression, v its rate)."""
    k = int(np.argmax(s))
    best = s[k]
    for i in (k - 1, k):
        if i < 0 or i + 1 >= t.size:
            continue
        h = t[i + 1] - t[i]
        a, b = s[i], v[i] * h
        c = 3 * (s[i + 1] - s[i]) - (2 * v[i] + v[i + 1]) * h
        d = 2 * (s[i] - s[i + 1]) + (v[i] + v[i + 1]) * h
        # roots of b + 2 c x + 3 d x^2 in (0, 1) (written for numba: no lists)
        A, B, C = 3 * d, 2 * c, b
        r1, r2 = -1.0, -1.0
        if abs(A) < 1e-300:
            if B != 0:
                r1 = -C / B
        else:
            disc = B * B - 4 * A * C
            if disc >= 0:
                r1 = (-B + np.sqrt(disc)) / (2 * A)
                r2 = (-B - np.sqrt(disc)) / (2 * A)
        for x in (r1, r2):
            if 0 < x < 1:
                val = a + x * (b + x * (c + x * d))
                if val > best:
                    best = val
    return scale * max(best, 0.0)


def hermite_peak(t, Y, k2, A):
    """Peak pressure from states Y (6 x n: x1, v1, x2, v2, x3, v3)."""
    return _hermite_peak(t, Y[2] - Y[4], Y[3] - Y[5], k2 / A)


def _data(p):
    return np.array([p[k] for k in P_NAMES], dtype=np.float64)


_NB = {}


def _numba():
    """(rhs address, dop853, njit peak) of numbalsoda, compiled once; None without it."""
    if "fns" in _NB:
        return _NB["fns"]
    try:
        from numba import cfunc, njit, prange
        from numbalsoda import dop853, lsoda_sig
    except ImportError:
        _NB["fns"] = None
        return None

    @cfunc(lsoda_sig)
    def rhs(t, u, du, p):
        d = u[0] - u[2]
        dn = d ** p[4] if d > 0 else 0.0
        fc = p[3] * dn + p[5] * dn * (u[1] - u[3])
        if fc < 0:
            fc = 0.0
        do = u[2] - u[4]
        fo = p[6] * do if do > 0 else 0.0
        du[0] = u[1]
        du[1] = -fc / p[0]
        du[2] = u[3]
        du[3] = (fc - fo - p[8] * u[3]) / p[1]
        du[4] = u[5]
        du[5] = (fo - p[7] * u[4]) / p[2]

    peak = njit(_hermite_peak)

    @njit
    def one(fp, u0, t, data, rtol, atol):
        usol, ok = dop853(fp, u0, t, data=data, rtol=rtol, atol=atol)
        return peak(t, usol[:, 2] - usol[:, 4], usol[:, 3] - usol[:, 5], data[6] / data[9])

    @njit(parallel=True)
    def many(fp, V, K, t, base, rtol, atol, out):
        for i in prange(V.size):
            data = base.copy()
            data[6] = K[i]
            u0 = np.zeros(6)
            u0[1] = V[i]
            usol, ok = dop853(fp, u0, t, data=data, rtol=rtol, atol=atol)
            out[i] = peak(t, usol[:, 2] - usol[:, 4], usol[:, 3] - usol[:, 5], K[i] / base[9])

    _NB["fns"] = (rhs.address, one, many)
    return _NB["fns"]


def numbalsoda_single(t, p, rtol=1e-8, atol=1e-10):
    """A function running one simulation and returning its Hermite peak."""
    fns = _numba()
    if fns is None:
        return None
    fp, one, _ = fns
    data, u0 = _data(p), np.array([0, p["v0"], 0, 0, 0, 0], dtype=np.float64)
    return lambda: one(fp, u0, t, data, rtol, atol)


def numbalsoda_sweep(t, p, V, K, rtol=1e-8, atol=1e-10):
    """A function running the sweep over (V[i], K[i]) in a numba prange loop,
    returning the peaks."""
    fns = _numba()
    if fns is None:
        return None
    fp, _, many = fns
    base = _data(p)

    def run():
        out = np.empty(V.size)
        many(fp, V, K, t, base, rtol, atol, out)
        return out
    return run


def diffrax_single(t, p, rtol=1e-8, atol=1e-10):
    """diffrax Dopri8 under jax.jit (CPU, float64): one simulation, Hermite peak."""
    try:
        import jax
        jax.config.update("jax_enable_x64", True)
        import diffrax
        import jax.numpy as jnp
    except ImportError:
        return None
    q = {k: float(p[k]) for k in P_NAMES}

    def f(tt, u, args):
        d = u[0] - u[2]
        dn = jnp.where(d > 0, jnp.abs(d) ** q["n"], 0.0)
        fc = jnp.maximum(q["k1"] * dn + q["D"] * dn * (u[1] - u[3]), 0.0)
        fo = q["k2"] * jnp.maximum(u[2] - u[4], 0.0)
        return jnp.array([u[1], -fc / q["m1"], u[3], (fc - fo - q["c2"] * u[3]) / q["m2"], u[5],
                          (fo - q["k3"] * u[4]) / q["m3"]])

    ts = jnp.asarray(t)

    @jax.jit
    def solve(v0):
        sol = diffrax.diffeqsolve(diffrax.ODETerm(f), diffrax.Dopri8(), 0.0, float(t[-1]), None,
                                  jnp.array([0.0, v0, 0.0, 0.0, 0.0, 0.0]),
                                  saveat=diffrax.SaveAt(ts=ts),
                                  stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol),
                                  max_steps=200000)
        return sol.ys

    def run():
        Y = np.asarray(solve(float(p["v0"]))).T
        return hermite_peak(t, Y, p["k2"], p["A"])
    return run


def diffrax_sweep(t, p, V, K, rtol=1e-8, atol=1e-10):
    """diffrax Dopri8 under jax.jit(jax.vmap) over (V[i], K[i]): the peaks."""
    try:
        import jax
        jax.config.update("jax_enable_x64", True)
        import diffrax
        import jax.numpy as jnp
    except ImportError:
        return None
    q = {k: float(p[k]) for k in P_NAMES}

    def f(tt, u, k2):
        d = u[0] - u[2]
        dn = jnp.where(d > 0, jnp.abs(d) ** q["n"], 0.0)
        fc = jnp.maximum(q["k1"] * dn + q["D"] * dn * (u[1] - u[3]), 0.0)
        fo = k2 * jnp.maximum(u[2] - u[4], 0.0)
        return jnp.array([u[1], -fc / q["m1"], u[3], (fc - fo - q["c2"] * u[3]) / q["m2"], u[5],
                          (fo - q["k3"] * u[4]) / q["m3"]])

    ts = jnp.asarray(t)

    def solve(v0, k2):
        sol = diffrax.diffeqsolve(diffrax.ODETerm(f), diffrax.Dopri8(), 0.0, float(t[-1]), None,
                                  jnp.array([0.0, v0, 0.0, 0.0, 0.0, 0.0]), args=k2,
                                  saveat=diffrax.SaveAt(ts=ts),
                                  stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol),
                                  max_steps=200000)
        return sol.ys

    many = jax.jit(jax.vmap(solve))

    def run():
        Y = np.asarray(many(jnp.asarray(V), jnp.asarray(K)))
        return np.array([_hermite_peak(t, Y[i, :, 2] - Y[i, :, 4], Y[i, :, 3] - Y[i, :, 5],
                                       K[i] / p["A"]) for i in range(V.size)])
    return run

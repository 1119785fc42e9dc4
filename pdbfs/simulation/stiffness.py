"""Which method suits a rig: ``method="auto"``, the cheapest by the cost
model of pdbfs.native.stiffness (steps the modes allow x the cost of a step).

The modes are the eigenvalues of d(ode)/dx at the start: dense for small
rigs, the few of largest modulus (ARPACK) for large ones. Impact rigs are
mostly oscillating chains: a chain of masses and stiff springs rings at its
highest modes, which every method must resolve, and the explicit method of
order 8 takes 5-10 times fewer steps than CVODE's (compiled backend). A mode
that decays fast without oscillating holds the explicit method and Adams to
short steps but not BDF: that is where BDF is the cheaper method. A rig whose
stiffness appears only later (a contact that closes) is judged by its start:
pass ``method=`` to override. Through CasADi the choice is between Adams and
BDF.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from pdbfs.native.stiffness import DENSE_UP_TO, ode_instructions, run_costs

METHOD_NAMES = {"erk": "explicit Runge-Kutta 8(5,3)", "adams": "CVODE Adams", "bdf": "CVODE BDF"}


def jacobian_function(dae) -> ca.Function:
    """d(ode)/dx as a sparse CasADi Function of (t, x, p), cached on the DAE."""
    f = dae.__dict__.get("_jac_x")
    if f is None:
        f = ca.Function("jac_x", [dae.t, dae.x, dae.p], [ca.jacobian(dae.ode, dae.x)])
        dae.__dict__["_jac_x"] = f
    return f


def fast_modes(dae, p, x0, t0=0.0, k: int = 6) -> np.ndarray:
    """Eigenvalues of d(ode)/dx at (t0, x0): all of them for small rigs,
    the ``k`` of largest modulus for large ones."""
    J = jacobian_function(dae)(t0, x0, p)
    rows, cols = J.sparsity().get_triplet()
    n = dae.x.numel()
    values = np.asarray(J.nonzeros(), float)
    if not np.all(np.isfinite(values)):
        return np.zeros(0, complex)
    if n <= DENSE_UP_TO or values.size == 0:      # (no scipy: a one-shot run starts sooner)
        A = np.zeros((n, n))
        A[rows, cols] = values
        return np.linalg.eigvals(A)
    import scipy.sparse as sps
    import scipy.sparse.linalg as spla
    A = sps.csc_matrix((values, (rows, cols)), shape=(n, n))
    try:
        return spla.eigs(A, k=min(k, n - 2), which="LM", return_eigenvectors=False,
                         maxiter=20 * n, tol=1e-3)
    except spla.ArpackNoConvergence as err:   # what did converge still tells
        return np.asarray(err.eigenvalues, complex)


def rates(lam) -> tuple[float, float, float]:
    """(the largest modulus of the eigenvalues ``lam``; the fastest decay
    -Re lambda of a mode that does not oscillate, |Re| > |Im|; the largest
    modulus of a mode that does, |Im| >= |Re|; 0 where none): all the choice
    below needs of them."""
    lam = np.asarray(lam, complex)
    decaying = np.abs(lam.real) > np.abs(lam.imag)
    return (float(np.max(np.abs(lam), initial=0.0)), float(np.max(-lam[decaying].real, initial=0.0)),
            float(np.max(np.abs(lam[~decaying]), initial=0.0)))


def decide(fastest: float, rate: float, osc: float, n: int, instructions: float, t_end: float,
           methods=("erk", "adams", "bdf")) -> tuple[str, str]:
    """(the cheapest of ``methods`` for a run of ``t_end`` s, why) from the
    modes' ``rates``, the state count and the right-hand side's instructions
    (t_end infinite: a run of unknown length, by the cost of each second)."""
    cost = run_costs(fastest, rate, osc, n, instructions, t_end)
    best = min(methods, key=cost.__getitem__)        # (a tie: the first)
    # (no comprehension, lambda or generator: each is a Python call, counted as above)
    priced = []
    for m in methods:
        priced.append(f"{m} {cost[m]:.3g}")
    unit = "ns a second" if t_end == float("inf") else "ns"
    why = (f"the cheapest by the estimate ({', '.join(priced)} {unit}): "
           f"the fastest mode ({fastest:.3g} rad/s), the fastest oscillating {osc:.3g} rad/s")
    if rate > 0:
        why += f", a mode decays at {rate:.3g} 1/s without oscillating"
    return best, why


def choose_method(dae, p, x0, t_end: float, lam=None) -> tuple[str, str]:
    """("adams" or "bdf", why) for integrating ``dae`` over [0, t_end] from x0
    through CasADi (``lam``: fast_modes' answer, if at hand)."""
    if not dae.is_ode or dae.x.numel() == 0:
        return "bdf", "a DAE rig (IDAS uses BDF)"
    lam = fast_modes(dae, p, x0) if lam is None else lam
    return decide(*rates(lam), dae.x.numel(), ode_instructions(dae), t_end, ("adams", "bdf"))


def auto_method(dae, p, x0, t_end: float, lib=None, backend: str = "c") -> tuple[str, str]:
    """method="auto" for a run of ``t_end`` from x0: (the method, why): in the
    compiled backend (``backend`` "c") the cheapest of "erk", "adams" and
    "bdf", else of "adams" and "bdf". The modes come from the compiled library
    ``lib`` where given (pdbfs_modes.c, the FMU's C too: a few microseconds,
    where CasADi's Jacobian and LAPACK took longer than the run), else from
    fast_modes."""
    # (a library is of an ODE with states; casadi's numel is a Python call, and a loop
    # over new parameters decides at every run: tests/test_run_overhead.py counts them)
    modes = lib.modes(x0, p) if lib is not None and lib.nx <= DENSE_UP_TO else None
    if modes is not None:
        n = lib.nx
    elif not dae.is_ode or dae.x.numel() == 0:
        return "bdf", "a DAE rig (IDAS uses BDF)"
    else:
        n, modes = dae.x.numel(), rates(fast_modes(dae, p, x0))
    methods = ("erk", "adams", "bdf") if backend == "c" else ("adams", "bdf")
    instructions = dae.__dict__.get("_ode_instructions") or ode_instructions(dae)
    return decide(*modes, n, instructions, t_end, methods)

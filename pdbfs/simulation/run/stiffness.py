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

A choice is made once per rig and class of runs (:func:`cached_method`): the
estimate reads the Jacobian at the start, so runs whose states and
parameters that Jacobian depends on are the same (a loop over a parameter
it does not read) share one choice, found by those values; and runs whose
modes come out the same share the cost model's verdict.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from pdbfs.native.stiffness import DENSE_UP_TO, ode_instructions, run_costs

from ..state import state_of

METHOD_NAMES = {"erk": "explicit Runge-Kutta 8(5,3)", "adams": "CVODE Adams", "bdf": "CVODE BDF"}
#: choices kept per rig: a loop over new parameters makes them anew past this
AUTO_MAX = 4096


def jacobian_function(dae) -> ca.Function:
    """d(ode)/dx as a sparse CasADi Function of (t, x, p), made once per DAE."""
    state = state_of(dae)
    if state.jac_x is None:
        state.jac_x = ca.Function("jac_x", [dae.t, dae.x, dae.p], [ca.jacobian(dae.ode, dae.x)])
    return state.jac_x


def estimate_inputs(dae) -> tuple[np.ndarray, np.ndarray]:
    """(the states, the parameters) whose values d(ode)/dx depends on, as
    index arrays: all that method="auto"'s estimate reads of a run's start
    (its Jacobian at t = 0: no rig's depends on time there). Made once per DAE
    from the Jacobian's sparsity."""
    state = state_of(dae)
    if state.auto_inputs is None:
        J = jacobian_function(dae)

        def read(i):
            return np.unique(np.asarray(J.jac_sparsity(0, i).get_col(), dtype=np.intp))
        state.auto_inputs = (read(1), read(2))
    return state.auto_inputs


def cached_method(sim, p, x0, span: float, backend: str) -> str:
    """method="auto" for a run of ``sim`` (a Simulator) of ``span`` s from
    ``x0`` at parameters ``p``: auto_method's choice, made once per class of
    runs. Found first by the values the estimate reads (estimate_inputs; a
    new value of one of them is a new class), then by the modes they give
    (runs with other values but the same modes: the same verdict)."""
    if not sim.dae.is_ode or sim.dae.x.numel() == 0:      # (no modes: nothing to cache)
        return _decide(sim.dae, None, 0, span, backend)[0]
    state = sim.state
    ix, ip = state.auto_inputs or estimate_inputs(sim.dae)
    key = (backend == "c", span, x0[ix].tobytes(), p[ip].tobytes())
    method = state.auto.get(key)
    if method is None:
        if len(state.auto) >= AUTO_MAX:
            state.auto.clear()
        lib = sim.compiled() if backend == "c" and sim.nx else None
        rates, n = start_rates(sim.dae, p, x0, lib)
        verdict = ("modes", backend == "c", span, rates, n)
        method = state.auto.get(verdict)
        if method is None:
            method = state.auto[verdict] = _decide(sim.dae, rates, n, span, backend)[0]
        state.auto[key] = method
    return method


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
    priced = [f"{m} {cost[m]:.3g}" for m in methods]
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
    return _decide(dae, *start_rates(dae, p, x0, lib), t_end, backend)


def start_rates(dae, p, x0, lib=None) -> tuple[tuple | None, int]:
    """(the modes' rates at the start, the number of states): from the
    compiled library ``lib`` where given and small enough, else from
    fast_modes; (None, 0) for a DAE rig or one without states."""
    modes = lib.modes(x0, p) if lib is not None and lib.nx <= DENSE_UP_TO else None
    if modes is not None:
        return modes, lib.nx
    if not dae.is_ode or dae.x.numel() == 0:
        return None, 0
    return rates(fast_modes(dae, p, x0)), dae.x.numel()


def _decide(dae, modes, n, t_end, backend) -> tuple[str, str]:
    if modes is None:
        return "bdf", "a DAE rig (IDAS uses BDF)"
    methods = ("erk", "adams", "bdf") if backend == "c" else ("adams", "bdf")
    return decide(*modes, n, ode_instructions(dae), t_end, methods)

"""Which linear multistep method suits a rig: ``method="auto"``.

CVODE's Adams methods take steps no longer than about 1/|lambda| for the
fastest eigenvalue lambda of the Jacobian; its BDF methods are stable for
fast *decaying* modes at any step but lose accuracy and stability on fast
*oscillating* ones (orders 3-5 are not stable near the imaginary axis).
Impact rigs are mostly the second kind: a chain of masses and stiff
springs rings at its highest mode, and Adams is the cheaper method there
(measured on the split piston, N = 10 ... 200: Adams needs 15-30 % fewer
steps than BDF). A rig is stiff in BDF's sense when a fast mode decays
without oscillating (|Re lambda| > |Im lambda|) and would force Adams into
more than ``STIFF_STEPS`` steps over the run.

The eigenvalues are those of d(ode)/dx at the start: dense for small rigs,
the few of largest modulus (ARPACK) for large ones. A rig whose stiffness
appears only later (a contact that closes) is judged by its start: pass
``method=`` to override.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

# the thresholds (STIFF_STEPS: a fast decaying mode's Adams steps that make BDF
# the cheaper method; DENSE_UP_TO: above, only the modes of largest modulus;
# ERK_RADIANS: the longest run, in radians of the fastest mode, given the
# explicit method) are shared with the FMU's C
from pdbfs.native.stiffness import DENSE_UP_TO, ERK_RADIANS, STIFF_STEPS  # noqa: F401


def jacobian_function(dae) -> ca.Function:
    """d(ode)/dx as a sparse CasADi Function of (t, x, p), made once per DAE."""
    from ..state import state_of
    state = state_of(dae)
    if state.jac_x is None:
        state.jac_x = ca.Function("jac_x", [dae.t, dae.x, dae.p], [ca.jacobian(dae.ode, dae.x)])
    return state.jac_x


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


def rates(lam) -> tuple[float, float]:
    """(the largest modulus of the eigenvalues ``lam``, the fastest decay
    -Re lambda of a mode that does not oscillate, |Re| > |Im|; 0 if none):
    all the choice below needs of them."""
    lam = np.asarray(lam, complex)
    decaying = lam[np.abs(lam.real) > np.abs(lam.imag)]
    return float(np.max(np.abs(lam), initial=0.0)), float(np.max(-decaying.real, initial=0.0))


def decide(fastest: float, rate: float, t_end: float) -> tuple[str, str, bool]:
    """(CVODE's method, "adams" or "bdf"; why; whether the explicit method
    suits the run instead) from the modes' ``rates`` and the run's length."""
    if rate * t_end > STIFF_STEPS:
        return "bdf", (f"a mode decays at {rate:.3g} 1/s without oscillating: Adams would need "
                       f"about {rate * t_end:.3g} steps"), False
    return ("adams", f"the fastest mode ({fastest:.3g} rad/s) oscillates or is slow: not stiff",
            fastest * t_end <= ERK_RADIANS)


def choose_method(dae, p, x0, t_end: float, lam=None) -> tuple[str, str]:
    """("adams" or "bdf", why) for integrating ``dae`` over [0, t_end] from x0
    (``lam``: fast_modes' answer, if at hand)."""
    if not dae.is_ode or dae.x.numel() == 0:
        return "bdf", "a DAE rig (IDAS uses BDF)"
    lam = fast_modes(dae, p, x0) if lam is None else lam
    return decide(*rates(lam), t_end)[:2]


def auto_method(dae, p, x0, t_end: float, lib=None) -> tuple[str, str, bool]:
    """method="auto" for a run of ``t_end`` from x0: decide()'s answer. The
    modes come from the compiled library ``lib`` where given (the FMU's C,
    pdbfs_modes.c: a few microseconds, where CasADi's Jacobian and LAPACK
    took longer than the run), else from fast_modes."""
    if lib is not None and lib.nx <= DENSE_UP_TO:     # (a library is of an ODE with states)
        found = lib.modes(x0, p)
        if found is not None:
            return decide(*found, t_end)
    if not dae.is_ode or dae.x.numel() == 0:
        return (*choose_method(dae, p, x0, t_end), False)
    return decide(*rates(fast_modes(dae, p, x0)), t_end)

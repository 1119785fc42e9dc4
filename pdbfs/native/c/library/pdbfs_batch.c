/*
 * pdbfs generic batch driver: one whole simulation over an output grid in
 * one call, for pdbfs.simulate(..., backend="c").
 *
 * This file is the same for every rig (compiled once per machine).
 * Everything model-specific comes from two generated files, linked in:
 *   pdbfs_batch_model.c  pdbfs_rig: sizes (states, parameters, event
 *                        indicators, CasADi work arrays; pdbfs_batch_model.h)
 *   pdbfs_model_funcs.c  CasADi-generated C of pdbfs_ode, pdbfs_jac and
 *                        pdbfs_events
 * The integration itself (CVODE through the non-smooth points, dense output)
 * is native/c/pdbfs_cvode.c, shared with the FMU; CVODE's stop time is the
 * last output time.  With one state more than the rig has (a rig with a
 * contact force role), the last is the contact force's impulse, integrated
 * with the states (pdbfs_ode_q, left out of the error test): the summary's
 * impulses on the solution, whatever the output grid (summary.py).
 *
 * Thread safe and reentrant: every call allocates its own CVODE memory and
 * CasADi work arrays.  Never aborts: every failure is a return code, the time
 * reached and a message.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_batch_model.h"
#include "pdbfs_cvode.h"
#include "pdbfs_erk.h"
#include "pdbfs_modes.h"

#define NX PDBFS_NX
#define NP PDBFS_NP
#define NE PDBFS_NE
#define NQ (PDBFS_ROLE_FORCE >= 0 ? 1 : 0)   /* the contact force's impulse (pdbfs_ode_q) */

#define API __attribute__((visibility("default")))

/* version of the calling convention below: the Python side checks it */
#define PDBFS_BATCH_ABI 10

/* return codes (CVODE's own failures return CVODE's negative flag) */
#define RC_OK 0
#define RC_BAD_INPUT 1       /* sizes, grid, tolerances: nothing was integrated */
#define RC_SETUP 2           /* CVODE or memory could not be set up */
#define RC_TOO_MUCH_WORK PDBFS_CV_TOO_MUCH_WORK   /* max_num_steps steps between two outputs */
#define RC_NOT_FINITE 4      /* NaN or infinity in the solution */
#define RC_LIMIT 8           /* a variable at its declared range's bound (pdbfs_record.h) */

/* pdbfs_record.h */
int pdbfs_limit_near(PdbfsEval *ev, double t0, const double *x0, double t, const double *x,
                     char *msg, size_t len);

/* info[] slots */
#define INFO_T 0             /* time reached (last successful CVODE step, or t_end) */
#define INFO_STEPS 1         /* internal steps */
#define INFO_ROOTS 2         /* restarts at roots of the event indicators */
#define INFO_RHS 3           /* right-hand side evaluations */
#define INFO_FLAG 4          /* CVODE flag of the failure, 0 if none */
#define INFO_JAC 5           /* Jacobian evaluations */
#define INFO_METHOD 6        /* the solver used: method | nls << 4 | linsol << 8 (auto resolved) */
#define INFO_N 7

typedef struct {
    char *msg;
    size_t msglen;
} Msg;

static void setmsg(Msg *c, const char *fmt, ...) {
    va_list ap;
    if (!c->msg || c->msglen == 0) return;
    va_start(ap, fmt);
    vsnprintf(c->msg, c->msglen, fmt, ap);
    va_end(ap);
}

/* keep CVODE's last error message (warnings and events are dropped) */
static void keep_error(void *env, int kind, const char *text) {
    if (kind == PDBFS_LOG_ERROR) setmsg((Msg *)env, "%s", text);
}

static int all_finite(const double *v, long n) {
    long i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* Sizes compiled in: out[0..2] = states, parameters, event indicators. */
API int pdbfs_batch_abi(void) { return PDBFS_BATCH_ABI; }

API void pdbfs_batch_sizes(long long *out) {
    if (!out) return;
    out[0] = NX;
    out[1] = NP;
    out[2] = NE;
}

/* The modes of d(ode)/dx at (t0, x0) with the parameters p (pdbfs_modes.h),
 * for method "auto": out[0] the largest modulus of an eigenvalue, out[1] the
 * fastest decay of a mode that does not oscillate, out[2] the largest modulus
 * of a mode that does.  pdbfs_modes_at's code
 * (0; 1: the Jacobian is not finite there; -1: no convergence), or RC_SETUP
 * when out of memory. */
API int pdbfs_batch_modes(const double *p, const double *x0, double t0, double *out) {
    PdbfsEval ev;
    void *block = pdbfs_eval_alloc(&ev, PDBFS_SZ_ARG, PDBFS_SZ_RES, PDBFS_SZ_IW, PDBFS_SZ_W);
    double *work = malloc(sizeof(double) * pdbfs_modes_work(NX));
    int rc = RC_SETUP;
    out[0] = out[1] = out[2] = 0.0;
    if (block && work) {
        ev.p = p;
        rc = pdbfs_modes_at(&ev, NX, t0, x0, work, out, out + 1, out + 2);
    }
    free(work);
    free(block);
    return rc;
}

/* For a run with new parameters p, in one call: the start values x0 (NX,
 * pdbfs_start: the compiled drivers' start) and the components' conditions c
 * (pdbfs_conditions, each >= 0 where p is consistent).  Either may be NULL.
 * 0, or RC_SETUP when out of memory. */
API int pdbfs_batch_start(const double *p, double *x0, double *c) {
    PdbfsEval ev;
    void *block = pdbfs_eval_alloc(&ev, PDBFS_SZ_ARG, PDBFS_SZ_RES, PDBFS_SZ_IW, PDBFS_SZ_W);
    if (!block) return RC_SETUP;
    ev.arg[0] = p;
    if (x0) {
        ev.res[0] = x0;
        pdbfs_start(ev.arg, ev.res, ev.iw, ev.w, 0);
    }
    if (c) {
        ev.res[0] = c;
        pdbfs_conditions(ev.arg, ev.res, ev.iw, ev.w, 0);
    }
    free(block);
    return RC_OK;
}

/*
 * Integrate from (t[0], x0) and write the state at every t[k] into
 * X[i * nt + k] (state-major: row i is state i over the grid).
 *
 *   nx, np        must equal the compiled sizes (nx one more with a contact
 *                 force: its impulse is the last state, x0's last entry its
 *                 start value)
 *   t             nt >= 2 finite, strictly increasing times
 *   rtol, atol    positive; atol applies to every state
 *   method        solver code: 0 Adams, 1 BDF, | nls << 4 (0 auto, 1 fixed
 *                 point, 2 Newton; Adams only) | linsol << 8 (0 auto, 1 dense,
 *                 2 band; see pdbfs_cvode.h)
 *   max_step      largest internal step (0: no limit)
 *   max_num_steps most internal steps between two output points
 *   info[7]       time reached, steps, roots, rhs evaluations, CVODE flag,
 *                 Jacobian evaluations, the solver code used (INFO_*)
 *   msg           message on failure (msglen bytes, always terminated)
 *
 * Returns 0, a positive RC_* code or CVODE's negative flag.  On failure the
 * output points before info[INFO_T] are filled in.
 */
API int pdbfs_batch_run(long long nx, long long np, const double *p, const double *x0,
                        long long nt, const double *t, double *X, double rtol, double atol,
                        int method, double max_step, long long max_num_steps, double *info,
                        char *msg, long long msglen) {
    Msg c;
    PdbfsEval ev;
    PdbfsCvode s;
    PdbfsCvodeSettings set = {0};
    double *atolv = NULL, *x;   /* on the heap: a large rig's state would fill a thread's stack */
    void *work = NULL;
    long long k, i;
    double treached;
    int flag, rc = RC_OK;

    c.msg = msg;
    c.msglen = msg && msglen > 0 ? (size_t)msglen : 0;
    if (c.msglen) msg[0] = 0;
    if (info) for (i = 0; i < INFO_N; i++) info[i] = 0.0;
    if (!info || !t || !X || !x0 || (NP > 0 && !p)) {
        setmsg(&c, "NULL argument");
        return RC_BAD_INPUT;
    }
    info[INFO_T] = nt > 0 ? t[0] : 0.0;
    if ((nx != NX && !(NQ && nx == NX + NQ)) || np != NP) {
        setmsg(&c, "sizes: %lld states and %lld parameters given, the library has %d and %d", nx, np, NX, NP);
        return RC_BAD_INPUT;
    }
    if (nt < 2) {
        setmsg(&c, "need at least 2 output times, got %lld", nt);
        return RC_BAD_INPUT;
    }
    for (k = 0; k < nt; k++) {
        if (!isfinite(t[k]) || (k > 0 && !(t[k] > t[k - 1]))) {
            setmsg(&c, "output times must be finite and strictly increasing (t[%lld] = %g)", k, t[k]);
            return RC_BAD_INPUT;
        }
    }
    if (!(rtol > 0) || !(atol > 0) || !isfinite(rtol) || !isfinite(atol)) {
        setmsg(&c, "rtol = %g, atol = %g: must be positive", rtol, atol);
        return RC_BAD_INPUT;
    }
    if (!(max_step >= 0) || !isfinite(max_step)) {
        setmsg(&c, "max_step = %g: must be >= 0 (0: no limit)", max_step);
        return RC_BAD_INPUT;
    }
    if (max_num_steps < 1) {
        setmsg(&c, "max_num_steps = %lld: must be >= 1", max_num_steps);
        return RC_BAD_INPUT;
    }
    if (!PDBFS_CODE_VALID(method) && method != PDBFS_ERK) {
        setmsg(&c, "solver code %d: method 0 (Adams) or 1 (BDF) | nls << 4 | linsol << 8, "
               "or 2 (explicit Runge-Kutta)", method);
        return RC_BAD_INPUT;
    }
    if (!all_finite(x0, (long)nx) || !all_finite(p, NP)) {
        setmsg(&c, "start values or parameters are not finite");
        return RC_BAD_INPUT;
    }

    if (method == PDBFS_ERK)
        return pdbfs_batch_run_erk((int)nx, p, x0, nt, t, X, rtol, atol, max_step, max_num_steps,
                                   info, msg, msglen);
    work = pdbfs_eval_alloc(&ev, PDBFS_SZ_ARG, PDBFS_SZ_RES, PDBFS_SZ_IW, PDBFS_SZ_W);
    atolv = malloc(sizeof(double) * 2 * (NX + NQ + 1));
    if (!work || !atolv) {
        free(work);
        free(atolv);
        setmsg(&c, "out of memory");
        return RC_SETUP;
    }
    x = atolv + NX + NQ + 1;
    ev.p = p;

    for (i = 0; i < nx; i++) atolv[i] = i < NX ? atol : 1e300;   /* the impulse: no error test */
    set.method = PDBFS_CODE_METHOD(method);
    set.nls = PDBFS_CODE_NLS(method);
    set.linsol = PDBFS_CODE_LINSOL(method);
    set.rtol = rtol;
    set.atol = atolv;
    set.max_step = max_step;
    set.t_stop = t[nt - 1];
    pdbfs_cvode_init(&s, (int)nx, NE, &ev, keep_error, &c);
    s.nte = PDBFS_NTE;   /* CVODE stops at each switch time */
    if (nx > NX) {       /* with the impulse */
        s.ode = pdbfs_ode_q;
        s.jac = pdbfs_jac_q;
        s.jac_sp = pdbfs_jac_q_sparsity_out(0);
    }
    treached = t[0];
    for (i = 0; i < nx; i++) X[i * nt] = x0[i];
    flag = pdbfs_cvode_start(&s, &set, t[0], x0);
    if (flag) {
        if (c.msglen && !msg[0]) setmsg(&c, "CVODE setup failed (flag %d)", flag);
        rc = RC_SETUP;
    }
    for (k = 1; k < nt && rc == RC_OK; k++) {
        flag = pdbfs_cvode_advance(&s, t[k], t[nt - 1], (long)max_num_steps, x);
        if (flag) {
            if (s.tn > treached) treached = s.tn;
            if (flag < 0) {
                if (c.msglen && !msg[0]) setmsg(&c, "CVODE failed (flag %d)", flag);
                info[INFO_FLAG] = flag;
            }
            rc = flag;
            break;
        }
        if (!all_finite(x, (long)nx)) {
            setmsg(&c, "the solution is NaN or infinite at t = %.17g", t[k]);
            rc = RC_NOT_FINITE;
            break;
        }
        for (i = 0; i < nx; i++) X[i * nt + k] = x[i];
        treached = t[k];
    }

#ifndef PDBFS_NO_CVODE
    /* a failure as a variable reached its declared range's bound: say which */
    if (rc && rc != RC_SETUP && pdbfs_limit_near(&ev, t[0], x0, s.tn, N_VGetArrayPointer(s.y),
                                                 msg, c.msglen))
        rc = RC_LIMIT;
#endif
    info[INFO_T] = treached;
    info[INFO_STEPS] = (double)s.steps;
    info[INFO_ROOTS] = (double)s.roots;
    info[INFO_RHS] = (double)s.rhs_evals;
    info[INFO_JAC] = (double)s.jac_evals;
    info[INFO_METHOD] = (double)(s.method | s.nls << 4 | s.linsol << 8);
    pdbfs_cvode_free(&s);
    free(work);
    free(atolv);
    if (c.msglen) msg[c.msglen - 1] = 0;
    return rc;
}

/*
 * pdbfs generic batch driver: one whole simulation over an output grid in
 * one call, for pdbfs.simulate(..., backend="c").
 *
 * This file is the same for every rig.  Everything model-specific comes from
 * two generated files:
 *   pdbfs_batch_model.h  sizes (states, parameters, event indicators, CasADi
 *                        work arrays)
 *   pdbfs_model_funcs.c  CasADi-generated C of pdbfs_ode, pdbfs_jac (d ode/dx,
 *                        dense, column major) and pdbfs_events
 *
 * CVODE (SUNDIALS 6.x, linked statically, symbols hidden): Adams-Moulton with
 * fixed-point iteration, or BDF with Newton, dense LU and the CasADi
 * Jacobian.  CVODE runs in one-step mode up to the last output time (its stop
 * time); the event indicators are root functions and CVODE is restarted at
 * every root (the right-hand side is not smooth there); the output points
 * are interpolated from CVODE's dense output (CVodeGetDky), so the trajectory
 * does not depend on the output grid.
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

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "pdbfs_batch_model.h"
#include "pdbfs_model_funcs.h"

#define NX PDBFS_NX
#define NP PDBFS_NP
#define NE PDBFS_NE

#define API __attribute__((visibility("default")))

/* version of the calling convention below: the Python side checks it */
#define PDBFS_BATCH_ABI 1

/* methods */
#define METHOD_ADAMS 0
#define METHOD_BDF 1

/* return codes (CVODE's own failures return CVODE's negative flag) */
#define RC_OK 0
#define RC_BAD_INPUT 1       /* sizes, grid, tolerances: nothing was integrated */
#define RC_SETUP 2           /* CVODE or memory could not be set up */
#define RC_TOO_MUCH_WORK 3   /* max_num_steps steps between two output points */
#define RC_NOT_FINITE 4      /* NaN or infinity in the solution */

/* info[] slots */
#define INFO_T 0             /* time reached (last successful CVODE step, or t_end) */
#define INFO_STEPS 1         /* internal steps */
#define INFO_ROOTS 2         /* restarts at roots of the event indicators */
#define INFO_RHS 3           /* right-hand side evaluations */
#define INFO_FLAG 4          /* CVODE flag of the failure, 0 if none */
#define INFO_N 5

typedef struct {
    const double *p;
    const casadi_real **arg;
    casadi_real **res;
    casadi_int *iw;
    casadi_real *w;
    long nrhs;
    char *msg;
    size_t msglen;
} Ctx;

static void setmsg(Ctx *c, const char *fmt, ...) {
    va_list ap;
    if (!c->msg || c->msglen == 0) return;
    va_start(ap, fmt);
    vsnprintf(c->msg, c->msglen, fmt, ap);
    va_end(ap);
}

typedef int (*casadi_fn)(const casadi_real **, casadi_real **, casadi_int *, casadi_real *, int);

static int call_txp(Ctx *c, casadi_fn f, double t, const double *x, double *out) {
    double tt = t;
    c->arg[0] = &tt;
    c->arg[1] = x;
    c->arg[2] = NULL;
    c->arg[3] = c->p;
    c->res[0] = out;
    return f(c->arg, c->res, c->iw, c->w, 0);
}

static int all_finite(const double *v, long n) {
    long i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static int cv_rhs(realtype t, N_Vector y, N_Vector ydot, void *ud) {
    Ctx *c = (Ctx *)ud;
    double *yd = N_VGetArrayPointer(ydot);
    c->nrhs++;
    if (call_txp(c, pdbfs_ode, t, N_VGetArrayPointer(y), yd)) return -1;
    return all_finite(yd, NX) ? 0 : 1;   /* recoverable: CVODE retries with a smaller step */
}

static int cv_jac(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *ud,
                  N_Vector t1, N_Vector t2, N_Vector t3) {
    Ctx *c = (Ctx *)ud;
    double *jd = SUNDenseMatrix_Data(J); /* column major, like CasADi */
    (void)fy; (void)t1; (void)t2; (void)t3;
    if (call_txp(c, pdbfs_jac, t, N_VGetArrayPointer(y), jd)) return -1;
    return all_finite(jd, (long)NX * NX) ? 0 : 1;
}

static int cv_root(realtype t, N_Vector y, realtype *g, void *ud) {
    Ctx *c = (Ctx *)ud;
    return call_txp(c, pdbfs_events, t, N_VGetArrayPointer(y), g) ? -1 : 0;
}

/* keep CVODE's last error message (warnings are dropped: nothing is printed) */
static void cv_err(int code, const char *module, const char *function, char *msg, void *ud) {
    Ctx *c = (Ctx *)ud;
    (void)module;
    if (code < 0) setmsg(c, "%s (%s, flag %d)", msg ? msg : "", function ? function : "?", code);
}

/* Sizes compiled in: out[0..2] = states, parameters, event indicators. */
API int pdbfs_batch_abi(void) { return PDBFS_BATCH_ABI; }

API void pdbfs_batch_sizes(long long *out) {
    if (!out) return;
    out[0] = NX;
    out[1] = NP;
    out[2] = NE;
}

/*
 * Integrate from (t[0], x0) and write the state at every t[k] into
 * X[i * nt + k] (state-major: row i is state i over the grid).
 *
 *   nx, np        must equal the compiled sizes
 *   t             nt >= 2 finite, strictly increasing times
 *   rtol, atol    positive; atol applies to every state
 *   method        0 Adams (fixed point), 1 BDF (Newton, dense LU, exact Jacobian)
 *   max_step      largest internal step (0: no limit)
 *   max_num_steps most internal steps between two output points
 *   info[5]       time reached, steps, roots, rhs evaluations, CVODE flag
 *   msg           message on failure (msglen bytes, always terminated)
 *
 * Returns 0, a positive RC_* code or CVODE's negative flag.  On failure the
 * output points before info[INFO_T] are filled in.
 */
API int pdbfs_batch_run(long long nx, long long np, const double *p, const double *x0,
                        long long nt, const double *t, double *X, double rtol, double atol,
                        int method, double max_step, long long max_num_steps, double *info,
                        char *msg, long long msglen) {
    Ctx c;
    SUNContext ctx = NULL;
    N_Vector y = NULL, tmp = NULL;
    SUNMatrix A = NULL;
    SUNLinearSolver LS = NULL;
    SUNNonlinearSolver NLS = NULL;
    void *cv = NULL;
    void *work = NULL;
    long long k, i, steps = 0, since_out = 0, roots = 0;
    double tend, tret, limit, treached = 0.0;
    int flag = 0, rc = RC_OK;

    memset(&c, 0, sizeof c);
    c.msg = msg;
    c.msglen = msg && msglen > 0 ? (size_t)msglen : 0;
    if (c.msglen) msg[0] = 0;
    if (info) for (i = 0; i < INFO_N; i++) info[i] = 0.0;
    if (!info || !t || !X || !x0 || (NP > 0 && !p)) {
        setmsg(&c, "NULL argument");
        return RC_BAD_INPUT;
    }
    info[INFO_T] = nt > 0 ? t[0] : 0.0;
    if (nx != NX || np != NP) {
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
    if (method != METHOD_ADAMS && method != METHOD_BDF) {
        setmsg(&c, "method = %d: 0 (Adams) or 1 (BDF)", method);
        return RC_BAD_INPUT;
    }
    if (!all_finite(x0, NX) || !all_finite(p, NP)) {
        setmsg(&c, "start values or parameters are not finite");
        return RC_BAD_INPUT;
    }

    /* CasADi work arrays, one block */
    {
        size_t sz = sizeof(double) * (PDBFS_SZ_W + 1) + sizeof(casadi_int) * (PDBFS_SZ_IW + 1)
                    + sizeof(double *) * (PDBFS_SZ_ARG + 1) + sizeof(double *) * (PDBFS_SZ_RES + 1);
        char *b = (char *)malloc(sz);
        if (!b) {
            setmsg(&c, "out of memory");
            return RC_SETUP;
        }
        work = b;
        c.w = (casadi_real *)b;
        b += sizeof(double) * (PDBFS_SZ_W + 1);
        c.arg = (const casadi_real **)b;
        b += sizeof(double *) * (PDBFS_SZ_ARG + 1);
        c.res = (casadi_real **)b;
        b += sizeof(double *) * (PDBFS_SZ_RES + 1);
        c.iw = (casadi_int *)b;
    }
    c.p = p;

    tend = t[nt - 1];
    treached = t[0];
    for (i = 0; i < NX; i++) X[i * nt] = x0[i];

#define SETUP(cond, what) do { if (!(cond)) { setmsg(&c, "CVODE setup failed: %s", what); rc = RC_SETUP; goto done; } } while (0)
    SETUP(SUNContext_Create(NULL, &ctx) == 0, "SUNContext_Create");
    y = N_VNew_Serial(NX, ctx);
    tmp = N_VNew_Serial(NX, ctx);
    SETUP(y && tmp, "N_VNew_Serial");
    for (i = 0; i < NX; i++) NV_Ith_S(y, i) = x0[i];
    cv = CVodeCreate(method == METHOD_ADAMS ? CV_ADAMS : CV_BDF, ctx);
    SETUP(cv, "CVodeCreate");
    SETUP(CVodeSetErrHandlerFn(cv, cv_err, &c) == CV_SUCCESS, "CVodeSetErrHandlerFn");
    SETUP(CVodeInit(cv, cv_rhs, t[0], y) == CV_SUCCESS, "CVodeInit");
    SETUP(CVodeSetUserData(cv, &c) == CV_SUCCESS, "CVodeSetUserData");
    if (method == METHOD_ADAMS) {
        NLS = SUNNonlinSol_FixedPoint(y, 0, ctx);
        SETUP(NLS, "SUNNonlinSol_FixedPoint");
        SETUP(CVodeSetNonlinearSolver(cv, NLS) == CV_SUCCESS, "CVodeSetNonlinearSolver");
    } else {
        A = SUNDenseMatrix(NX, NX, ctx);
        SETUP(A, "SUNDenseMatrix");
        LS = SUNLinSol_Dense(y, A, ctx);
        SETUP(LS, "SUNLinSol_Dense");
        SETUP(CVodeSetLinearSolver(cv, LS, A) == CV_SUCCESS, "CVodeSetLinearSolver");
        SETUP(CVodeSetJacFn(cv, cv_jac) == CV_SUCCESS, "CVodeSetJacFn");
    }
    if (NE > 0) {
        SETUP(CVodeRootInit(cv, NE, cv_root) == CV_SUCCESS, "CVodeRootInit");
        SETUP(CVodeSetNoInactiveRootWarn(cv) == CV_SUCCESS, "CVodeSetNoInactiveRootWarn");
    }
    SETUP(CVodeSStolerances(cv, rtol, atol) == CV_SUCCESS, "CVodeSStolerances");
    SETUP(CVodeSetMaxStep(cv, max_step) == CV_SUCCESS, "CVodeSetMaxStep");
    SETUP(CVodeSetStopTime(cv, tend) == CV_SUCCESS, "CVodeSetStopTime");
#undef SETUP

    k = 1;
    while (k < nt) {
        if (since_out >= max_num_steps) {
            setmsg(&c, "%lld internal steps without reaching the next output time %.10g", since_out, t[k]);
            rc = RC_TOO_MUCH_WORK;
            break;
        }
        flag = CVode(cv, tend, y, &tret, CV_ONE_STEP);
        if (flag < 0) {
            double tc = treached;
            if (CVodeGetCurrentTime(cv, &tc) == CV_SUCCESS && tc > treached) treached = tc;
            if (c.msglen && !msg[0]) setmsg(&c, "CVODE failed (flag %d)", flag);
            info[INFO_FLAG] = flag;
            rc = flag;
            break;
        }
        steps++;
        since_out++;
        /* output points up to the end of this step, or up to the root */
        limit = tret;
        if (flag != CV_ROOT_RETURN) {
            double tn = tret;
            CVodeGetCurrentTime(cv, &tn);
            if (tn > limit) limit = tn;
        }
        if (limit > tend) limit = tend;
        for (; k < nt && t[k] <= limit; k++) {
            double *xv;
            if (t[k] == tret) {
                xv = N_VGetArrayPointer(y);
            } else {
                int f2 = CVodeGetDky(cv, t[k], 0, tmp);
                if (f2 != CV_SUCCESS) {
                    setmsg(&c, "CVodeGetDky failed at t = %.17g (flag %d)", t[k], f2);
                    info[INFO_FLAG] = f2;
                    rc = RC_SETUP;
                    goto done;
                }
                xv = N_VGetArrayPointer(tmp);
            }
            if (!all_finite(xv, NX)) {
                setmsg(&c, "the solution is NaN or infinite at t = %.17g", t[k]);
                rc = RC_NOT_FINITE;
                goto done;
            }
            for (i = 0; i < NX; i++) X[i * nt + k] = xv[i];
            treached = t[k];
            since_out = 0;
        }
        if (tret > treached) treached = tret;
        if (flag == CV_ROOT_RETURN && k < nt) {
            /* restart at the root: the right-hand side is not smooth there */
            roots++;
            flag = CVodeReInit(cv, tret, y);
            if (flag == CV_SUCCESS) flag = CVodeSetStopTime(cv, tend);
            if (flag != CV_SUCCESS) {
                setmsg(&c, "CVodeReInit failed at the root t = %.17g (flag %d)", tret, flag);
                info[INFO_FLAG] = flag;
                rc = RC_SETUP;
                break;
            }
        }
    }

done:
    info[INFO_T] = treached;
    info[INFO_STEPS] = (double)steps;
    info[INFO_ROOTS] = (double)roots;
    info[INFO_RHS] = (double)c.nrhs;
    if (cv) CVodeFree(&cv);
    if (LS) SUNLinSolFree(LS);
    if (NLS) SUNNonlinSolFree(NLS);
    if (A) SUNMatDestroy(A);
    if (y) N_VDestroy(y);
    if (tmp) N_VDestroy(tmp);
    if (ctx) SUNContext_Free(&ctx);
    free(work);
    if (c.msglen) msg[c.msglen - 1] = 0;
    return rc;
}

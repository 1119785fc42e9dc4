/* pdbfs_cvode: see pdbfs_cvode.h.  Never aborts, never prints: failures are
 * return codes, messages go to the caller's log callback. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "pdbfs_cvode.h"

#define NO_MEMORY (-100)

static int arm_time_event(PdbfsCvode *s);

static void say(PdbfsCvode *s, int kind, const char *fmt, ...) PDBFS_PRINTF(3, 4);

static void say(PdbfsCvode *s, int kind, const char *fmt, ...) {
    char buf[512];
    va_list ap;
    if (!s->log) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    s->log(s->env, kind, buf);
}

static int all_finite(const double *v, long n) {
    long i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* ------------------------------------------------------- CVODE callbacks */
static int cv_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *ud) {
    PdbfsCvode *s = (PdbfsCvode *)ud;
    double *yd = N_VGetArrayPointer(ydot);
    s->rhs_evals++;
    if (pdbfs_eval_txp(s->ev, s->ode, t, N_VGetArrayPointer(y), yd)) return -1;
    return all_finite(yd, s->nx) ? 0 : 1;   /* recoverable: CVODE retries with a smaller step */
}

static int cv_root(sunrealtype t, N_Vector y, sunrealtype *g, void *ud) {
    PdbfsCvode *s = (PdbfsCvode *)ud;
    return pdbfs_eval_txp(s->ev, pdbfs_events, t, N_VGetArrayPointer(y), g) ? -1 : 0;
}

static int cv_user_root(sunrealtype t, N_Vector y, sunrealtype *g, void *ud) {
    PdbfsCvode *s = (PdbfsCvode *)ud;
    return s->user_root(s->root_env, t, N_VGetArrayPointer(y), g) ? -1 : 0;
}

/* SUNDIALS 7 reports through its context's handler stack: ours replaces
 * the default one (which prints to stderr) and logs through the host */
static void cv_err(int line, const char *func, const char *file, const char *msg, SUNErrCode code,
                   void *ud, SUNContext ctx) {
    PdbfsCvode *s = (PdbfsCvode *)ud;
    (void)line; (void)file; (void)ctx;
    say(s, code < 0 ? PDBFS_LOG_ERROR : PDBFS_LOG_WARNING, "%s (CVODE %s, flag %d)", msg ? msg : "",
        func ? func : "?", code);
}

/* ------------------------------------------------------------- life cycle */
void pdbfs_cvode_free(PdbfsCvode *s) {
    if (s->cv) CVodeFree(&s->cv);
    if (s->LS) SUNLinSolFree(s->LS);
    if (s->NLS) SUNNonlinSolFree(s->NLS);
    if (s->A) SUNMatDestroy(s->A);
    if (s->y) N_VDestroy(s->y);
    if (s->tmp) N_VDestroy(s->tmp);
    if (s->atol) N_VDestroy(s->atol);
    if (s->ctx) SUNContext_Free(&s->ctx);
    free(s->jac_nz);
    s->jac_nz = NULL;
    free(s->g);
    s->g = NULL;
    s->cv = NULL; s->LS = NULL; s->NLS = NULL; s->A = NULL;
    s->y = NULL; s->tmp = NULL; s->atol = NULL; s->ctx = NULL;
}

static int choose_nls(const PdbfsCvodeSettings *set, int nx) {
    if (set->method == PDBFS_BDF) return PDBFS_NLS_NEWTON;
    if (set->nls == PDBFS_NLS_FIXED_POINT || set->nls == PDBFS_NLS_NEWTON) return set->nls;
    return nx >= PDBFS_NEWTON_FROM ? PDBFS_NLS_NEWTON : PDBFS_NLS_FIXED_POINT;
}

/* a new CVODE memory for set->method, at (t0, y); on failure the caller
 * frees whatever was built */
static int create(PdbfsCvode *s, const PdbfsCvodeSettings *set, double t0) {
    int flag;
    s->cv = CVodeCreate(set->method == PDBFS_ADAMS ? CV_ADAMS : CV_BDF, s->ctx);
    if (!s->cv) return NO_MEMORY;
    s->method = set->method;
    s->nls = choose_nls(set, s->nx);
    flag = CVodeInit(s->cv, cv_rhs, t0, s->y);
    if (flag == CV_SUCCESS) flag = CVodeSetUserData(s->cv, s);
    if (flag == CV_SUCCESS && s->nls == PDBFS_NLS_FIXED_POINT) {
        s->NLS = SUNNonlinSol_FixedPoint(s->y, 0, s->ctx);
        if (!s->NLS) return NO_MEMORY;
        flag = CVodeSetNonlinearSolver(s->cv, s->NLS);
    } else if (flag == CV_SUCCESS) {
        pdbfs_cvode_bandwidths(s);
        s->linsol = pdbfs_cvode_choose_linsol(s, set->linsol);
        free(s->jac_nz);
        s->jac_nz = malloc(sizeof(double) * (size_t)(pdbfs_pattern_nnz(s->jac_sp, s->nx) + 1));
        if (!s->jac_nz) return NO_MEMORY;
        if (s->linsol == PDBFS_LS_BAND) {
            s->A = SUNBandMatrix(s->nx, s->mu, s->ml, s->ctx);
            s->LS = s->A ? pdbfs_cvode_band_solver(s) : NULL;
        } else {
            s->A = SUNDenseMatrix(s->nx, s->nx, s->ctx);
            s->LS = s->A ? SUNLinSol_Dense(s->y, s->A, s->ctx) : NULL;
        }
        if (!s->LS) return NO_MEMORY;
        flag = CVodeSetLinearSolver(s->cv, s->LS, s->A);
        if (flag == CV_SUCCESS) flag = CVodeSetJacFn(s->cv, pdbfs_cvode_jac);
    }
    if (flag == CV_SUCCESS && s->ne > 0) {
        flag = CVodeRootInit(s->cv, s->ne, cv_root);
        if (flag == CV_SUCCESS) flag = CVodeSetNoInactiveRootWarn(s->cv);
    }
    return flag;
}

int pdbfs_cvode_start(PdbfsCvode *s, const PdbfsCvodeSettings *set, double t0, const double *x0) {
    int flag = CV_SUCCESS, i;
    if (s->cv && (s->method != set->method || s->nls != choose_nls(set, s->nx)
                  || (s->A && set->linsol && s->linsol != set->linsol)))
        pdbfs_cvode_free(s);
    if (!s->ctx) {
        if (SUNContext_Create(SUN_COMM_NULL, &s->ctx) != 0) return NO_MEMORY;
        SUNContext_ClearErrHandlers(s->ctx);
        SUNContext_PushErrHandler(s->ctx, cv_err, s);
    }
    if (!s->y) s->y = N_VNew_Serial(s->nx, s->ctx);
    if (!s->tmp) s->tmp = N_VNew_Serial(s->nx, s->ctx);
    if (!s->atol) s->atol = N_VNew_Serial(s->nx, s->ctx);
    if (!s->y || !s->tmp || !s->atol) {
        say(s, PDBFS_LOG_ERROR, "out of memory (N_Vector of %d states)", s->nx);
        pdbfs_cvode_free(s);
        return NO_MEMORY;
    }
    N_VEnableFusedOps_Serial(s->y, 1);   /* one call per linear combination: small rigs are call-bound */
    for (i = 0; i < s->nx; i++) NV_Ith_S(s->y, i) = x0[i];
    for (i = 0; i < s->nx; i++) NV_Ith_S(s->atol, i) = set->atol[i];
    if (!s->cv) flag = create(s, set, t0);
    else flag = CVodeReInit(s->cv, t0, s->y);
    if (flag == CV_SUCCESS && s->roots_changed) {   /* back to the rig's events */
        flag = CVodeRootInit(s->cv, s->ne, s->ne > 0 ? cv_root : NULL);
        s->roots_changed = 0;
    }
    if (flag == CV_SUCCESS) flag = CVodeSVtolerances(s->cv, set->rtol, s->atol);
    if (flag == CV_SUCCESS) flag = CVodeSetMaxStep(s->cv, set->max_step > 0 ? set->max_step : 0.0);
    if (flag == CV_SUCCESS && isfinite(set->t_stop)) flag = CVodeSetStopTime(s->cv, set->t_stop);
    if (flag != CV_SUCCESS) {
        /* half-built or half-set memory is never reused: the next start builds it anew */
        say(s, PDBFS_LOG_ERROR, "CVODE setup failed (flag %d)", flag);
        pdbfs_cvode_free(s);
        return flag < 0 ? flag : NO_MEMORY;
    }
    s->t_stop = set->t_stop;
    s->tn = t0;
    s->root_pending = 0;
    s->steps_since_start = 0;
    flag = arm_time_event(s);
    if (flag != CV_SUCCESS) say(s, PDBFS_LOG_ERROR, "CVODE setup failed (flag %d)", flag);
    return flag;
}

/* --------------------------------------------------------------- stepping */
double pdbfs_next_time_event(PdbfsCvode *s, double t, const double *x) {
    double next = INFINITY, ti, tol;
    int i;
    if (s->nte <= 0 || s->ne <= 0) return INFINITY;
    if (!s->g && !(s->g = malloc(sizeof(double) * (size_t)s->ne))) return INFINITY;
    if (pdbfs_eval_txp(s->ev, pdbfs_events, t, x, s->g)) return INFINITY;
    for (i = 0; i < s->nte && i < s->ne; i++) {
        ti = t - s->g[i];                     /* the indicator is t - t_i */
        tol = 64 * 2.220446049250313e-16 * fmax(fabs(t), fabs(ti));
        if (isfinite(ti) && ti > t + tol && ti < next) next = ti;
    }
    return next;
}

/* stop at the next time event after s->tn (or at the caller's t_stop) */
static int arm_time_event(PdbfsCvode *s) {
    double stop;
    s->t_break = INFINITY;
    if (s->nte <= 0) return CV_SUCCESS;
    s->t_break = pdbfs_next_time_event(s, s->tn, N_VGetArrayPointer(s->y));
    stop = s->t_break < s->t_stop ? s->t_break : s->t_stop;
    /* a stop time outlives CVodeReInit: past the last event, one out of reach */
    return CVodeSetStopTime(s->cv, isfinite(stop) ? stop : 1e300);
}

/* restart at the pending root: the right-hand side is not smooth there */
static int restart_at_root(PdbfsCvode *s) {
    int flag = CVodeGetDky(s->cv, s->t_root, 0, s->y);
    if (flag == CV_SUCCESS) flag = CVodeReInit(s->cv, s->t_root, s->y);
    if (flag == CV_SUCCESS && isfinite(s->t_stop)) flag = CVodeSetStopTime(s->cv, s->t_stop);
    if (flag != CV_SUCCESS) {
        say(s, PDBFS_LOG_ERROR, "restart at the root t = %.17g failed (flag %d)", s->t_root, flag);
        return flag;
    }
    say(s, PDBFS_LOG_EVENT, "event at t=%.17g, CVODE restarted", s->t_root);
    s->roots++;
    s->root_pending = 0;
    s->tn = s->t_root;
    s->steps_since_start = 0;
    flag = arm_time_event(s);
    if (flag != CV_SUCCESS) say(s, PDBFS_LOG_ERROR, "no stop at the next time event (flag %d)", flag);
    return flag;
}

int pdbfs_cvode_advance(PdbfsCvode *s, double t_out, double horizon, long max_steps, double *x_out) {
    long n = 0;
    int flag, i;
    double tret;
    for (;;) {
        if (s->root_pending && s->t_root <= t_out) {
            flag = restart_at_root(s);
            if (flag) return flag;
        }
        if (s->tn >= t_out || (s->root_pending && s->t_root > t_out)) break;
        if (++n > max_steps) {
            say(s, PDBFS_LOG_ERROR, "%ld internal steps without reaching t = %.10g", max_steps, t_out);
            return PDBFS_CV_TOO_MUCH_WORK;
        }
        /* tout only sizes the first step after a (re)start: with no horizon,
         * 1 s beyond the (re)start, so that it does not depend on t_out */
        flag = CVode(s->cv, isfinite(horizon) ? horizon : s->tn + 1.0, s->y, &tret, CV_ONE_STEP);
        if (flag < 0) {
            CVodeGetCurrentTime(s->cv, &s->tn);
            return flag;
        }
        s->steps++;
        s->steps_since_start++;
        if (isfinite(s->t_break) && (flag == CV_TSTOP_RETURN || flag == CV_ROOT_RETURN)
            && fabs(tret - s->t_break) <= 64 * 2.220446049250313e-16 * fabs(s->t_break)) {
            s->root_pending = 1;        /* a time event: restart there, whatever the size */
            s->t_root = tret;
        } else if (flag == CV_ROOT_RETURN && s->nx < PDBFS_RESTART_BELOW) {
            s->root_pending = 1;
            s->t_root = tret;
        } else if (flag == CV_ROOT_RETURN) {   /* integrated through, under error control */
            say(s, PDBFS_LOG_EVENT, "event at t=%.17g, integrated through", tret);
            s->roots++;
        }
        CVodeGetCurrentTime(s->cv, &s->tn);
        flag = s->on_step ? s->on_step(s->step_env, tret, N_VGetArrayPointer(s->y)) : 0;
        if (flag && flag != PDBFS_STEP_PAUSE)
            say(s, PDBFS_LOG_ERROR, "stopped by the step callback at t = %.10g", tret);
        if (flag) return PDBFS_CV_STOPPED;
    }
    if (s->steps_since_start == 0) {   /* t_out is the (re)start point itself */
        for (i = 0; i < s->nx; i++) x_out[i] = NV_Ith_S(s->y, i);
        return 0;
    }
    flag = CVodeGetDky(s->cv, t_out, 0, s->tmp);
    if (flag != CV_SUCCESS) {
        say(s, PDBFS_LOG_ERROR, "CVodeGetDky failed at t = %.17g (flag %d)", t_out, flag);
        return flag;
    }
    for (i = 0; i < s->nx; i++) x_out[i] = NV_Ith_S(s->tmp, i);
    return 0;
}

int pdbfs_cvode_roots(PdbfsCvode *s, const PdbfsCvodeSettings *set, double t0, const double *x0,
                      double t1, pdbfs_root_fn g, void *env, int dir, int max, double *t_root,
                      double *x_root, int *dir_root) {
    PdbfsCvodeSettings local = *set;
    int flag, n = 0, i, found;
    long nst = 0;
    double tret;
    local.t_stop = t1;
    flag = pdbfs_cvode_start(s, &local, t0, x0);
    if (flag) return flag < 0 ? flag : -100;
    s->user_root = g;
    s->root_env = env;
    s->roots_changed = 1;
    flag = CVodeRootInit(s->cv, 1, cv_user_root);
    if (flag == CV_SUCCESS) flag = CVodeSetRootDirection(s->cv, &dir);
    if (flag == CV_SUCCESS) flag = CVodeSetNoInactiveRootWarn(s->cv);
    while (flag >= 0 && n < max) {
        flag = CVode(s->cv, t1, s->y, &tret, CV_NORMAL);
        if (flag == CV_ROOT_RETURN) {
            t_root[n] = tret;
            for (i = 0; i < s->nx; i++) x_root[n * s->nx + i] = NV_Ith_S(s->y, i);
            if (dir_root) {
                found = 0;
                CVodeGetRootInfo(s->cv, &found);
                dir_root[n] = found < 0 ? -1 : 1;
            }
            n++;
        } else if (flag >= 0) {
            break;       /* reached t1 */
        }
    }
    if (s->cv && CVodeGetNumSteps(s->cv, &nst) == CV_SUCCESS) s->steps += nst;
    return flag < 0 ? flag : n;
}

/*
 * One simulation over an output grid and its summary from the same
 * integration (pdbfs.simulate's default path): the states at the output
 * times as pdbfs_batch_run gives them, and the record of every step (with
 * the contact force's impulse as an extra state) that pdbfs_summary.c
 * reduces to the summary, so that Result.summary() costs no second run.
 *
 * Explicit Runge-Kutta (pdbfs_erk.c, records also inside its long steps;
 * peaks and crossings located on its dense output) or CVODE (pdbfs_cvode.c;
 * CVODE's root finding on a recorded step, as in the summary driver).
 *
 * With the explicit method the run may also be kept (pdbfs_run_summary's
 * keep): the states on the grid are then not computed, the record is kept,
 * and pdbfs_run_trajectory makes them from it when they are first asked for
 * (pdbfs_run_trajectory.c): a summary alone costs no dense output.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_batch_model.h"
#include "pdbfs_cvode.h"
#include "pdbfs_erk.h"
#include "pdbfs_pulse.h"
#include "pdbfs_record.h"

#define API __attribute__((visibility("default")))
#define NSUM 7                 /* pdbfs_summary.c's entries */
#define RC_BAD_INPUT 1
#define RC_SETUP 2
#define RC_NOT_FINITE 4
enum { INFO_T, INFO_STEPS, INFO_ROOTS, INFO_RHS, INFO_FLAG, INFO_JAC, INFO_METHOD, INFO_N };

int pdbfs_summarise(History *H, double *out, double *x_pk, Note *m);

static void keep_error(void *env, int kind, const char *text) {
    Note *m = (Note *)env;
    if (kind == PDBFS_LOG_ERROR && m->text && m->len) snprintf(m->text, m->len, "%s", text);
}

void pdbfs_kept_free(Kept *K) {
    if (!K) return;
    pdbfs_erk_free(&K->rk);
    pdbfs_record_release(&K->H);     /* its memory for the next run */
    free(K->work);
    free(K->mem);
    free(K);
}

/*
 * As pdbfs_batch_run (the arguments checked by the caller, pdbfs.simulation.
 * compiled: sizes, a strictly increasing grid from t[0] = 0, positive
 * tolerances, a valid solver code or PDBFS_ERK), and the summary of the run:
 * out[NSUM] (pdbfs_summary.c's entries, NaN where undefined), *scode its
 * code (0, or the summary's failure), note its warnings or failure.
 * keep not NULL and the explicit method: X is not written (it may be NULL),
 * and a run that succeeds is kept in *keep for pdbfs_run_trajectory
 * (freed by pdbfs_run_release); else *keep is NULL.
 * Returns the run's code (0, RC_*, or CVODE's negative flag); msg its reason.
 */
API int pdbfs_run_summary(const double *p, const double *x0, long long nt, const double *t,
                          double *X, double rtol, double atol, int method, double max_step,
                          long long max_num_steps, double *info, char *msg, long long msglen,
                          double *out, int *scode, char *note, long long notelen, void **keep) {
    PdbfsCvode s;
    PdbfsCvodeSettings set, refine;
    Note err, m;
    const int erk = method == PDBFS_ERK, lazy = erk && keep;
    double *atolv, *x, *x_pk;
    Kept *K;
    History *H;
    long long k, i;
    int rc = 0;
    err.text = msg;
    err.len = msg && msglen > 0 ? (size_t)msglen : 0;
    m.text = note;
    m.len = note && notelen > 0 ? (size_t)notelen : 0;
    if (keep) *keep = NULL;
    if (err.len) msg[0] = 0;
    if (m.len) note[0] = 0;
    /* the states go to X unless a lazy run keeps them: without either, nothing
     * could hold them (a caller's mistake, refused rather than written through) */
    if (!p || !x0 || !t || nt < 2 || !info || !out || !scode || (!lazy && !X)) {
        if (err.len) snprintf(msg, err.len, "run_summary: a buffer is missing or the grid "
                              "has fewer than 2 times");
        return RC_BAD_INPUT;
    }
    K = calloc(1, sizeof(Kept));
    H = K ? &K->H : NULL;
    for (i = 0; i < NSUM; i++) out[i] = NAN;
    for (i = 0; i < INFO_N; i++) info[i] = 0.0;
    *scode = -1;
    if (K) {
        K->work = pdbfs_eval_alloc(&K->ev, PDBFS_SZ_ARG, PDBFS_SZ_RES, PDBFS_SZ_IW, PDBFS_SZ_W);
        /* the tolerances, the state, the peak's state, its tolerances, p (a kept run's own) */
        K->mem = malloc(sizeof(double) * (NXQ * 4 + PDBFS_NP + 1));
    }
    if (!K || !K->work || !K->mem || (erk && pdbfs_erk_init(&K->rk, NXQ, PDBFS_NE, &K->ev))) {
        pdbfs_kept_free(K);
        if (err.len) snprintf(msg, err.len, "out of memory");
        return RC_SETUP;
    }
    atolv = K->mem;
    x = atolv + NXQ;
    x_pk = x + NXQ;
    memcpy(x_pk + 2 * NXQ, p, sizeof(double) * PDBFS_NP);
    K->ev.p = x_pk + 2 * NXQ;
    for (i = 0; i < NXQ; i++) {
        atolv[i] = i < PDBFS_NX ? atol : 1e300;     /* the impulse: no error test */
        x_pk[NXQ + i] = 0.01 * atolv[i];
    }
    pdbfs_summary_settings(&set, method, erk, rtol, atolv, max_step, t[nt - 1]);
    refine = set;               /* as the summary driver: tighter after the 8th-order pass */
    if (erk) {
        refine.rtol = 0.01 * rtol;
        refine.atol = x_pk + NXQ;
    }
    pdbfs_cvode_init(&s, NXQ, PDBFS_NE, &K->ev, keep_error, &err);
    s.ode = pdbfs_ode_q;
    s.jac = pdbfs_jac_q;
    s.jac_sp = pdbfs_jac_q_sparsity_out(0);
    K->rk.ode = pdbfs_ode_q;
    K->rk.nq = NQ;              /* the impulse: a quadrature */
    K->rk.substeps = 1;
    K->rk.lazy = lazy;          /* no dense output but where a root or a summary needs it */
    H->ev = &K->ev;
    H->cv = &s;
    H->set = &refine;
    H->rk = erk ? &K->rk : NULL;    /* refinements on its dense output */
    pdbfs_record_adopt(H);          /* the memory of the record a run before released */

    for (i = 0; i < PDBFS_NX; i++) x[i] = x0[i];
    for (i = PDBFS_NX; i < NXQ; i++) x[i] = 0.0;
    for (i = 0; i < PDBFS_NX && !lazy; i++) X[i * nt] = x0[i];
    info[INFO_T] = t[0];
    rc = erk ? (pdbfs_erk_start(&K->rk, &set, t[0], x) ? RC_NOT_FINITE : 0)
             : (pdbfs_cvode_start(&s, &set, t[0], x) ? RC_SETUP : 0);
    if (!rc) pdbfs_record_step(H, t[0], x);
    s.on_step = K->rk.on_step = pdbfs_record_step;
    s.step_env = K->rk.step_env = H;
    if (!rc && erk) {
        long reached = 1;
        int flag = pdbfs_erk_grid(&K->rk, (long)nt, t, PDBFS_NX, lazy ? NULL : X, (long)nt,
                                  (long)max_num_steps, &reached);
        info[INFO_T] = t[reached - 1];
        if (flag) {
            /* the time reached is the last accepted step's, not the last output time */
            if (K->rk.t > info[INFO_T]) info[INFO_T] = K->rk.t;
            rc = flag == -3 || H->bad ? RC_NOT_FINITE : flag == PDBFS_ERK_STEP_UNDERFLOW ? -3 : flag;
            if (err.len && !msg[0]) snprintf(msg, err.len, "%s", K->rk.msg);
            if (H->oom && err.len) snprintf(msg, err.len, "out of memory");
        }
    }
    for (k = 1; k < nt && !rc && !erk; k++) {
        int flag = pdbfs_cvode_advance(&s, t[k], t[nt - 1], (long)max_num_steps, x);
        if (flag) {
            if (s.tn > info[INFO_T]) info[INFO_T] = s.tn;   /* where CVODE got to */
            rc = H->bad ? RC_NOT_FINITE : flag;
            if (H->oom && err.len) snprintf(msg, err.len, "out of memory");
            if (flag < 0) info[INFO_FLAG] = flag;
            break;
        }
        for (i = 0; i < PDBFS_NX; i++) {
            if (!isfinite(x[i])) {
                if (err.len) snprintf(msg, err.len, "the solution is NaN or infinite at t = %.17g", t[k]);
                rc = RC_NOT_FINITE;
            }
            X[i * nt + k] = x[i];
        }
        if (!rc) info[INFO_T] = t[k];
    }
    s.on_step = K->rk.on_step = NULL;
    info[INFO_STEPS] = (double)(erk ? K->rk.steps : s.steps);
    info[INFO_ROOTS] = (double)(erk ? K->rk.roots : s.roots);
    info[INFO_RHS] = (double)(erk ? K->rk.rhs_evals : s.rhs_evals);
    info[INFO_JAC] = (double)s.jac_evals;
    info[INFO_METHOD] = erk ? (double)PDBFS_ERK : (double)(s.method | s.nls << 4 | s.linsol << 8);
    if (rc) rc = pdbfs_limit_message(H, rc, msg, err.len);   /* a variable out of its range */
    if (!rc && t[0] == 0.0) *scode = pdbfs_summarise(H, out, x_pk, &m);
    pdbfs_cvode_free(&s);
    H->cv = NULL;
    H->set = NULL;
    if (lazy && !rc) *keep = K;
    else pdbfs_kept_free(K);
    return rc;
}

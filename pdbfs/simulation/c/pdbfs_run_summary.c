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
#define RC_SETUP 2
#define RC_NOT_FINITE 4
enum { INFO_T, INFO_STEPS, INFO_ROOTS, INFO_RHS, INFO_FLAG, INFO_JAC, INFO_METHOD, INFO_N };

int pdbfs_summarise(History *H, double *out, double *x_pk, Note *m);

static void keep_error(void *env, int kind, const char *text) {
    Note *m = (Note *)env;
    if (kind == PDBFS_LOG_ERROR && m->text && m->len) snprintf(m->text, m->len, "%s", text);
}

/*
 * As pdbfs_batch_run (the arguments checked by the caller, pdbfs.simulation.
 * compiled: sizes, a strictly increasing grid from t[0] = 0, positive
 * tolerances, a valid solver code or PDBFS_ERK), and the summary of the run:
 * out[NSUM] (pdbfs_summary.c's entries, NaN where undefined), *scode its
 * code (0, or the summary's failure), note its warnings or failure.
 * Returns the run's code (0, RC_*, or CVODE's negative flag); msg its reason.
 */
API int pdbfs_run_summary(const double *p, const double *x0, long long nt, const double *t,
                          double *X, double rtol, double atol, int method, double max_step,
                          long long max_num_steps, double *info, char *msg, long long msglen,
                          double *out, int *scode, char *note, long long notelen) {
    PdbfsEval ev;
    PdbfsCvode s;
    PdbfsErk rk;
    PdbfsCvodeSettings set, refine;
    History H;
    Note err, m;
    const int erk = method == PDBFS_ERK;
    double *atolv, *x, *x_pk;
    void *work = pdbfs_eval_alloc(&ev, PDBFS_SZ_ARG, PDBFS_SZ_RES, PDBFS_SZ_IW, PDBFS_SZ_W);
    long long k, i;
    int rc = 0;
    err.text = msg;
    err.len = msg && msglen > 0 ? (size_t)msglen : 0;
    m.text = note;
    m.len = note && notelen > 0 ? (size_t)notelen : 0;
    if (err.len) msg[0] = 0;
    if (m.len) note[0] = 0;
    for (i = 0; i < NSUM; i++) out[i] = NAN;
    for (i = 0; i < INFO_N; i++) info[i] = 0.0;
    *scode = -1;
    memset(&H, 0, sizeof H);
    memset(&rk, 0, sizeof rk);
    atolv = malloc(sizeof(double) * NXQ * 4);
    if (!work || !atolv || (erk && pdbfs_erk_init(&rk, NXQ, PDBFS_NE, &ev))) {
        free(work);
        free(atolv);
        pdbfs_erk_free(&rk);
        if (err.len) snprintf(msg, err.len, "out of memory");
        return RC_SETUP;
    }
    x = atolv + NXQ;
    x_pk = x + NXQ;
    ev.p = p;
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
    pdbfs_cvode_init(&s, NXQ, PDBFS_NE, &ev, keep_error, &err);
    s.ode = pdbfs_ode_q;
    s.jac = pdbfs_jac_q;
    s.jac_sp = pdbfs_jac_q_sparsity_out(0);
    rk.ode = pdbfs_ode_q;
    rk.substeps = 1;
    H.ev = &ev;
    H.cv = &s;
    H.set = &refine;
    H.rk = erk ? &rk : NULL;    /* refinements on its dense output */

    for (i = 0; i < PDBFS_NX; i++) x[i] = x0[i];
    for (i = PDBFS_NX; i < NXQ; i++) x[i] = 0.0;
    for (i = 0; i < PDBFS_NX; i++) X[i * nt] = x0[i];
    info[INFO_T] = t[0];
    rc = erk ? (pdbfs_erk_start(&rk, &set, t[0], x) ? RC_NOT_FINITE : 0)
             : (pdbfs_cvode_start(&s, &set, t[0], x) ? RC_SETUP : 0);
    if (!rc) pdbfs_record_step(&H, t[0], x);
    s.on_step = rk.on_step = pdbfs_record_step;
    s.step_env = rk.step_env = &H;
    for (k = 1; k < nt && !rc; k++) {
        int flag = erk ? pdbfs_erk_advance(&rk, t[k], (long)max_num_steps, x)
                       : pdbfs_cvode_advance(&s, t[k], t[nt - 1], (long)max_num_steps, x);
        if (flag) {
            rc = (flag == -3 && erk) || H.bad ? RC_NOT_FINITE
                 : flag == PDBFS_ERK_STEP_UNDERFLOW ? -3 : flag;
            if (erk && err.len && !msg[0]) snprintf(msg, err.len, "%s", rk.msg);
            if (H.oom && err.len) snprintf(msg, err.len, "out of memory");
            if (flag < 0 && !erk) info[INFO_FLAG] = flag;
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
    s.on_step = rk.on_step = NULL;
    info[INFO_STEPS] = (double)(erk ? rk.steps : s.steps);
    info[INFO_ROOTS] = (double)(erk ? rk.roots : s.roots);
    info[INFO_RHS] = (double)(erk ? rk.rhs_evals : s.rhs_evals);
    info[INFO_JAC] = (double)s.jac_evals;
    info[INFO_METHOD] = erk ? (double)PDBFS_ERK : (double)(s.method | s.nls << 4 | s.linsol << 8);
    if (!rc && t[0] == 0.0) *scode = pdbfs_summarise(&H, out, x_pk, &m);
    pdbfs_cvode_free(&s);
    pdbfs_erk_free(&rk);
    pdbfs_free_history(&H);
    free(atolv);
    free(work);
    return rc;
}

/*
 * pdbfs_batch_run with the explicit Runge-Kutta method (pdbfs_erk.c): one
 * whole simulation over an output grid, the states at the output times from
 * the dense output.  The arguments were checked by pdbfs_batch_run; codes
 * and info[] as there (no CVODE flag, no Jacobian).  nx: the rig's states,
 * or one more: the contact force's impulse, a quadrature (pdbfs_batch.c).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_batch_model.h"
#include "pdbfs_erk.h"

#define RC_SETUP 2
#define RC_NOT_FINITE 4
#define RC_LIMIT 8           /* as pdbfs_record.h */
enum { INFO_T, INFO_STEPS, INFO_ROOTS, INFO_RHS, INFO_FLAG, INFO_JAC, INFO_METHOD };

/* pdbfs_record.h */
int pdbfs_limit_near(PdbfsEval *ev, double t0, const double *x0, double t, const double *x,
                     char *msg, size_t len);

int pdbfs_batch_run_erk(int nx, const double *p, const double *x0, long long nt, const double *t,
                        double *X, double rtol, double atol, double max_step,
                        long long max_num_steps, double *info, char *msg, long long msglen) {
    PdbfsEval ev;
    PdbfsErk s;
    PdbfsCvodeSettings set;
    double *atolv;
    void *work = pdbfs_eval_alloc(&ev, PDBFS_SZ_ARG, PDBFS_SZ_RES, PDBFS_SZ_IW, PDBFS_SZ_W);
    long long i;
    int rc = 0;
    atolv = malloc(sizeof(double) * 2 * (nx + 1));
    if (!work || !atolv || pdbfs_erk_init(&s, nx, PDBFS_NE, &ev)) {
        free(work);
        free(atolv);
        if (msg && msglen > 0) snprintf(msg, (size_t)msglen, "out of memory");
        return RC_SETUP;
    }
    ev.p = p;
    if (nx > PDBFS_NX) {       /* the impulse: a quadrature, out of the error test */
        s.ode = pdbfs_ode_q;
        s.nq = nx - PDBFS_NX;
    }
    for (i = 0; i < nx; i++) atolv[i] = i < PDBFS_NX ? atol : 1e300;
    memset(&set, 0, sizeof set);
    set.rtol = rtol;
    set.atol = atolv;
    set.max_step = max_step;
    set.t_stop = t[nt - 1];
    for (i = 0; i < nx; i++) X[i * nt] = x0[i];
    info[INFO_T] = t[0];
    rc = pdbfs_erk_start(&s, &set, t[0], x0) ? RC_NOT_FINITE : 0;
    if (!rc) {
        long reached = 1;
        int flag = pdbfs_erk_grid(&s, (long)nt, t, nx, X, (long)nt, (long)max_num_steps,
                                  &reached);
        info[INFO_T] = t[reached - 1];
        if (flag) {
            rc = flag == -3 ? RC_NOT_FINITE : flag == PDBFS_ERK_STEP_UNDERFLOW ? -3 : flag;
            if (reached < nt && s.t > info[INFO_T]) info[INFO_T] = s.t < t[reached] ? s.t : t[reached - 1];
        }
    }
    if (rc && msg && msglen > 0) snprintf(msg, (size_t)msglen, "%s", s.msg);
    /* a failure as a variable reached its declared range's bound: say which */
    if (rc && rc != RC_NOT_FINITE && pdbfs_limit_near(&ev, t[0], x0, s.t, s.y, msg,
                                                      msg && msglen > 0 ? (size_t)msglen : 0))
        rc = RC_LIMIT;
    info[INFO_STEPS] = (double)s.steps;
    info[INFO_ROOTS] = (double)s.roots;
    info[INFO_RHS] = (double)s.rhs_evals;
    info[INFO_METHOD] = PDBFS_ERK;
    pdbfs_erk_free(&s);
    free(work);
    free(atolv);
    return rc;
}

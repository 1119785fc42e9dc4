/*
 * The states on the output grid of a run that pdbfs_run_summary kept (the
 * explicit method's record of every step: its start, length and stages),
 * made when they are first asked for: each step's dense output from its
 * stages, at the grid's times inside it.  The numbers pdbfs_erk_grid writes
 * during a run, output time by output time (its cases: a time at a step's
 * end is its state, one within roundoff past a root that of the step
 * before), so the grid's states do not depend on when they are made.
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_batch_model.h"
#include "pdbfs_erk.h"
#include "pdbfs_record.h"

#define API __attribute__((visibility("default")))
#define RC_SETUP 2
#define RC_NOT_FINITE 4

static void from_record(const History *H, long j, long k, long long nt, double *X) {
    int i;
    for (i = 0; i < PDBFS_NX; i++) X[i * nt + k] = H->x[j * NXQ + i];
}

/*
 * The states of a kept run at the times t[0 .. nt-1] (the grid it ran on)
 * into X (PDBFS_NX x nt, row major).  0; RC_NOT_FINITE when a state is not
 * finite; RC_SETUP when the grid reaches past the run.  msg: the reason.
 */
API int pdbfs_run_trajectory(void *run, long long nt, const double *t, double *X, char *msg,
                             long long msglen) {
    Kept *K = (Kept *)run;
    History *H = &K->H;
    long j = 0, k = 1;
    if (msg && msglen > 0) msg[0] = 0;
    if (H->n < 1) {
        if (msg && msglen > 0) snprintf(msg, (size_t)msglen, "the run kept no record");
        return RC_SETUP;
    }
    from_record(H, 0, 0, nt, X);
    while (k < nt) {
        const double tk = t[k];
        const double *d;
        int near = 0;
        long k1, bad;
        while (H->t[j] < tk) {
            /* a restart at a root within roundoff of tk: no step is that short */
            if (PDBFS_ERK_NEAR(tk, H->t[j])) {
                near = 1;
                break;
            }
            if (++j >= H->n) {
                if (msg && msglen > 0)
                    snprintf(msg, (size_t)msglen, "the run ends at t = %.17g, before t = %.17g",
                             H->t[H->n - 1], tk);
                return RC_SETUP;
            }
        }
        d = H->dn + j * DNREC;
        if (j == 0 || d[2] == DN_NONE || tk == H->t[j] || (near && !(tk <= d[0] + d[1]))) {
            from_record(H, j, k++, nt, X);
            continue;
        }
        k1 = k + 1;
        if (!near)
            while (k1 < nt && t[k1] < H->t[j]) k1++;
        d = pdbfs_step_dense(H, j);
        bad = d ? pdbfs_erk_poly_times(d + 3, d + 3 + NXQ, NXQ, PDBFS_NX, d[0], d[1], t, k, k1,
                                       X, (long)nt)
                : k + 1;
        if (bad) {
            if (msg && msglen > 0)
                snprintf(msg, (size_t)msglen, "the solution is NaN or infinite at t = %.17g",
                         t[bad - 1]);
            return RC_NOT_FINITE;
        }
        k = k1;
    }
    return 0;
}

/* a kept run's memory, freed (NULL: nothing) */
API void pdbfs_run_release(void *run) {
    pdbfs_kept_free((Kept *)run);
}

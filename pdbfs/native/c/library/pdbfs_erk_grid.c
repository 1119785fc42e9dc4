/*
 * pdbfs_erk_grid: the explicit Runge-Kutta method (pdbfs_erk.c) over a whole
 * output grid, for the drivers of one simulation (pdbfs_batch_erk.c,
 * pdbfs_run_summary.c).  The same steps and the same numbers as calling
 * pdbfs_erk_advance at every output time, but each step's output times are
 * written together, state by state over the times (the dense output's
 * polynomial vectorised over them): one call per output time, and its
 * polynomial of every state, were a fifth of a run.
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pdbfs_erk.h"

#define CHUNK 64                 /* output times evaluated together */

long pdbfs_erk_poly_times(const double *y_old, const double *rows, int n, int nout, double t_old,
                          double h_old, const double *t, long k0, long k1, double *X, long ld) {
    double th[CHUNK];
    long k, c;
    int i, j;
    for (c = k0; c < k1; c += CHUNK) {
        const long m = k1 - c < CHUNK ? k1 - c : CHUNK;
        for (j = 0; j < m; j++) {
            double v = (t[c + j] - t_old) / h_old;
            th[j] = v < 0 ? 0.0 : v > 1 ? 1.0 : v;
        }
        for (i = 0; i < nout; i++) {
            const double *r = rows + i, y0 = y_old[i];
            const double r0 = r[0], r1 = r[n], r2 = r[2 * n], r3 = r[3 * n], r4 = r[4 * n],
                         r5 = r[5 * n], r6 = r[6 * n];
            double *x = X + (size_t)i * (size_t)ld + c;
            for (j = 0; j < m; j++) {        /* pdbfs_erk_poly's sums, in its order */
                const double a = th[j], b = 1.0 - a;
                double acc = r6 * a;
                acc = (acc + r5) * b;
                acc = (acc + r4) * a;
                acc = (acc + r3) * b;
                acc = (acc + r2) * a;
                acc = (acc + r1) * b;
                acc = (acc + r0) * a;
                x[j] = y0 + acc;
            }
            /* theta and 1 - theta within [0, 1]: no value exceeds the sum of
             * the magnitudes; only where that overflows is each one looked at */
            if (!(fabs(y0) + fabs(r0) + fabs(r1) + fabs(r2) + fabs(r3) + fabs(r4) + fabs(r5)
                  + fabs(r6) <= DBL_MAX))
                for (k = 0; k < m; k++)
                    if (!isfinite(x[k])) return c + k + 1;
        }
    }
    return 0;
}

/* outputs k0 .. k1-1 (inside the last step, t_old < t[k] < t) from the
 * step's dense output, as pdbfs_erk_dense gives them */
static long from_dense(const PdbfsErk *s, const double *t, long k0, long k1, int nout,
                       double *X, long ld) {
    return pdbfs_erk_poly_times(s->y_old, s->dense, s->nx, nout, s->t_old, s->h_old, t, k0, k1,
                                X, ld);
}

static void from_state(const PdbfsErk *s, long k, int nout, double *X, long ld) {
    int i;
    for (i = 0; i < nout; i++) X[(size_t)i * (size_t)ld + k] = s->y[i];
}

int pdbfs_erk_grid(PdbfsErk *s, long nt, const double *t, int nout, double *X, long ld,
                   long max_steps, long *reached) {
    long k = 1, n = 0, bad;
    int flag;
    *reached = 1;
    while (k < nt) {
        const double t_out = t[k];
        if (!X && s->t >= t_out) {                /* nothing to write: count the steps */
            while (k < nt && t[k] <= s->t) k++;
            *reached = k;
            n = 0;
            continue;
        }
        if (s->t >= t_out) {
            /* every output time the last step reached: those inside it from its
             * dense output, the one at its end (or a fresh start's) its state */
            long k1 = k;
            while (k1 < nt && t[k1] <= s->t) k1++;
            if (s->fresh || !s->dense_ready) {
                for (; k < k1; k++) from_state(s, k, nout, X, ld);
            } else {
                long kd = k1 > k && t[k1 - 1] == s->t ? k1 - 1 : k1;
                if (kd > k && (bad = from_dense(s, t, k, kd, nout, X, ld))) {
                    *reached = bad - 1;
                    snprintf(s->msg, sizeof s->msg, "the solution is NaN or infinite at t = %.17g",
                             t[bad - 1]);
                    return -3;
                }
                if (kd < k1) from_state(s, kd, nout, X, ld);
                k = k1;
            }
            *reached = k;
            n = 0;
            continue;
        }
        /* restarted at a root within roundoff of t_out: no step is that short */
        if (PDBFS_ERK_NEAR(t_out, s->t)) {
            if (X && s->dense_ready && !s->fresh && t_out <= s->t_old + s->h_old) {
                double *xi = s->tmp;
                int i;
                pdbfs_erk_dense(s, t_out, xi);
                for (i = 0; i < nout; i++) X[(size_t)i * (size_t)ld + k] = xi[i];
            } else if (X) {
                from_state(s, k, nout, X, ld);
            }
            *reached = ++k;
            n = 0;
            continue;
        }
        if (++n > max_steps) {
            snprintf(s->msg, sizeof s->msg, "%ld steps without reaching t = %.10g", max_steps, t_out);
            return PDBFS_CV_TOO_MUCH_WORK;
        }
        /* no output: the dense output is not asked for at t_out */
        flag = pdbfs_erk_step_watched(s, X ? t_out : t[nt - 1]);
        if (flag == PDBFS_ERK_AGAIN) continue;
        if (flag) return flag;
    }
    return 0;
}

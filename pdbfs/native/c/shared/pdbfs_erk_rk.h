/* pdbfs_erk_rk.h: the Runge-Kutta arithmetic of pdbfs_erk.c (an attempted
 * step, its dense output) for n states of which the first m are integrated,
 * inlined where it is called: with the rig's own state counts as constants
 * (pdbfs_erk_sized.c, compiled with each rig's model) and with any counts
 * (pdbfs_erk_rk.c, the same for every rig).  Internal to those two. */
#ifndef PDBFS_ERK_RK_H
#define PDBFS_ERK_RK_H

#include <float.h>
#include <math.h>
#include <string.h>

#include "pdbfs_erk.h"
#include "pdbfs_erk_la.h"
#include "pdbfs_erk_table.h"

/* one attempt from (t, y, f) over h: ynew, k[0..12]; the weighted error, or
 * INFINITY when a stage is not finite.  The stages' states and the error
 * are of the first m states only: the others are integrals (quadratures)
 * that the right-hand side does not read and the error test leaves out */
ERK_INLINE double attempt_n(PdbfsErk *s, double h, const int n, const int m) {
    double local[2 * ERK_LOCAL], *k = s->k, e3 = 0.0, e5 = 0.0;
    double *acc = n <= ERK_LOCAL ? local : s->acc, *acc3 = n <= ERK_LOCAL ? local + ERK_LOCAL : s->tmp;
    int i;
    memcpy(k, s->f, sizeof(double) * (size_t)n);
    /* the stages written out (ERK_STAGE): each sum's coefficients are then
     * constants, its zero terms dropped by the compiler (a tenth of a run).
     * The stage before's term is added last, to a state made of the others
     * meanwhile: after the right-hand side a stage waits for one product and
     * one sum, not four operations (2 % of a run) */
#define ERK_STAGE(st)                                                              \
    erk_at_last(m, n, (st) - 1, RK_A + (st) * NK, h, h * RK_A[(st) * NK + (st) - 1], s->y, k,  \
                acc, s->tmp);                                                      \
    if (erk_rhs_unchecked(s, s->t + RK_C[st] * h, s->tmp, k + (st) * n)) return INFINITY;
    ERK_STAGE(1) ERK_STAGE(2) ERK_STAGE(3) ERK_STAGE(4) ERK_STAGE(5) ERK_STAGE(6)
    ERK_STAGE(7) ERK_STAGE(8) ERK_STAGE(9) ERK_STAGE(10) ERK_STAGE(11)
#undef ERK_STAGE
    erk_at(n, n, NSTAGE, RK_B, h, s->y, k, acc, s->ynew);
    if (erk_rhs_unchecked(s, s->t + h, s->ynew, k + NSTAGE * n)) return INFINITY;
    /* every stage at once (a stage that is not finite made the ones after it
     * so, or not: either way the attempt fails, as it did when tested alone) */
    if (!erk_finite(NSTAGE * n, k + n)) return INFINITY;
    /* the 5th- and 3rd-order estimates, blended as Hairer's DOP853 (tmp is
     * free: acc3 may be it); the RMS over the m states the error test sees
     * (a quadrature changes no step: a run with one is the run without) */
    erk_combine(m, n, NSTAGE + 1, RK_E5, k, acc);
    erk_combine(m, n, NSTAGE + 1, RK_E3, k, acc3);
    for (i = 0; i < m; i++) {
        double sc = s->atol[i] + s->rtol * fmax(fabs(s->y[i]), fabs(s->ynew[i]));
        double a5 = acc[i] / sc, a3 = acc3[i] / sc;
        e5 += a5 * a5;
        e3 += a3 * a3;
    }
    if (e5 == 0.0 && e3 == 0.0) return 0.0;
    return fabs(h) * e5 / sqrt((e5 + 0.01 * e3) * m);
}

/* the dense output of the step just accepted (y_old, k of the step, h_old):
 * three more stages */
ERK_INLINE int make_dense_n(PdbfsErk *s, const int n, const int m) {
    const double h = s->h_old, *k = s->k;
    double local[ERK_LOCAL], *acc = n <= ERK_LOCAL ? local : s->acc, *r = s->dense;
    int i;
#define ERK_STAGE(st)                                                              \
    erk_at(m, n, st, RK_A + (st) * NK, h, s->y_old, k, acc, s->tmp);               \
    if (erk_rhs_n(s, n, s->t_old + RK_C[st] * h, s->tmp, s->k + (st) * n)) return 1;
    ERK_STAGE(NSTAGE + 1) ERK_STAGE(NSTAGE + 2) ERK_STAGE(NSTAGE + 3)
#undef ERK_STAGE
    for (i = 0; i < n; i++) {
        double dy = s->ynew[i] - s->y_old[i];
        r[i] = dy;
        r[n + i] = h * k[i] - dy;
        r[2 * n + i] = 2.0 * dy - h * (k[i] + k[NSTAGE * n + i]);
    }
#define ERK_ROW(st)                                                                \
    erk_combine(n, n, NK, RK_D + (st) * NK, k, acc);                               \
    for (i = 0; i < n; i++) r[(3 + (st)) * n + i] = h * acc[i];
    ERK_ROW(0) ERK_ROW(1) ERK_ROW(2) ERK_ROW(3)
#undef ERK_ROW
    s->dense_ready = 1;
    return 0;
}

/* a state's difference below this (of its size) is roundoff */
#define STIFF_ROUNDOFF (1e3 * DBL_EPSILON)

/* h |lambda| of the step just attempted over h, for the fastest mode the
 * step saw: the change of f between the last stage and the step's end (both
 * at t + h) over the change of the state between them (Hairer's DOP853
 * estimate; y12 - ynew is h times the stages weighted by the differences of
 * the last stage's row and the weights).  Both in the error test's weights,
 * so that states of other units (a pressure in Pa beside a position in m)
 * do not make a stiffness of the scaling, and of the states whose
 * difference is more than roundoff only.  0 where f did not change at all
 * (nothing moves that a fast mode could amplify: a breech at rest on its
 * mount, an oil column in cavitation); -1 where f changed but no state by
 * more than roundoff (near an equilibrium: the estimate before holds) */
ERK_INLINE double stiffness_n(PdbfsErk *s, double h, const int n, const int m) {
    const double *k = s->k;
    double local[ERK_LOCAL], *dy = n <= ERK_LOCAL ? local : s->acc, c[NSTAGE];
    double num = 0.0, den = 0.0, moved = 0.0;
    int i, j;
    /* (the table's constants: the compiler folds them, and the sum over the
     * stages is erk_combine's, vectorised over the states, in the same order) */
    for (j = 0; j < NSTAGE; j++) c[j] = RK_A[(NSTAGE - 1) * NK + j] - RK_B[j];
    erk_combine(m, n, NSTAGE, c, k, dy);
    for (i = 0; i < m; i++) {
        double d = k[NSTAGE * n + i] - k[(NSTAGE - 1) * n + i], w;
        w = 1.0 / (s->atol[i] + s->rtol * fabs(s->ynew[i]));
        moved += fabs(d);
        if (!(fabs(dy[i] * h) > STIFF_ROUNDOFF * fabs(s->ynew[i]))) continue;
        num += d * d * w * w;
        den += dy[i] * dy[i] * w * w;
    }
    if (moved == 0.0) return 0.0;
    /* (h cancels: dy is the difference over h) */
    return den > 0.0 ? sqrt(num / den) : -1.0;
}

/* pdbfs_erk_rk.c's, for any number of states: what pdbfs_erk_sized.c does
 * for sizes other than the rig's */
double pdbfs_erk_attempt_any(PdbfsErk *s, double h);
int pdbfs_erk_make_dense_any(PdbfsErk *s);
double pdbfs_erk_stiffness_any(PdbfsErk *s, double h);
void pdbfs_erk_poly_any(const double *y_old, const double *r, int n, double th, double *out);

#endif

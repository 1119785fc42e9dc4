/* pdbfs_erk_rk: the Runge-Kutta arithmetic of pdbfs_erk.c (an attempted
 * step and its check by two half steps, its dense output, the dense
 * output's polynomial); see
 * pdbfs_erk_la.h.  Never aborts, never prints. */
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
    erk_combine(m, n, (st) - 1, RK_A + (st) * NK, k, acc);                         \
    {                                                                              \
        const double hc = h * RK_A[(st) * NK + (st) - 1], *kl = k + ((st) - 1) * n;  \
        for (i = 0; i < m; i++) s->tmp[i] = (s->y[i] + h * acc[i]) + hc * kl[i];     \
    }                                                                              \
    if (erk_rhs(s, s->t + RK_C[st] * h, s->tmp, k + (st) * n)) return INFINITY;
    ERK_STAGE(1) ERK_STAGE(2) ERK_STAGE(3) ERK_STAGE(4) ERK_STAGE(5) ERK_STAGE(6)
    ERK_STAGE(7) ERK_STAGE(8) ERK_STAGE(9) ERK_STAGE(10) ERK_STAGE(11)
#undef ERK_STAGE
    erk_combine(n, n, NSTAGE, RK_B, k, acc);
    for (i = 0; i < n; i++) s->ynew[i] = s->y[i] + h * acc[i];
    if (erk_rhs(s, s->t + h, s->ynew, k + NSTAGE * n)) return INFINITY;
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

double pdbfs_erk_attempt(PdbfsErk *s, double h) {
#define ERK_ATTEMPT(N, M) attempt_n(s, h, N, M)
    return ERK_BY_SIZE(s, ERK_ATTEMPT);
#undef ERK_ATTEMPT
}

/* the first step after a kink is checked by two half steps: the difference of
 * their end and the step's is (1 - 2^-p) of the step's error for a local
 * order p >= 2, hence the factor; it shows a law of low order where it is
 * KINK_LOW times the embedded estimate or more */
#define KINK_HALVES (4.0 / 3.0)
#define KINK_LOW 4.0
#define KINK_NOISE 1e3

/* an attempt over h (as pdbfs_erk_attempt) whose error, where the
 * embedded estimate passes it, is also checked by two half steps, the
 * larger estimate returned: just after a kink, where a law that grows as a
 * fractional power from its onset (a contact's d^1.5) leaves an error that
 * the embedded estimate underrates a hundredfold.  *low set: the halves saw
 * KINK_LOW times the embedded estimate or more */
double pdbfs_erk_attempt_halves(PdbfsErk *s, double h, int *low) {
    const int n = s->nx, m = s->nx - s->nq;
    const size_t bytes = sizeof(double) * (size_t)n, stages = bytes * (NSTAGE + 1);
    double *y1 = s->half, *f1 = s->half + n, *y2 = s->half + 2 * n, *kept = s->half + 3 * n;
    double *y0 = s->y, *f0 = s->f, t0 = s->t, err = pdbfs_erk_attempt(s, h), e, sum = 0.0;
    int i;
    if (!(err <= 1.0)) return err;
    memcpy(kept, s->ynew, bytes);          /* the step's end and stages, for its dense output */
    memcpy(kept + n, s->k, stages);
    e = pdbfs_erk_attempt(s, 0.5 * h);
    if (isfinite(e)) {
        memcpy(y1, s->ynew, bytes);
        memcpy(f1, s->k + NSTAGE * n, bytes);
        s->y = y1;
        s->f = f1;
        s->t = t0 + 0.5 * h;
        e = pdbfs_erk_attempt(s, 0.5 * h);
        s->y = y0;
        s->f = f0;
        s->t = t0;
    }
    memcpy(y2, s->ynew, bytes);
    memcpy(s->ynew, kept, bytes);
    memcpy(s->k, kept + n, stages);
    if (!isfinite(e)) return INFINITY;
    for (i = 0; i < m; i++) {
        double w = (s->ynew[i] - y2[i]) / (s->atol[i] + s->rtol * fmax(fabs(y0[i]), fabs(s->ynew[i])));
        sum += w * w;
    }
    sum = KINK_HALVES * sqrt(sum / m);
    /* (below KINK_NOISE the two differ by roundoff only) */
    if (sum >= KINK_LOW * err && sum > KINK_NOISE * DBL_EPSILON / s->rtol) *low = 1;
    return fmax(err, sum);
}

/* the states' difference below this (of their size) is roundoff */
#define STIFF_ROUNDOFF (1e3 * DBL_EPSILON)

/* h |lambda| of the step just attempted over h, for the fastest mode the
 * step saw: the change of f between the last stage and the step's end (both
 * at t + h) over the change of the state between them (Hairer's DOP853
 * estimate; y12 - ynew is h times the stages weighted by the differences of
 * the last stage's row and the weights) */
double pdbfs_erk_stiffness(PdbfsErk *s, double h) {
    const int n = s->nx, m = s->nx - s->nq;
    const double *k = s->k;
    double num = 0.0, den = 0.0, size = 0.0;
    int i, j;
    for (i = 0; i < m; i++) {
        double d = k[NSTAGE * n + i] - k[(NSTAGE - 1) * n + i], dy = 0.0;
        for (j = 0; j < NSTAGE; j++) dy += (RK_A[(NSTAGE - 1) * NK + j] - RK_B[j]) * k[j * n + i];
        num += d * d;
        den += dy * dy;
        size += s->ynew[i] * s->ynew[i];
    }
    /* h cancels (dy is the difference over h); a difference of a few roundoffs
     * (a rig at rest) tells nothing: 0 */
    return den * h * h > STIFF_ROUNDOFF * STIFF_ROUNDOFF * size ? sqrt(num / den) : 0.0;
}

/* the dense output of the step just accepted (y_old, k of the step, h_old):
 * three more stages */
ERK_INLINE int make_dense_n(PdbfsErk *s, const int n, const int m) {
    const double h = s->h_old, *k = s->k;
    double local[ERK_LOCAL], *acc = n <= ERK_LOCAL ? local : s->acc, *r = s->dense;
    int i;
#define ERK_STAGE(st)                                                              \
    erk_combine(m, n, st, RK_A + (st) * NK, k, acc);                               \
    for (i = 0; i < m; i++) s->tmp[i] = s->y_old[i] + h * acc[i];                  \
    if (erk_rhs(s, s->t_old + RK_C[st] * h, s->tmp, s->k + (st) * n)) return 1;
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

int pdbfs_erk_make_dense(PdbfsErk *s) {
#define ERK_DENSE(N, M) make_dense_n(s, N, M)
    return ERK_BY_SIZE(s, ERK_DENSE);
#undef ERK_DENSE
}

int pdbfs_erk_rows(PdbfsErk *s, double t_old, double h, const double *y_old,
                   const double *y_end, const double *k13, double *rows) {
    const size_t n = (size_t)s->nx;
    memcpy(s->y_old, y_old, sizeof(double) * n);
    memcpy(s->ynew, y_end, sizeof(double) * n);
    memcpy(s->k, k13, sizeof(double) * n * (NSTAGE + 1));
    s->t_old = t_old;
    s->h_old = h;
    if (pdbfs_erk_make_dense(s)) return 1;
    memcpy(rows, s->dense, sizeof(double) * n * 7);
    return 0;
}

void pdbfs_erk_poly(const double *y_old, const double *r, int n, double th, double *out) {
#define ERK_POLY(N) erk_poly_n(N, y_old, r, th, out)
    if (n == PDBFS_ERK_NX + 1) ERK_POLY(PDBFS_ERK_NX + 1);
    else if (n == PDBFS_ERK_NX) ERK_POLY(PDBFS_ERK_NX);
    else ERK_POLY(n);
#undef ERK_POLY
}

void pdbfs_erk_dense(const PdbfsErk *s, double t, double *out) {
    double th = s->h_old > 0 ? (t - s->t_old) / s->h_old : 0.0;
    if (!s->dense_ready || s->fresh) {
        memcpy(out, s->y, sizeof(double) * (size_t)s->nx);
        return;
    }
    pdbfs_erk_poly(s->y_old, s->dense, s->nx, th < 0 ? 0.0 : th > 1 ? 1.0 : th, out);
}

/* pdbfs_erk_rk: the Runge-Kutta arithmetic of pdbfs_erk.c for any number of
 * states (the rig's own counts take pdbfs_erk_sized.c's, compiled for them),
 * and the dense output's rows and values; the same for every rig (compiled
 * once per machine into the compiled backend's drivers).  Never aborts,
 * never prints. */
/* the arithmetic's helpers not forced inline here: any size is the rare
 * case, the numbers are the same, and the compilation takes a third */
#define ERK_INLINE static inline

#include <float.h>
#include <math.h>
#include <string.h>

#include "pdbfs_erk.h"
#include "pdbfs_erk_rk.h"

double pdbfs_erk_attempt_any(PdbfsErk *s, double h) {
    return attempt_n(s, h, s->nx, s->nx - s->nq);
}

int pdbfs_erk_make_dense_any(PdbfsErk *s) {
    return make_dense_n(s, s->nx, s->nx - s->nq);
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

double pdbfs_erk_stiffness_any(PdbfsErk *s, double h) {
    return stiffness_n(s, h, s->nx, s->nx - s->nq);
}

void pdbfs_erk_poly_any(const double *y_old, const double *r, int n, double th, double *out) {
    erk_poly_n(n, y_old, r, th, out);
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

void pdbfs_erk_dense(const PdbfsErk *s, double t, double *out) {
    double th = s->h_old > 0 ? (t - s->t_old) / s->h_old : 0.0;
    if (!s->dense_ready || s->fresh) {
        memcpy(out, s->y, sizeof(double) * (size_t)s->nx);
        return;
    }
    pdbfs_erk_poly(s->y_old, s->dense, s->nx, th < 0 ? 0.0 : th > 1 ? 1.0 : th, out);
}

/* pdbfs_erk_rk: the Runge-Kutta arithmetic of pdbfs_erk.c for any number of
 * states (the rig's own counts take pdbfs_erk_sized.c's, compiled for them),
 * and the dense output's rows and values; the same for every rig (compiled
 * once per machine into the compiled backend's drivers).  Never aborts,
 * never prints. */
/* the arithmetic's helpers not forced inline here: any size is the rare
 * case, the numbers are the same, and the compilation takes a third */
#define ERK_INLINE static inline

#include <string.h>

#include "pdbfs_erk.h"
#include "pdbfs_erk_rk.h"

double pdbfs_erk_attempt_any(PdbfsErk *s, double h) {
    return attempt_n(s, h, s->nx, s->nx - s->nq);
}

int pdbfs_erk_make_dense_any(PdbfsErk *s) {
    return make_dense_n(s, s->nx, s->nx - s->nq);
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

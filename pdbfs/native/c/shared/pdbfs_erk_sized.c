/* pdbfs_erk_sized: pdbfs_erk.c's step arithmetic (pdbfs_erk_rk.h) with the
 * rig's own state counts as constants (pdbfs_erk_size.h: the states, and the
 * states with the summary drivers' impulse as a quadrature), so that the
 * sums over a few states stay in registers and are unrolled; any other
 * count is pdbfs_erk_rk.c's.  The one part of the integrator compiled with
 * each rig's model. */
#include "pdbfs_erk_size.h"       /* PDBFS_ERK_NX: the rig's state count */
#include "pdbfs_erk_rk.h"

/* call(n, m) with n the states of s and m those the stages need (n less its
 * quadratures) where they are the rig's counts, else any(s) */
#define ERK_BY_SIZE(s, call, any)                                                  \
    ((s)->nx == PDBFS_ERK_NX + 1 && (s)->nq == 1 ? call(PDBFS_ERK_NX + 1, PDBFS_ERK_NX)   \
     : (s)->nx == PDBFS_ERK_NX && (s)->nq == 0 ? call(PDBFS_ERK_NX, PDBFS_ERK_NX)         \
     : any(s))

double pdbfs_erk_attempt(PdbfsErk *s, double h) {
#define ERK_ATTEMPT(N, M) attempt_n(s, h, N, M)
#define ERK_ATTEMPT_ANY(s) pdbfs_erk_attempt_any(s, h)
    return ERK_BY_SIZE(s, ERK_ATTEMPT, ERK_ATTEMPT_ANY);
#undef ERK_ATTEMPT
#undef ERK_ATTEMPT_ANY
}

int pdbfs_erk_make_dense(PdbfsErk *s) {
#define ERK_DENSE(N, M) make_dense_n(s, N, M)
    return ERK_BY_SIZE(s, ERK_DENSE, pdbfs_erk_make_dense_any);
#undef ERK_DENSE
}

double pdbfs_erk_stiffness(PdbfsErk *s, double h) {
#define ERK_STIFFNESS(N, M) stiffness_n(s, h, N, M)
#define ERK_STIFFNESS_ANY(s) pdbfs_erk_stiffness_any(s, h)
    return ERK_BY_SIZE(s, ERK_STIFFNESS, ERK_STIFFNESS_ANY);
#undef ERK_STIFFNESS
#undef ERK_STIFFNESS_ANY
}

void pdbfs_erk_poly(const double *y_old, const double *r, int n, double th, double *out) {
#define ERK_POLY(N) erk_poly_n(N, y_old, r, th, out)
    if (n == PDBFS_ERK_NX + 1) ERK_POLY(PDBFS_ERK_NX + 1);
    else if (n == PDBFS_ERK_NX) ERK_POLY(PDBFS_ERK_NX);
    else pdbfs_erk_poly_any(y_old, r, n, th, out);
#undef ERK_POLY
}

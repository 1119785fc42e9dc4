/*
 * The arithmetic of pdbfs_erk.c's steps (stages, error, dense output),
 * written once for any number of states n and inlined where it is called
 * with the rig's own state counts as constants (pdbfs_erk_sized.c with
 * pdbfs_erk_size.h: the states, and the states with the impulse of the
 * summary drivers), so that the compiler keeps the sums of a few states in
 * registers and unrolls them: these loops were half of a run's time, more
 * than the model's right-hand side.  The sums run over the stages in their
 * order, as the textbook's (a stage's last term added last, to the state:
 * pdbfs_erk_rk.h).  Also what pdbfs_erk.c calls of pdbfs_erk_sized.c
 * (internal: the library exports neither).
 */
#ifndef PDBFS_ERK_LA_H
#define PDBFS_ERK_LA_H

#include <float.h>
#include <math.h>

#include "pdbfs_erk.h"

#define NSTAGE 12                  /* stages of a step; the 13th is f at its end */
#define NK 16                      /* with the dense output's three */

/* forced inline (a file may say otherwise: pdbfs_erk_rk.c) */
#ifndef ERK_INLINE
#if defined(__GNUC__) || defined(__clang__)
#define ERK_INLINE static inline __attribute__((always_inline))
#else
#define ERK_INLINE static inline
#endif
#endif

/* the sums' operands do not overlap: the compiler may vectorise them over the
 * states without checking (C99's restrict; MSVC's C spells it __restrict) */
#if defined(_MSC_VER) && !defined(__clang__)
#define ERK_RESTRICT __restrict
#else
#define ERK_RESTRICT restrict
#endif

/* up to so many states the sums are local (registers); beyond, in memory */
#define ERK_LOCAL 16

/* acc = the sum of c[j] k_j over j < nj (zero coefficients skipped), of the
 * first m of the n entries of each stage k_j */
ERK_INLINE void erk_combine(const int m, const int n, int nj, const double *ERK_RESTRICT c,
                             const double *ERK_RESTRICT k, double *ERK_RESTRICT acc) {
    int i;
    for (i = 0; i < m; i++) acc[i] = 0.0;
    /* written out: where nj and c are the table's (every call), no loop over
     * the stages and no test of a coefficient is left */
#define ERK_TERM(j)                                                                \
    if ((j) < nj && c[j] != 0.0)                                                   \
        for (i = 0; i < m; i++) acc[i] += c[j] * k[(size_t)(j) * (size_t)n + i];
    ERK_TERM(0) ERK_TERM(1) ERK_TERM(2) ERK_TERM(3) ERK_TERM(4) ERK_TERM(5)
    ERK_TERM(6) ERK_TERM(7) ERK_TERM(8) ERK_TERM(9) ERK_TERM(10) ERK_TERM(11)
    ERK_TERM(12) ERK_TERM(13) ERK_TERM(14) ERK_TERM(15)
#undef ERK_TERM
}

/* out = y + h acc, acc the sum of c[j] k_j over j < nj (erk_combine), of
 * the first m states; with hl: out = (y + h acc) + hl k_nj, the last term
 * added last.  Every pointer a restrict parameter of a function inlined:
 * the compiler trusts restrict there (not on a local pointer), so it takes
 * the states a vector at a time, each lane doing the same operations in
 * the same order (the same numbers); a third of the instructions of a
 * stage's sums */
ERK_INLINE void erk_at(const int m, const int n, int nj, const double *ERK_RESTRICT c, double h,
                       const double *ERK_RESTRICT y, const double *ERK_RESTRICT k,
                       double *ERK_RESTRICT acc, double *ERK_RESTRICT out) {
    int i;
    erk_combine(m, n, nj, c, k, acc);
    for (i = 0; i < m; i++) out[i] = y[i] + h * acc[i];
}

ERK_INLINE void erk_at_last(const int m, const int n, int nj, const double *ERK_RESTRICT c,
                            double h, double hl, const double *ERK_RESTRICT y,
                            const double *ERK_RESTRICT k, double *ERK_RESTRICT acc,
                            double *ERK_RESTRICT out) {
    const double *ERK_RESTRICT kl = k + (size_t)nj * (size_t)n;
    int i;
    erk_combine(m, n, nj, c, k, acc);
    for (i = 0; i < m; i++) out[i] = (y[i] + h * acc[i]) + hl * kl[i];
}

/* the polynomial of a step's dense output at theta (pdbfs_erk_poly) */
ERK_INLINE void erk_poly_n(const int n, const double *ERK_RESTRICT y_old,
                           const double *ERK_RESTRICT r, double th, double *ERK_RESTRICT out) {
    const double th1 = 1.0 - th;
    int i;
    for (i = 0; i < n; i++) {          /* alternately times theta and 1 - theta */
        double acc = r[6 * n + i] * th;
        acc = (acc + r[5 * n + i]) * th1;
        acc = (acc + r[4 * n + i]) * th;
        acc = (acc + r[3 * n + i]) * th1;
        acc = (acc + r[2 * n + i]) * th;
        acc = (acc + r[n + i]) * th1;
        acc = (acc + r[i]) * th;
        out[i] = y_old[i] + acc;
    }
}

/* f(t, x) into out, counted, its test for finite values left to the caller
 * (erk_finite: an attempt tests all its stages at once, where a test per
 * stage was a fifth of a stage's instructions); 1 when the function fails */
ERK_INLINE int erk_rhs_unchecked(PdbfsErk *s, double t, const double *x, double *out) {
    s->rhs_evals++;
    return pdbfs_eval_txp(s->ev, s->rhs, t, x, out);
}

/* whether the n values of v are all finite (every entry tested at once, no
 * branch per entry: with n a constant the test is unrolled, where a loop
 * over s->nx was 8 % of a run) */
ERK_INLINE int erk_finite(const int n, const double *ERK_RESTRICT v) {
    int i, finite = 1;
    for (i = 0; i < n; i++) finite &= fabs(v[i]) <= DBL_MAX;
    return finite;
}

/* f(t, x) of the n states into out, counted; 1 when it fails or is not finite */
ERK_INLINE int erk_rhs_n(PdbfsErk *s, const int n, double t, const double *x, double *out) {
    return erk_rhs_unchecked(s, t, x, out) || !erk_finite(n, out);
}

#define erk_rhs(s, t, x, out) erk_rhs_n(s, (s)->nx, t, x, out)

/* the event indicators at (t, x) into g */
ERK_INLINE void erk_events(PdbfsErk *s, double t, const double *x, double *g) {
    if (s->ne > 0) pdbfs_eval_txp(s->ev, s->events, t, x, g);
}

/* ... and their rates for the state's derivative f (dg/dx f + dg/dt) into
 * g[ne .. 2 ne - 1]: where a step begins and ends (pdbfs_erk_near_a_root) */
ERK_INLINE void erk_events_both(PdbfsErk *s, double t, const double *x, const double *f, double *g) {
    if (s->ne > 0) pdbfs_eval_txvp(s->ev, s->events_both, t, x, f, g);
}

/* the indicators are also looked at inside each step, at these many equal
 * parts of it: a contact that opens and closes within one long step, which
 * the step's ends alone would not show, is found */
#define EVENT_PARTS 4
/* a rejected attempt's kink is located on the attempt's ends to this (of it) */
#define KINK_TOL 1e-4

/* where an attempt of length h that failed its error test has an indicator
 * change sign: the first such theta in (0, 1), 2 when none does; and whether a
 * lazy step needs its dense output to look at its indicators
 * (pdbfs_erk_screen.c) */
double pdbfs_erk_kink_in_attempt(PdbfsErk *s, double h);
int pdbfs_erk_near_a_root(PdbfsErk *s, double h);

/* one attempt from (t, y, f) over h: ynew, k[0..12]; the weighted error, or
 * INFINITY when a stage is not finite (pdbfs_erk_sized.c) */
double pdbfs_erk_attempt(PdbfsErk *s, double h);

/* an attempt as pdbfs_erk_attempt whose error, where the embedded estimate
 * passes it, is checked by two half steps too: the larger estimate; *low set
 * where the halves show a law of low order (pdbfs_erk_rk.c) */
double pdbfs_erk_attempt_halves(PdbfsErk *s, double h, int *low);

/* h |lambda| for the fastest mode the attempt just made over h saw; 0: f did
 * not change, -1: no state changed by more than roundoff (pdbfs_erk_sized.c) */
double pdbfs_erk_stiffness(PdbfsErk *s, double h);

/* the dense output of the step just accepted (y_old, ynew, k of the step,
 * t_old, h_old): three more stages; 0, or 1 when one is not finite */
int pdbfs_erk_make_dense(PdbfsErk *s);

#endif

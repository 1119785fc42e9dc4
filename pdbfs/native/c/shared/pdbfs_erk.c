/* pdbfs_erk: see pdbfs_erk.h.  Never aborts, never prints. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_erk.h"
#include "pdbfs_erk_la.h"

#define SAFETY 0.9
#define GROW_MAX 6.0
#define SHRINK_MIN 0.333
#define ROOT_ITER 100
#define RESTART_STEP 0.01          /* first step after a root, of the step before */
#define KINK_STEPS 1               /* steps after a kink with its own control (factor()) */
#define KINK_GROW 50.0
#define STEP_AGAIN 1               /* step(): no step taken, try again from where it began */
/* a rejected attempt across a kink: its retry ends this much (of the
 * kink's theta) past it, at least KINK_MIN of the attempt */
#define KINK_MARGIN 1e-3
#define KINK_MIN 1e-3
/* h |lambda| (pdbfs_erk_stiffness) at most STIFF_DAMPED, where the method's
 * stability function is 0.18 (its stability ends at 6.4 on the negative real
 * axis), where two steps' estimates agree to STIFF_AGREE */
#define STIFF_DAMPED 5.5
#define STIFF_AGREE 0.25
/* the first step after a kink is checked by two half steps
 * (pdbfs_erk_attempt_halves), and may shrink faster */
#define KINK_SHRINK_MIN 0.1
/* ... and then no step is longer than KINK_GRADE times its distance from
 * the kink: up to there the embedded estimate holds (measured on the
 * quadrature of t^1.5 from its onset: it underrates the error below) */
#define KINK_GRADE 2.0

/* the step's factor for an error err, within [lo, hi]: as err^(-1/8), but
 * err^(-1/3) just after a kink, where the solution is a few times
 * differentiable only (a contact's force grows as d^1.5) and the error falls
 * as h^3, not h^8 (roots, not libm's general pow: it took 2 % of a run) */
static double factor(const PdbfsErk *s, double err, double lo, double hi) {
    if (!isfinite(err)) return 0.25;
    if (err == 0.0) return hi;
    return fmin(hi, fmax(lo, SAFETY / (s->kink_steps ? cbrt(err) : sqrt(sqrt(sqrt(err))))));
}

int pdbfs_erk_init(PdbfsErk *s, int nx, int ne, PdbfsEval *ev) {
    size_t n = (size_t)nx, m = (size_t)(ne > 0 ? ne : 1);
    memset(s, 0, sizeof *s);
    s->nx = nx;
    s->ne = ne;
    s->ev = ev;
    s->ode = s->rhs = pdbfs_ode;
    s->events = pdbfs_events;
    s->events_both = pdbfs_events_both;
    /* y, f, y_old, ynew, tmp, acc, dense (7), k (16), half (3 + 1 + 13) */
    s->y = malloc(sizeof(double) * (n * (6 + 7 + NK + 4 + NSTAGE + 1) + 7 * m));
    if (!s->y) return -100;
    s->f = s->y + n;
    s->y_old = s->f + n;
    s->ynew = s->y_old + n;
    s->tmp = s->ynew + n;
    s->acc = s->tmp + n;
    s->dense = s->acc + n;
    s->k = s->dense + 7 * n;
    s->g_old = s->k + NK * n;
    s->g_new = s->g_old + 2 * m;
    s->g_tmp = s->g_new + 2 * m;
    s->g_a = s->g_tmp + m;
    s->g_b = s->g_a + m;
    s->half = s->g_b + m;
    s->t_kink = -INFINITY;
    return 0;
}

void pdbfs_erk_free(PdbfsErk *s) {
    free(s->y);
    s->y = NULL;
}

/* RMS of v / (atol + rtol |y|) over the states the error test sees (not
 * the quadratures: a run with one takes the steps of the run without) */
static double wnorm(const PdbfsErk *s, const double *v, const double *y) {
    const int m = s->nx - s->nq;
    double sum = 0.0;
    int i;
    for (i = 0; i < m; i++) {
        double w = v[i] / (s->atol[i] + s->rtol * fabs(y[i]));
        sum += w * w;
    }
    return sqrt(sum / m);
}

/* Hairer's first step: an Euler step's change of f predicts the scale */
static double first_step(PdbfsErk *s) {
    double d0 = wnorm(s, s->y, s->y), d1 = wnorm(s, s->f, s->y), d2, h0, h1;
    double *f1 = s->k + s->nx;
    int i;
    h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (isfinite(s->t_stop) && s->t_stop > s->t && h0 > s->t_stop - s->t) h0 = s->t_stop - s->t;
    for (i = 0; i < s->nx; i++) s->tmp[i] = s->y[i] + h0 * s->f[i];
    if (erk_rhs(s, s->t + h0, s->tmp, f1)) return 1e-3 * h0;
    for (i = 0; i < s->nx; i++) f1[i] -= s->f[i];
    d2 = wnorm(s, f1, s->y) / h0;
    h1 = fmax(d1, d2) <= 1e-15 ? fmax(1e-6, 1e-3 * h0) : pow(0.01 / fmax(d1, d2), 1.0 / 8.0);
    return fmin(100.0 * h0, h1);
}

int pdbfs_erk_start(PdbfsErk *s, const PdbfsCvodeSettings *set, double t0, const double *x0) {
    int i;
    s->rtol = set->rtol;
    s->atol = set->atol;
    s->max_step = set->max_step;
    s->t_stop = set->t_stop;
    s->t = s->t_old = t0;
    s->h_old = 0.0;
    s->dense_ready = 0;
    s->fresh = 1;
    s->quiet = -1;
    s->err_prev = 0.0;
    s->kink_steps = 0;
    s->t_kink = -INFINITY;
    s->stiff_z = 0.0;
    s->stiff_steps = 0;
    s->msg[0] = 0;
    s->rhs = pdbfs_for_params(s->ode, s->ev->p);
    s->events = pdbfs_for_params(pdbfs_events, s->ev->p);
    s->events_both = pdbfs_for_params(pdbfs_events_both, s->ev->p);
    memcpy(s->y, x0, sizeof(double) * (size_t)s->nx);
    if (erk_rhs(s, t0, s->y, s->f)) {
        snprintf(s->msg, sizeof s->msg, "the right-hand side is not finite at t = %.10g", t0);
        return 1;
    }
    erk_events_both(s, t0, s->y, s->f, s->g_old);
    s->h = first_step(s);
    /* a start at a kink (an indicator at its root: a contact that begins at
     * t0) is a restart: the estimate above assumes a smooth solution */
    for (i = 0; i < s->ne && s->g_old[i] != 0.0; i++) {}
    if (i < s->ne) {
        s->h *= RESTART_STEP;
        s->kink_steps = KINK_STEPS;
    }
    if (s->max_step > 0 && s->h > s->max_step) s->h = s->max_step;
    return 0;
}

static void dense_at(const PdbfsErk *s, double th, double *out) {
    pdbfs_erk_poly(s->y_old, s->dense, s->nx, th, out);
}

/* indicator i on the dense output at theta */
static double g_at(PdbfsErk *s, int i, double th) {
    dense_at(s, th, s->tmp);
    erk_events(s, s->t_old + th * s->h_old, s->tmp, s->g_tmp);
    return s->g_tmp[i];
}

/* the smallest theta past the root of indicator i in (a, b] (Illinois), g0
 * and g1 its values at a and b: the right end of a bracket a few roundoffs wide */
static double root_of(PdbfsErk *s, int i, double a, double b, double g0, double g1) {
    double fa = g0, fb = g1;
    double tol = (4.0 * DBL_EPSILON * fabs(s->t_old + s->h_old) + 1e-300) / s->h_old;
    int side = 0, it;
    if (tol < 1e-15) tol = 1e-15;
    for (it = 0; it < ROOT_ITER && b - a > tol; it++) {
        double c = (fa != fb) ? b - fb * (b - a) / (fb - fa) : 0.5 * (a + b), fc;
        if (!(c > a && c < b)) c = 0.5 * (a + b);
        if (c - a < 0.25 * tol) c = a + 0.5 * tol;           /* keep both ends moving */
        if (b - c < 0.25 * tol) c = b - 0.5 * tol;
        fc = g_at(s, i, c);
        if ((g0 < 0) ? fc >= 0 : fc <= 0) {                  /* past the root */
            b = c;
            fb = fc;
            if (side == 1) fa *= 0.5;
            side = 1;
        } else {
            a = c;
            fa = fc;
            if (side == -1) fb *= 0.5;
            side = -1;
        }
    }
    return b;
}

/* one accepted step (rejections inside); dense output made when the step
 * reaches t_out or holds a root, where the step is cut and restarted */
static int step(PdbfsErk *s, double t_out) {
    const int n = s->nx;
    double h = s->h, err, fac, ec;
    int rejected = 0, i, first = -1, was_fresh = s->fresh, low = 0;
    double th_root = 2.0;
    for (;;) {
        if (s->max_step > 0 && h > s->max_step) h = s->max_step;
        /* a graded mesh away from a kink of a law of low order */
        if (!s->kink_steps && s->t > s->t_kink && h > KINK_GRADE * (s->t - s->t_kink))
            h = KINK_GRADE * (s->t - s->t_kink);
        if (isfinite(s->t_stop) && s->t + h * (1.0 + 1e-6) >= s->t_stop) h = s->t_stop - s->t;
        if (!(h > 8.0 * DBL_EPSILON * fabs(s->t))) {
            snprintf(s->msg, sizeof s->msg, "the step size fell below roundoff at t = %.10g", s->t);
            return PDBFS_ERK_STEP_UNDERFLOW;
        }
        err = s->kink_steps ? pdbfs_erk_attempt_halves(s, h, &low) : pdbfs_erk_attempt(s, h);
        if (err <= 1.0) break;
        s->rejected++;
        rejected = 1;
        fac = factor(s, err, s->kink_steps ? KINK_SHRINK_MIN : SHRINK_MIN, 1.0);
        /* a kink inside: the next attempt ends just past it (its root is
         * then located on that step's dense output, and the step cut there) */
        if (isfinite(err) && s->ne > 0) {
            double th = pdbfs_erk_kink_in_attempt(s, h) * (1.0 + KINK_MARGIN);
            if (th < fac) fac = fmax(th, KINK_MIN);
        }
        h *= fac;
    }
    /* the step grows by the larger of this error and the one before: on this
     * kind of rig the error estimate swings tenfold from step to step (with
     * the phase of the oscillations), and growing on one small estimate cost a
     * rejected step in three (a tenth fewer evaluations, measured on the
     * paper rig's sweep) */
    ec = fmax(err, s->err_prev);
    s->err_prev = err;
    fac = factor(s, ec, 0.0, s->kink_steps ? KINK_GROW : GROW_MAX);
    if (s->kink_steps) {
        s->kink_steps--;
        s->t_kink = low ? s->t : -INFINITY;
    }
    if (rejected && fac > 1.0) fac = 1.0;
    /* where the steps are held by stability a fast mode is barely damped
     * (|R(h lambda)| near 1), and the errors of many steps add up instead of
     * dying out (an approach to equilibrium ended 40 tolerances off): the
     * steps stay where it is damped */
    {
        /* (an estimate that two steps in a row agree on: a dominant fast mode,
         * not the noise of oscillations in several; where the states barely
         * change, the one before holds; where f did not change at all, no
         * step is held back, and the one before is kept to compare the next
         * estimate with) */
        double z = pdbfs_erk_stiffness(s, h), prev = s->stiff_z, lam = z < 0.0 ? prev : z / h;
        if (z != 0.0) {
            s->stiff_z = lam;
            if (fabs(lam - prev) <= STIFF_AGREE * fmax(lam, prev) && fmin(lam, prev) * h * fac > STIFF_DAMPED)
                fac = STIFF_DAMPED / (fmin(lam, prev) * h);
        }
    }
    s->t_old = s->t;
    s->h_old = h;
    memcpy(s->y_old, s->y, sizeof(double) * (size_t)n);
    s->dense_ready = 0;
    s->fresh = 0;
    s->steps++;
    s->h = h * fac;
    if (s->ne > 0) {
        int part;
        double *ga = s->g_a, *gb = s->g_b;
        erk_events_both(s, s->t_old + h, s->ynew, s->k + NSTAGE * n, s->g_new);
        if (s->lazy && !pdbfs_erk_near_a_root(s, h)) part = EVENT_PARTS + 1;   /* nothing to look at */
        else if (pdbfs_erk_make_dense(s)) return -3;
        else part = 1;
        memcpy(ga, s->g_old, sizeof(double) * (size_t)s->ne);
        for (; part <= EVENT_PARTS && first < 0; part++) {
            double a = (double)(part - 1) / EVENT_PARTS, b = (double)part / EVENT_PARTS, *sw;
            if (part == EVENT_PARTS) {
                memcpy(gb, s->g_new, sizeof(double) * (size_t)s->ne);
            } else {
                dense_at(s, b, s->tmp);
                erk_events(s, s->t_old + b * h, s->tmp, gb);
            }
            for (i = 0; i < s->ne; i++) {
                double g0 = ga[i], g1 = gb[i];
                if (i == s->quiet) continue;
                if ((g0 < 0 && g1 >= 0) || (g0 > 0 && g1 <= 0)) {
                    double th = root_of(s, i, a, b, g0, g1);
                    if (th < th_root) {
                        th_root = th;
                        first = i;
                    }
                }
            }
            sw = ga;
            ga = gb;
            gb = sw;
        }
    }
    if (s->stiff_after > 0) s->stiff_steps = h >= s->stiff_h ? s->stiff_steps + 1 : 0;
    if (first >= 0 && th_root < 1.0) {
        /* restart just past the root: the kink is not stepped over.  The step
         * that found it has stages beyond the kink; the step is taken again up
         * to the root (its stages all before it), with its own dense output */
        double h2 = th_root * h;
        double e2 = h2 > 8.0 * DBL_EPSILON * fabs(s->t_old) ? pdbfs_erk_attempt(s, h2) : INFINITY;
        if (e2 <= 1.0) {
            s->h_old = h2;
            if (pdbfs_erk_make_dense(s)) return -3;
            memcpy(s->y, s->ynew, sizeof(double) * (size_t)n);
            s->t = s->t_old + h2;
        } else if (h2 > 8.0 * DBL_EPSILON * fabs(s->t_old)) {
            /* the step up to the root fails its error test (near a contact's
             * end the solution is not smooth: the force falls as d^1.5), so the
             * first step's error estimate, across the kink, did not see its
             * error either: no step is taken.  The next attempt ends short of
             * the root (its length to the root would fail again) */
            s->steps--;
            s->rejected++;
            s->dense_ready = 0;
            s->fresh = was_fresh;
            s->h = h2 * factor(s, e2, SHRINK_MIN, 1.0);
            return STEP_AGAIN;
        } else {                  /* at the start: its dense output is the start */
            s->t = s->t_old + th_root * h;
            dense_at(s, th_root, s->y);
        }
        if (erk_rhs(s, s->t, s->y, s->f)) return -3;
        erk_events_both(s, s->t, s->y, s->f, s->g_old);
        s->roots++;
        /* past a kink the solution is smooth again only to a low order (the
         * contact force grows as d^1.5): begin with a short step, grown back
         * by the step control for that order (factor(), KINK_STEPS) */
        if (s->h > RESTART_STEP * h) s->h = RESTART_STEP * h;
        s->err_prev = 0.0;        /* a fresh start: the errors before the kink say nothing */
        s->stiff_steps = 0;
        s->kink_steps = KINK_STEPS;
        s->quiet = first;
    } else {
        s->quiet = -1;
        s->t = s->t_old + h;
        memcpy(s->y, s->ynew, sizeof(double) * (size_t)n);
        memcpy(s->f, s->k + NSTAGE * n, sizeof(double) * (size_t)n);   /* f at the end: FSAL */
        if (first >= 0) s->roots++;                                      /* the root is the end */
        if (s->ne > 0) memcpy(s->g_old, s->g_new, sizeof(double) * 2 * (size_t)s->ne);
        if (s->t >= t_out && !s->dense_ready && pdbfs_erk_make_dense(s)) return -3;
    }
    for (i = 0; i < n; i++)
        if (!isfinite(s->y[i])) {
            snprintf(s->msg, sizeof s->msg, "the solution is NaN or infinite at t = %.10g", s->t);
            return -3;
        }
    return 0;
}

int pdbfs_erk_step_watched(PdbfsErk *s, double t_out) {
    int flag = step(s, t_out);
    if (flag == STEP_AGAIN) return PDBFS_ERK_AGAIN;
    if (flag) return flag;
    /* whoever watches the steps may read their dense output (pdbfs_record.c) */
    if (s->on_step && !s->dense_ready && !s->lazy && s->t > s->t_old && pdbfs_erk_make_dense(s))
        return -3;
    if (s->on_step && s->substeps > 1) {
        int j;
        double *xi = s->k + 13 * s->nx;    /* free once the dense output is made */
        for (j = 1; j < s->substeps; j++) {
            double ti = s->t_old + (s->t - s->t_old) * j / s->substeps;
            dense_at(s, (ti - s->t_old) / s->h_old, xi);
            if (s->on_step(s->step_env, ti, xi)) {
                snprintf(s->msg, sizeof s->msg, "stopped by the step callback at t = %.10g", ti);
                return PDBFS_CV_STOPPED;
            }
        }
    }
    if (s->on_step && s->on_step(s->step_env, s->t, s->y)) {
        snprintf(s->msg, sizeof s->msg, "stopped by the step callback at t = %.10g", s->t);
        return PDBFS_CV_STOPPED;
    }
    return 0;
}

int pdbfs_erk_advance(PdbfsErk *s, double t_out, long max_steps, double *x_out) {
    long n = 0;
    int flag;
    while (s->t < t_out) {
        /* restarted at a root within roundoff of t_out: no step is that short */
        if (PDBFS_ERK_NEAR(t_out, s->t)) {
            if (s->dense_ready && !s->fresh && t_out <= s->t_old + s->h_old)
                pdbfs_erk_dense(s, t_out, x_out);
            else
                memcpy(x_out, s->y, sizeof(double) * (size_t)s->nx);
            return 0;
        }
        if (++n > max_steps) {
            snprintf(s->msg, sizeof s->msg, "%ld steps without reaching t = %.10g", max_steps, t_out);
            return PDBFS_CV_TOO_MUCH_WORK;
        }
        if (s->stiff_after > 0 && s->stiff_steps >= s->stiff_after) {
            snprintf(s->msg, sizeof s->msg, "%d steps in a row of at least %.3g s, held by stability",
                     s->stiff_steps, s->stiff_h);
            return PDBFS_ERK_STIFF;
        }
        flag = pdbfs_erk_step_watched(s, t_out);
        if (flag == PDBFS_ERK_AGAIN) continue;
        if (flag) return flag;
    }
    if (s->fresh || t_out == s->t) memcpy(x_out, s->y, sizeof(double) * (size_t)s->nx);
    else pdbfs_erk_dense(s, t_out, x_out);
    return 0;
}

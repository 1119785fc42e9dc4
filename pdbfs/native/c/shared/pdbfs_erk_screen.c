/* pdbfs_erk_screen: where a step of pdbfs_erk.c may hold a root of an event
 * indicator, judged on the cubic Hermite interpolant of the step's ends (its
 * states and derivatives: no evaluation of the right-hand side); see
 * pdbfs_erk_la.h.  Never aborts, never prints. */
#include <math.h>

#include "pdbfs_erk.h"
#include "pdbfs_erk_la.h"

/* the cubic Hermite interpolant of (y0, f0) and (y1, f1) over h at theta c, into s->tmp */
static void hermite(PdbfsErk *s, const double *y0, const double *f0, const double *y1,
                    const double *f1, double h, double c) {
    const double c2 = c * c, c3 = c2 * c;
    int j;
    for (j = 0; j < s->nx; j++)
        s->tmp[j] = (2 * c3 - 3 * c2 + 1) * y0[j] + (c3 - 2 * c2 + c) * h * f0[j]
                    + (3 * c2 - 2 * c3) * y1[j] + (c3 - c2) * h * f1[j];
}

/* where an attempt that failed its error test has an indicator change sign
 * (its stages straddle a kink: that, not the step's length, is what failed):
 * the first such theta in (0, 1), located roughly on the cubic Hermite
 * interpolant of the attempt's ends; 2 when none changes sign */
double pdbfs_erk_kink_in_attempt(PdbfsErk *s, double h) {
    const int n = s->nx;
    const double *y1 = s->ynew, *f0 = s->k, *f1 = s->k + NSTAGE * n;
    double best = 2.0;
    int i, it;
    erk_events(s, s->t + h, y1, s->g_new);
    for (i = 0; i < s->ne; i++) {
        double g0 = s->g_old[i], g1 = s->g_new[i], a = 0.0, b = 1.0, fa = g0, fb = g1;
        if (i == s->quiet || !((g0 < 0 && g1 >= 0) || (g0 > 0 && g1 <= 0))) continue;
        for (it = 0; it < 30 && b - a > KINK_TOL; it++) {   /* Illinois, to KINK_TOL */
            double c = (fa != fb) ? b - fb * (b - a) / (fb - fa) : 0.5 * (a + b), fc;
            if (!(c > a && c < b)) c = 0.5 * (a + b);
            hermite(s, s->y, f0, y1, f1, h, c);
            erk_events(s, s->t + c * h, s->tmp, s->g_tmp);
            fc = s->g_tmp[i];
            if ((g0 < 0) ? fc >= 0 : fc <= 0) {
                b = c;
                fb = fc;
                fa *= 0.5;
            } else {
                a = c;
                fa = fc;
                fb *= 0.5;
            }
        }
        if (b < best) best = b;
    }
    return best;
}

/* whether an indicator stays clear of zero inside a step of length h, on
 * the cubic Hermite interpolant of its values g0, g1 and rates r0, r1 at
 * the step's ends, at the step's parts: nowhere closer to zero than twice
 * its bend from the line between its ends (pdbfs_erk_near_a_root) */
static int clear_at_parts(double h, double g0, double g1, double r0, double r1) {
    const double sg = g0 > 0 ? 1.0 : -1.0;
    double lo = fmin(fabs(g0), fabs(g1)), bend = 0.0;
    int part;
    for (part = 1; part < EVENT_PARTS; part++) {
        const double c = (double)part / EVENT_PARTS, c2 = c * c, c3 = c2 * c;
        const double b00 = 2 * c3 - 3 * c2 + 1, b10 = (c3 - 2 * c2 + c) * h, b01 = 3 * c2 - 2 * c3,
                     b11 = (c3 - c2) * h;
        const double v = sg * (b00 * g0 + b10 * r0 + b01 * g1 + b11 * r1);
        const double line = sg * (g0 + c * (g1 - g0));
        lo = fmin(lo, v);
        bend = fmax(bend, fabs(v - line));
    }
    return lo > 2.0 * bend;
}

/* lazy (sweeps): whether the indicators need the look on the step's dense
 * output, judged on each indicator's cubic Hermite interpolant of its values
 * and rates at the step's ends (g_old, g_new: no evaluation, where states'
 * interpolants and the indicators at each part were a tenth of a run; the
 * same numbers for an indicator linear in the state and time, as a contact's
 * and a valve's are) at the same parts: an indicator that is zero or changes
 * sign at an end or a part, or bends inside the step by half its distance
 * from zero or more; the others stay clear of zero, and the step needs no
 * dense output.  Most are clear by a bound, without the parts: the
 * interpolant leaves the line between its ends by at most c (1 - c) times
 * the larger of its ends' slopes' differences from the line's (d0 - dg,
 * d1 - dg, over the step): a quarter of it.  An indicator farther from zero
 * than the whole of it (with roundoff to spare) passes the look at the parts
 * (its distance there at least 3/4 of it, its bend at most 1/4), so the
 * answer is the same (the look was a tenth of a run) */
int pdbfs_erk_near_a_root(PdbfsErk *s, double h) {
    const int ne = s->ne;
    const double *r0 = s->g_old + ne, *r1 = s->g_new + ne;
    int i;
    for (i = 0; i < ne; i++) {
        const double g0 = s->g_old[i], g1 = s->g_new[i], d0 = h * r0[i], d1 = h * r1[i];
        const double dg = g1 - g0, near = fmin(fabs(g0), fabs(g1));
        if (i == s->quiet) continue;
        if (!(g0 * g1 > 0)) return 1;
        if (near > fmax(fabs(d0 - dg), fabs(d1 - dg))
                       + 1e-12 * (fabs(g0) + fabs(g1) + fabs(d0) + fabs(d1)))
            continue;
        if (!clear_at_parts(h, g0, g1, r0[i], r1[i])) return 1;
    }
    return 0;
}

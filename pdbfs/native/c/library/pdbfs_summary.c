/*
 * pdbfs summary driver: many parameter points in one call, each integrated
 * with CVODE (native/c/pdbfs_cvode.c) and reduced to its summary, for
 * sweeps at the speed of compiled CVODE (pdbfs.simulation.compiled).
 *
 * The same for every rig: the rig's pdbfs_rig (pdbfs_batch_model.h) says which
 * outputs play which summary role (pressure, contact force, piston
 * displacement, striker velocity; -1 where the rig has none), and
 * CasADi-generated functions give those outputs (pdbfs_roles), their time
 * derivatives (pdbfs_roles_dot) and the ODE with the contact force's
 * integral as an extra state (pdbfs_ode_q, pdbfs_jac_q): impulses come out
 * of the integration itself.
 *
 * One pass records the state and the roles after every internal step (the
 * rig's events are CVODE roots and restarts, so no step straddles a kink;
 * pdbfs_record.c).
 * Then the few steps that matter are integrated again from their recorded
 * start with CVODE's root finding on the quantity in question: the slope of
 * a role where its largest record lies (the peak), the pressure minus 1 % of
 * the peak where it crosses that level, the striker velocity where it turns.
 * These are the definitions of pdbfs/simulation/summary.py, located on the
 * solution to the solver's accuracy, not on an output grid.
 *
 * The pulse is paired from its crossings by their direction (up, then
 * down); a pulse that begins before t = 0 or has not ended by t_end has no
 * duration (NaN, and a message), crossings that do not alternate fail the
 * point; one whose highest pressure lies inside the run is followed past
 * t_end (follow()), as summary.py does, to tell whether that is its peak.
 * Whatever grows with the rig or the run is on the heap: a large rig's
 * state would fill a worker thread's stack.
 *
 * Thread safe: each call allocates its own memory; ctypes releases the GIL,
 * so threads run calls in parallel.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pdbfs_batch_model.h"
#include "pdbfs_cvode.h"
#include "pdbfs_erk.h"
#include "pdbfs_pulse.h"
#include "pdbfs_record.h"

#define API __attribute__((visibility("default")))

/* the summary's entries, in this order (pdbfs.simulation.compiled.SUMMARY_KEYS) */
enum { S_PEAK, S_TPEAK, S_DURATION, S_FORCE, S_DISP, S_RESTITUTION, S_COMPLETE, NSUM };
/* the statistics of a point, in this order (pdbfs.simulation.compiled.STAT_KEYS) */
enum { ST_STEPS, ST_RHS, ST_JAC, ST_ROOTS, ST_METHOD, ST_WALL, NSTAT };

/* a point's failures beyond pdbfs_batch_run's codes */
#define RC_NOT_FINITE 4      /* as pdbfs_batch.c */
#define RC_NO_MEMORY 2
#define RC_BAD_CROSSINGS 6   /* the pulse's crossings do not alternate or are not resolved */
#define RC_FOLLOW 7          /* a pulse cut off at t_end could not be followed past it */

/* Guo & Batzer's impulse ratio, as summary.py's restitution; NaN where it is
 * undefined or the run ends before the rebound's impulse is all in (a rig
 * with a contact force only) */
static double restitution(History *H, double *x_pk, int ended, int *oom, Note *m) {
    const int f = PDBFS_ROLE_FORCE, iq = PDBFS_NX;   /* the impulse state */
    long last = H->n - 1;
    double before = 0.0, after = 0.0;
    if (PDBFS_ROLE_VELOCITY >= 0) {
        /* over the blow, split where the striker stops (its velocity turns from
         * down to up), up to the apex of its rebound (or the end) */
        Crossings c = {0};
        long k = -1, i;
        int r = pdbfs_crossings(H, PDBFS_ROLE_VELOCITY, 0.0, &c);   /* -2: turns not resolved */
        if (r == -1) *oom = 1;
        if (r == -2) pdbfs_note(m, "the striker's turn is not resolved: no restitution (tighten "
                                "rtol and atol)");
        for (i = 0; i < c.n && k < 0; i++)
            if (c.dir[i] < 0) k = i;                     /* from down (v > 0) to up (v < 0) */
        if (!r && k >= 0 && (k + 1 < c.n || ended)) {
            double q_back = k + 1 < c.n ? c.x[(k + 1) * NXQ + iq] : H->x[last * NXQ + iq];
            before = c.x[k * NXQ + iq];
            after = q_back - before;
        }
        pdbfs_free_crossings(&c);
    } else {
        /* the first contact, split at its force peak */
        long k = 0, e;
        double t_pk, f_pk;
        while (k < H->n && !(R(H, k, f) > 0)) k++;
        for (e = k; e < H->n && R(H, e, f) > 0; e++) {}
        if (e <= last) {                                 /* the contact ended inside the run */
            *oom |= pdbfs_peak(H, f, k > 0 ? k - 1 : 0, e + 1, &t_pk, &f_pk, x_pk);
            before = x_pk[iq];
            after = H->x[e * NXQ + iq] - before;
        }
    }
    return before > 0 ? after / before : NAN;
}

/* the summary of one point into out; 0, or a failure code with its reason in m
 * (also pdbfs_run_summary.c's, on the record of a run over an output grid) */
int pdbfs_summarise(History *H, double *out, double *x_pk, Note *m) {
    int i, ended = 1, oom = 0, horizon;
    long last = H->n - 1;
    double t_end = H->t[last];
    Crossings c = {0};
    for (i = 0; i < NSUM; i++) out[i] = NAN;
    if (PDBFS_ROLE_FORCE >= 0 && R(H, last, PDBFS_ROLE_FORCE) > 0) ended = 0;
    if (PDBFS_ROLE_PRESSURE >= 0) {
        const int j = PDBFS_ROLE_PRESSURE;
        double level;
        int ups = 0, pulse, k;
        char why[256];
        /* the pulse rises from the start (static) pressure, as summary_run.py's */
        double base = R(H, 0, j);
        oom |= pdbfs_peak(H, j, 0, H->n, &out[S_TPEAK], &out[S_PEAK], NULL);
        level = base + PULSE_LEVEL * (out[S_PEAK] - base);
        if (!(out[S_PEAK] - base > 1e-5 * fabs(base) + 1e-3)) {   /* as summary_run.has_pulse */
            out[S_PEAK] = out[S_TPEAK] = out[S_DURATION] = NAN;
            out[S_COMPLETE] = 0.0;
            pdbfs_note(m, "no pressure pulse in [0, %.6g] s (the pressure does not rise above its "
                       "start value %.6g Pa)", t_end, base);
        } else {
            if (out[S_TPEAK] >= t_end) {      /* a maximum at the horizon is no peak */
                pdbfs_note(m, "the pressure still rises at t_end = %.6g s: its peak is later", t_end);
                out[S_PEAK] = out[S_TPEAK] = NAN;
            }
            k = pdbfs_crossings(H, j, level, &c);
            if (k) {
                pdbfs_free_crossings(&c);
                if (k == -1) pdbfs_note(m, "out of memory");
                else pdbfs_note(m, "the pressure's crossings of %g %% of its peak (%.6g) are not "
                                "resolved: integrated again, a step shows other crossings (tighten "
                                "rtol and atol)", 100 * PULSE_LEVEL, level);
                return k == -1 ? RC_NO_MEMORY : RC_BAD_CROSSINGS;
            }
            pulse = pdbfs_pulse_pairs(c.n, c.t, c.dir, R(H, 0, j) > level, R(H, last, j) > level,
                                      H->t[0], t_end, &out[S_DURATION], why, sizeof why);
            for (i = 0; i < c.n; i++) ups += c.dir[i] > 0;
            pdbfs_free_crossings(&c);
            if (pulse == PULSE_BAD) {
                pdbfs_note(m, "%s", why);
                return RC_BAD_CROSSINGS;
            }
            if (pulse == PULSE_CUT) pdbfs_note(m, "%s", why);
            out[S_COMPLETE] = pulse == PULSE_OK && ups > 0 && ended ? 1.0 : 0.0;
        }
    }
    if (!ended) pdbfs_note(m, "the contact continues at t_end: the blow has not ended");
    /* a pulse cut off at t_end: a maximum at the horizon is no maximum (summary.py's) */
    horizon = out[S_COMPLETE] == 0.0;
    if (PDBFS_ROLE_DISP >= 0) {
        double t;
        oom |= pdbfs_peak(H, PDBFS_ROLE_DISP, 0, H->n, &t, &out[S_DISP], NULL);
        if (horizon && t >= t_end * (1 - 1e-9)) out[S_DISP] = NAN;
    }
    if (PDBFS_ROLE_FORCE >= 0) {
        double t;
        oom |= pdbfs_peak(H, PDBFS_ROLE_FORCE, 0, H->n, &t, &out[S_FORCE], NULL);
        if (out[S_FORCE] > 0) out[S_RESTITUTION] = restitution(H, x_pk, ended, &oom, m);
        if (horizon && out[S_FORCE] > 0 && t >= t_end * (1 - 1e-9)) out[S_FORCE] = NAN;
    }                                                /* no contact: restitution undefined */
    if (oom & 1) {
        pdbfs_note(m, "out of memory");
        return RC_NO_MEMORY;
    }
    return 0;
}

/*
 * A pulse cut off at t_end whose highest pressure lies inside the run: is it
 * its peak?  The run of an explicit method (rk at t_end, the point's roles
 * in out) is followed past t_end as summary_run.py follows it: on its grid
 * of PDBFS_SUMMARY_STEP, in windows of PDBFS_FOLLOW_WINDOW samples, until a
 * window ends outside the pulse (the pressure under 1 % of the highest
 * pressure yet, no contact) or at its limit.  Where the pressure rises
 * higher there, the point has no peak (NaN, and a note), as Result.summary()
 * says.  0, or the integration's failure (the point is then summary.py's).
 */
static int follow(History *H, PdbfsErk *rk, PdbfsEval *ev, double t_end, double *out,
                  long max_steps, double *x, Note *m) {
    const double h = PDBFS_SUMMARY_STEP;
    const double limit = t_end + fmin(PDBFS_FOLLOW_HORIZONS * t_end,
                                      PDBFS_FOLLOW_WINDOWS * PDBFS_FOLLOW_WINDOW * h);
    double r[NRX], base, highest = out[S_PEAK], after = -INFINITY, t_last = t_end;
    int busy = 1;
    if (PDBFS_ROLE_PRESSURE < 0) return 0;           /* no pulse to follow */
    base = R(H, 0, PDBFS_ROLE_PRESSURE);
    rk->t_stop = limit;
    rk->dense_ready = 0;     /* its dense output may be a refinement's (pdbfs_step_dense) */
    while (busy && t_last < limit) {
        const long k = (long)floor(t_last / h + 1e-6) + 1;
        long j;
        for (j = 0; j < PDBFS_FOLLOW_WINDOW; j++) {
            int code;
            t_last = h * (double)(k + j);
            if (t_last >= limit - 1e-6 * h) t_last = limit;
            code = pdbfs_erk_advance(rk, t_last, max_steps, x);
            if (code) return code;
            if (PDBFS_NL > 0) {   /* past a variable's declared range: nothing to tell from here */
                double g[NLX];
                int i;
                pdbfs_eval_txp(ev, pdbfs_limits, t_last, x, g);
                for (i = 0; i < PDBFS_NL; i++)
                    if (g[i] < 0) return RC_LIMIT;
            }
            pdbfs_eval_txp(ev, pdbfs_roles, t_last, x, r);
            if (!isfinite(r[PDBFS_ROLE_PRESSURE])) return RC_NOT_FINITE;
            after = fmax(after, r[PDBFS_ROLE_PRESSURE]);
            if (t_last == limit) break;
        }
        highest = fmax(highest, after);
        busy = r[PDBFS_ROLE_PRESSURE] >= base + PULSE_LEVEL * (highest - base);
        if (PDBFS_ROLE_FORCE >= 0) busy = busy || r[PDBFS_ROLE_FORCE] > 0;
    }
    if (after > out[S_PEAK]) {
        pdbfs_note(m, "its highest pressure so far, %.4g Pa, is not its peak: it rises to %.4g Pa "
                   "after t_end", out[S_PEAK], after);
        out[S_PEAK] = out[S_TPEAK] = NAN;
    }
    return 0;
}

static double seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

API int pdbfs_summary_nsum(void) { return NSUM; }
API int pdbfs_summary_nstat(void) { return NSTAT; }

/*
 * Summaries of n parameter points (P: n x np, row major) over [0, t_end],
 * each from the rig's own start values x0(p).  out: n x NSUM (NaN where an
 * entry is undefined or the rig has no such role); codes: 0 or the point's
 * failure (as pdbfs_batch_run's, or RC_BAD_CROSSINGS); msgs: n x msglen, the
 * reason of a failure or the warnings of a point that did not fail (a pulse
 * cut off at t_end); stats: n x NSTAT (may be NULL).  Returns the number of
 * points that failed, -1 for bad arguments.
 */
API long long pdbfs_summary_batch(long long n, long long np, const double *P, double t_end,
                                  double rtol, double atol, int method, double max_step,
                                  long long max_num_steps, double *out, int *codes, char *msgs,
                                  long long msglen, double *stats) {
    long long i, failed = 0;
    PdbfsEval ev;
    History H;
    PdbfsCvode s;
    PdbfsErk rk;
    PdbfsCvodeSettings set, refine;
    void *work;
    const int erk = method == PDBFS_ERK;   /* explicit RK; the refinements stay CVODE's (Adams) */
    double *atolv, *x0, *xe, *x_pk;
    if (np != PDBFS_NP || n < 0 || !(t_end > 0) || !(PDBFS_CODE_VALID(method) || erk)) return -1;
    work = pdbfs_eval_alloc(&ev, PDBFS_SZ_ARG, PDBFS_SZ_RES, PDBFS_SZ_IW, PDBFS_SZ_W);
    atolv = malloc(sizeof(double) * NXQ * 5);
    memset(&H, 0, sizeof H);
    memset(&rk, 0, sizeof rk);
    if (!work || !atolv || (erk && pdbfs_erk_init(&rk, NXQ, PDBFS_NE, &ev))) {
        free(work);
        free(atolv);
        pdbfs_erk_free(&rk);
        return -1;
    }
    rk.ode = pdbfs_ode_q;
    rk.nq = NQ;          /* the impulse: a quadrature */
    rk.substeps = 1;     /* peaks and crossings on the dense output of each step (record.c) */
    rk.lazy = 1;         /* made only for the steps that need it: near a root, or refined */
    x0 = atolv + NXQ;
    xe = x0 + NXQ;
    x_pk = xe + NXQ;
    H.ev = &ev;
    H.cv = &s;
    H.set = erk ? &refine : &set;
    H.rk = erk ? &rk : NULL;    /* refinements on its dense output */
    pdbfs_record_adopt(&H);     /* the memory of the record a run before released */
    for (i = 0; i < NXQ; i++) atolv[i] = i < PDBFS_NX ? atol : 1e300;   /* impulses: no error test */
    pdbfs_summary_settings(&set, method, erk, rtol, atolv, max_step, t_end);
    /* after an 8th-order pass, the refinements' CVODE (Adams, a cold start
     * inside a long step) would be the larger error: tighter by 100 */
    refine = set;
    refine.rtol = 0.01 * rtol;
    refine.atol = x_pk + NXQ;
    for (i = 0; i < NXQ; i++) x_pk[NXQ + i] = 0.01 * atolv[i];
    pdbfs_cvode_init(&s, NXQ, PDBFS_NE, &ev, NULL, NULL);
    s.nte = PDBFS_NTE;   /* CVODE stops at each switch time */
    s.ode = pdbfs_ode_q;
    s.jac = pdbfs_jac_q;
    s.jac_sp = pdbfs_jac_q_sparsity_out(0);
    for (i = 0; i < n; i++) {
        Note m;
        int k, code = 0;
        double t0 = seconds();
        m.text = msgs && msglen > 0 ? msgs + i * msglen : NULL;
        m.len = m.text ? (size_t)msglen : 0;
        if (m.text) m.text[0] = 0;
        s.steps = s.roots = s.rhs_evals = s.jac_evals = 0;
        rk.steps = rk.roots = rk.rhs_evals = 0;
        ev.p = P + i * np;
        for (k = 0; k < NSUM; k++) out[i * NSUM + k] = NAN;
        ev.arg[0] = ev.p;
        ev.res[0] = x0;
        pdbfs_start(ev.arg, ev.res, ev.iw, ev.w, 0);
        for (k = PDBFS_NX; k < NXQ; k++) x0[k] = 0.0;
        for (k = 0; k < PDBFS_NX; k++)
            if (!isfinite(x0[k])) code = 1;
        for (k = 0; k < PDBFS_NP; k++)
            if (!isfinite(ev.p[k])) code = 1;
        if (code) {
            pdbfs_note(&m, "parameters or start values are not finite");
        } else {
            H.n = 0;
            H.oom = H.bad = H.limit = 0;
            s.on_step = NULL;
            rk.on_step = NULL;
            code = erk ? (pdbfs_erk_start(&rk, &set, 0.0, x0) ? RC_NOT_FINITE : 0)
                       : pdbfs_cvode_start(&s, &set, 0.0, x0);
            if (!code) pdbfs_record_step(&H, 0.0, x0);
            s.on_step = rk.on_step = pdbfs_record_step;
            s.step_env = rk.step_env = &H;
            if (!code && erk) {
                code = pdbfs_erk_advance(&rk, t_end, (long)max_num_steps, xe);
                if (code == -3) code = RC_NOT_FINITE;
                if (code == PDBFS_ERK_STEP_UNDERFLOW) code = -3;   /* as CVODE's error failure */
                s.tn = rk.t;
            } else if (!code) {
                code = pdbfs_cvode_advance(&s, t_end, t_end, (long)max_num_steps, xe);
            }
            s.on_step = rk.on_step = NULL;
            if (code && pdbfs_limit_message(&H, code, m.text, m.len) == RC_LIMIT)
                code = RC_LIMIT;         /* a variable out of its range: the message says which */
            else if (code)
                pdbfs_note(&m, "%s at t = %.6g s", H.oom ? "out of memory"
                     : H.bad ? "the solution became NaN or infinite"
                     : code == PDBFS_CV_TOO_MUCH_WORK ? "too many steps"
                     : erk ? "the explicit Runge-Kutta step failed" : "CVODE failed", s.tn);
            if (code && H.bad) code = RC_NOT_FINITE;
            if (!code) code = pdbfs_summarise(&H, out + i * NSUM, x_pk, &m);
            /* a pulse cut off with its highest pressure inside: its peak or not */
            if (!code && erk && PDBFS_ROLE_PRESSURE >= 0 && out[i * NSUM + S_COMPLETE] == 0.0
                && isfinite(out[i * NSUM + S_PEAK])
                && follow(&H, &rk, &ev, t_end, out + i * NSUM, (long)max_num_steps, xe, &m))
                code = RC_FOLLOW;
        }
        if (code)   /* a failed point has no values */
            for (k = 0; k < NSUM; k++) out[i * NSUM + k] = NAN;
        codes[i] = code;
        if (code) failed++;
        if (stats) {
            double *st = stats + i * NSTAT;
            st[ST_STEPS] = (double)(s.steps + rk.steps);
            st[ST_RHS] = (double)(s.rhs_evals + rk.rhs_evals);
            st[ST_JAC] = (double)s.jac_evals;
            st[ST_ROOTS] = (double)(s.roots + rk.roots);
            st[ST_METHOD] = erk ? (double)PDBFS_ERK : (double)(s.method | s.nls << 4 | s.linsol << 8);
            st[ST_WALL] = seconds() - t0;
        }
    }
    pdbfs_cvode_free(&s);
    pdbfs_erk_free(&rk);
    pdbfs_record_release(&H);
    free(atolv);
    free(work);
    return failed;
}

/*
 * pdbfs summary driver: many parameter points in one call, each integrated
 * with CVODE (native/c/pdbfs_cvode.c) and reduced to its summary, for
 * sweeps at the speed of compiled CVODE (pdbfs.simulation.compiled).
 *
 * The same for every rig: the generated pdbfs_batch_model.h says which
 * outputs play which summary role (pressure, contact force, piston
 * displacement, striker velocity; -1 where the rig has none), and
 * CasADi-generated functions give those outputs (pdbfs_roles), their time
 * derivatives (pdbfs_roles_dot) and the ODE with the contact force's
 * integral as an extra state (pdbfs_ode_q, pdbfs_jac_q): impulses come out
 * of the integration itself.
 *
 * One pass records the state and the roles after every internal step (the
 * rig's events are CVODE roots and restarts, so no step straddles a kink).
 * Then the few steps that matter are integrated again from their recorded
 * start with CVODE's root finding on the quantity in question: the slope of
 * a role where its largest record lies (the peak), the pressure minus 1 % of
 * the peak where it crosses that level, the striker velocity where it turns.
 * These are the definitions of pdbfs/simulation/summary.py, located on the
 * solution to the solver's accuracy, not on an output grid.
 *
 * Thread safe: each call allocates its own memory; ctypes releases the GIL,
 * so threads run calls in parallel.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_batch_model.h"
#include "pdbfs_cvode.h"

#define API __attribute__((visibility("default")))
#define NR PDBFS_NR
#define NRX (NR > 0 ? NR : 1)
#define NQ (PDBFS_ROLE_FORCE >= 0 ? 1 : 0)   /* the contact force's integral */
#define NXQ (PDBFS_NX + NQ)
#define MAXR 8                                /* roots taken from one refined step */

/* the summary's entries, in this order (pdbfs.simulation.compiled.SUMMARY_KEYS) */
enum { S_PEAK, S_TPEAK, S_DURATION, S_FORCE, S_DISP, S_RESTITUTION, NSUM };
#define PULSE_LEVEL 0.01

typedef struct {
    double *t, *x, *r;        /* per record: time, state (NXQ), roles (NR) */
    long n, cap;
    int oom, bad;             /* out of memory; a role not finite */
    PdbfsEval *ev;
    PdbfsCvode *cv;           /* for the refinements */
    const PdbfsCvodeSettings *set;
} History;

#define R(H, k, j) ((H)->r[(k) * NRX + (j)])

static int record(void *env, double t, const double *x) {
    History *h = (History *)env;
    int j;
    if (h->n == h->cap) {
        long cap = h->cap ? 2 * h->cap : 2048;
        double *nt = realloc(h->t, sizeof(double) * cap), *nx = NULL, *nr = NULL;
        if (nt) h->t = nt;
        if (nt) nx = realloc(h->x, sizeof(double) * cap * NXQ);
        if (nx) h->x = nx;
        if (nx) nr = realloc(h->r, sizeof(double) * cap * NRX);
        if (nr) h->r = nr;
        if (!nr) {
            h->oom = 1;
            return 1;
        }
        h->cap = cap;
    }
    h->t[h->n] = t;
    memcpy(h->x + h->n * NXQ, x, sizeof(double) * NXQ);
    if (NR > 0) pdbfs_eval_txp(h->ev, pdbfs_roles, t, x, h->r + h->n * NRX);
    for (j = 0; j < NR; j++)
        if (!isfinite(R(h, h->n, j))) h->bad = 1;
    h->n++;
    return h->bad;
}

/* ------------------------------------------------------------ refinement */

typedef struct {
    PdbfsEval *ev;
    int role, slope;          /* the role, and whether its slope (else value - level) */
    double level;
} Target;

static int target_fn(void *env, double t, const double *x, double *g) {
    Target *q = (Target *)env;
    double r[NRX];
    pdbfs_eval_txp(q->ev, q->slope ? pdbfs_roles_dot : pdbfs_roles, t, x, r);
    *g = r[q->role] - (q->slope ? 0.0 : q->level);
    return 0;
}

/* roots of the target on record steps k0 .. k1-1, integrated again from record k0 */
static int refine(const History *H, long k0, long k1, Target *q, int dir, double *t, double *x) {
    int n;
    if (k0 < 0) k0 = 0;
    if (k1 > H->n - 1) k1 = H->n - 1;
    if (k1 <= k0 || !(H->t[k1] > H->t[k0])) return 0;
    n = pdbfs_cvode_roots(H->cv, H->set, H->t[k0], H->x + k0 * NXQ, H->t[k1], target_fn, q, dir,
                          MAXR, t, x);
    return n > 0 ? n : 0;
}

static double role_at(const History *H, int j, double t, const double *x) {
    double r[NRX];
    pdbfs_eval_txp(H->ev, pdbfs_roles, t, x, r);
    return r[j];
}

/* the largest value of role j over records k0 .. k1-1, refined where its slope turns */
static void peak(const History *H, int j, long k0, long k1, double *t_pk, double *v_pk, double *x_pk) {
    long k, best = k0;
    double t[MAXR], x[MAXR * NXQ];
    Target q;
    int i, n;
    for (k = k0; k < k1; k++)
        if (R(H, k, j) > R(H, best, j)) best = k;
    *t_pk = H->t[best];
    *v_pk = R(H, best, j);
    if (x_pk) memcpy(x_pk, H->x + best * NXQ, sizeof(double) * NXQ);
    q.ev = H->ev;
    q.role = j;
    q.slope = 1;
    q.level = 0.0;
    n = refine(H, best > k0 ? best - 1 : k0, best + 1 < k1 ? best + 1 : k1 - 1, &q, -1, t, x);
    for (i = 0; i < n; i++) {
        double v = role_at(H, j, t[i], x + i * NXQ);
        if (v > *v_pk) {
            *v_pk = v;
            *t_pk = t[i];
            if (x_pk) memcpy(x_pk, x + i * NXQ, sizeof(double) * NXQ);
        }
    }
}

/* crossings of role j through level (dir as for CVODE roots), at most max: times and states */
static int crossings(const History *H, int j, double level, int dir, int max, double *tc, double *xc) {
    long k;
    int n = 0;
    Target q;
    q.ev = H->ev;
    q.role = j;
    q.slope = 0;
    q.level = level;
    for (k = 0; k + 1 < H->n && n < max; k++) {
        double a = R(H, k, j) - level, b = R(H, k + 1, j) - level;
        double t[MAXR], x[MAXR * NXQ];
        int i, m;
        if (!((a < 0 && b >= 0) || (a > 0 && b <= 0))) continue;
        m = refine(H, k, k + 1, &q, dir, t, x);
        for (i = 0; i < m && n < max; i++, n++) {
            tc[n] = t[i];
            if (xc) memcpy(xc + n * NXQ, x + i * NXQ, sizeof(double) * NXQ);
        }
    }
    return n;
}

/* -------------------------------------------------------------- summary */

#define MAXC 64

static void summarise(const History *H, double *out) {
    int i;
    long last = H->n - 1;
    double t_end = H->t[last];
    for (i = 0; i < NSUM; i++) out[i] = NAN;
    if (PDBFS_ROLE_PRESSURE >= 0) {
        const int j = PDBFS_ROLE_PRESSURE;
        double level, times[MAXC + 2], sum = 0.0;
        int n = 0;
        peak(H, j, 0, H->n, &out[S_TPEAK], &out[S_PEAK], NULL);
        level = PULSE_LEVEL * out[S_PEAK];
        if (R(H, 0, j) > level) times[n++] = H->t[0];
        n += crossings(H, j, level, 0, MAXC, times + n, NULL);
        if (R(H, last, j) > level) times[n++] = t_end;
        for (i = 0; i + 1 < n; i += 2) sum += times[i + 1] - times[i];
        out[S_DURATION] = sum;
    }
    if (PDBFS_ROLE_DISP >= 0) {
        double t;
        peak(H, PDBFS_ROLE_DISP, 0, H->n, &t, &out[S_DISP], NULL);
    }
#if PDBFS_ROLE_FORCE >= 0
    {
        const int f = PDBFS_ROLE_FORCE, iq = PDBFS_NX;   /* the impulse state */
        double t_pk, f_pk, before = 0.0, after = 0.0, x_pk[NXQ];
        peak(H, f, 0, H->n, &t_pk, &out[S_FORCE], NULL);
        if (!(out[S_FORCE] > 0)) return;                 /* no contact: restitution undefined */
        if (PDBFS_ROLE_VELOCITY >= 0) {
            /* Guo & Batzer over the blow, split where the striker stops (its velocity
             * turns from down to up), up to the apex of its rebound (or the end) */
            double tc[MAXC], xc[MAXC * NXQ], q_back;
            int n = crossings(H, PDBFS_ROLE_VELOCITY, 0.0, 0, MAXC, tc, xc), k = -1;
            for (i = 0; i < n && k < 0; i++) {
                double r[NRX];
                pdbfs_eval_txp(H->ev, pdbfs_roles_dot, tc[i], xc + i * NXQ, r);
                if (r[PDBFS_ROLE_VELOCITY] < 0) k = i;
            }
            if (k < 0) return;
            q_back = k + 1 < n ? xc[(k + 1) * NXQ + iq] : H->x[last * NXQ + iq];
            before = xc[k * NXQ + iq];
            after = q_back - before;
        } else {
            /* the first contact, split at its force peak */
            long k = 0, e;
            while (k < H->n && !(R(H, k, f) > 0)) k++;
            for (e = k; e < H->n && R(H, e, f) > 0; e++) {}
            if (e > last) e = last;
            peak(H, f, k > 0 ? k - 1 : 0, e + 1, &t_pk, &f_pk, x_pk);
            before = x_pk[iq];
            after = H->x[e * NXQ + iq] - before;
        }
        out[S_RESTITUTION] = before > 0 ? after / before : NAN;
    }
#endif
}

API int pdbfs_summary_nsum(void) { return NSUM; }

/*
 * Summaries of n parameter points (P: n x np, row major) over [0, t_end],
 * each from the rig's own start values x0(p).  out: n x NSUM (NaN where an
 * entry is undefined or the rig has no such role); codes: 0 or the point's
 * failure (as pdbfs_batch_run's); msgs: n x msglen.  Returns the number of
 * points that failed, -1 for bad arguments.
 */
API long long pdbfs_summary_batch(long long n, long long np, const double *P, double t_end,
                                  double rtol, double atol, int method, double max_step,
                                  long long max_num_steps, double *out, int *codes, char *msgs,
                                  long long msglen) {
    long long i, failed = 0;
    char *work = malloc(sizeof(double) * (PDBFS_SZ_W + 1) + sizeof(casadi_int) * (PDBFS_SZ_IW + 1)
                        + sizeof(void *) * (PDBFS_SZ_ARG + PDBFS_SZ_RES + 2));
    PdbfsEval ev;
    History H;
    PdbfsCvode s;
    PdbfsCvodeSettings set;
    double atolv[NXQ], x0[NXQ], xe[NXQ];
    char *b = work;
    if (!work || np != PDBFS_NP || n < 0 || !(t_end > 0) || !PDBFS_CODE_VALID(method)) {
        free(work);
        return -1;
    }
    ev.w = (casadi_real *)b;
    b += sizeof(double) * (PDBFS_SZ_W + 1);
    ev.arg = (const casadi_real **)b;
    b += sizeof(void *) * (PDBFS_SZ_ARG + 1);
    ev.res = (casadi_real **)b;
    b += sizeof(void *) * (PDBFS_SZ_RES + 1);
    ev.iw = (casadi_int *)b;
    memset(&H, 0, sizeof H);
    H.ev = &ev;
    H.cv = &s;
    H.set = &set;
    for (i = 0; i < NXQ; i++) atolv[i] = i < PDBFS_NX ? atol : 1e300;   /* impulses: no error test */
    memset(&set, 0, sizeof set);
    set.method = PDBFS_CODE_METHOD(method);
    set.nls = PDBFS_CODE_NLS(method);
    set.linsol = PDBFS_CODE_LINSOL(method);
    set.rtol = rtol;
    set.atol = atolv;
    set.max_step = max_step;
    set.t_stop = t_end;
    pdbfs_cvode_init(&s, NXQ, PDBFS_NE, &ev, NULL, NULL);
    s.ode = pdbfs_ode_q;
    s.jac = pdbfs_jac_q;
    s.jac_sp = pdbfs_jac_q_sparsity_out(0);
    for (i = 0; i < n; i++) {
        char *msg = msgs && msglen > 0 ? msgs + i * msglen : NULL;
        int k, code = 0;
        if (msg) msg[0] = 0;
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
            if (msg) snprintf(msg, (size_t)msglen, "parameters or start values are not finite");
        } else {
            H.n = 0;
            H.oom = H.bad = 0;
            s.on_step = NULL;
            code = pdbfs_cvode_start(&s, &set, 0.0, x0);
            if (!code) record(&H, 0.0, x0);
            s.on_step = record;
            s.step_env = &H;
            if (!code) code = pdbfs_cvode_advance(&s, t_end, t_end, (long)max_num_steps, xe);
            s.on_step = NULL;
            if (code && msg)
                snprintf(msg, (size_t)msglen, "%s at t = %.6g s", H.oom ? "out of memory"
                         : H.bad ? "the solution became NaN or infinite"
                         : code == PDBFS_CV_TOO_MUCH_WORK ? "too many steps" : "CVODE failed", s.tn);
            if (code && H.bad) code = 4;   /* RC_NOT_FINITE of pdbfs_batch.c */
            if (!code) summarise(&H, out + i * NSUM);
        }
        codes[i] = code;
        if (code) failed++;
    }
    pdbfs_cvode_free(&s);
    free(H.t);
    free(H.x);
    free(H.r);
    free(work);
    return failed;
}

/* pdbfs_record: see pdbfs_record.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_record.h"

#define API __attribute__((visibility("default")))

static pdbfs_probe_fn memory_probe = NULL;

API void pdbfs_set_memory_probe(pdbfs_probe_fn probe) { memory_probe = probe; }

/* whether a record of cap entries (with a Runge-Kutta run's dense output, rk)
 * fits in what the memory probe says is left */
static int record_fits(long cap, int rk) {
    const double size = 8.0 * (double)cap * (1 + NXQ + NRX + (rk ? DNREC + NRX : 0));
    double have;
    if (!memory_probe || size <= RECORD_ASK) return 1;
    have = memory_probe();
    return have < 0 || size <= RECORD_SHARE * have;
}

int pdbfs_record_step(void *env, double t, const double *x) {
    History *h = (History *)env;
    int j, roles_done = 0;
    if (h->n == h->cap) {
        long cap = h->cap ? 2 * h->cap : 256;
        double *nt, *nx = NULL, *nr = NULL;
        if (!record_fits(cap, h->rk != NULL)) {
            h->oom = 1;
            return 1;
        }
        nt = realloc(h->t, sizeof(double) * cap);
        if (nt) h->t = nt;
        if (nt) nx = realloc(h->x, sizeof(double) * cap * NXQ);
        if (nx) h->x = nx;
        if (nx) nr = realloc(h->r, sizeof(double) * cap * NRX);
        if (nr) h->r = nr;
        if (nr && h->rk) {
            double *nd = realloc(h->dn, sizeof(double) * cap * DNREC), *ns = NULL;
            if (nd) h->dn = nd;
            if (nd) ns = realloc(h->rdot, sizeof(double) * cap * NRX);
            if (ns) h->rdot = ns;
            else nr = NULL;
        }
        if (!nr) {
            h->oom = 1;
            return 1;
        }
        h->cap = cap;
    }
    h->t[h->n] = t;
    memcpy(h->x + h->n * NXQ, x, sizeof(double) * NXQ);
    if (h->rk) {               /* the step this record lies in (none for the first) */
        double *d = h->dn + h->n * DNREC;
        const PdbfsErk *rk = h->rk;
        int none = h->n == 0 || rk->fresh || (!rk->dense_ready && !rk->lazy);
        if (NR > 0 && x == rk->y) {
            /* the roles and their rates in one call, from the explicit method's
             * derivative at its own point (its next step's first stage, at hand:
             * no evaluation of the right-hand side) */
            double both[2 * NRX];
            pdbfs_eval_txvp(h->ev, pdbfs_roles_both, t, x, rk->f, both);
            memcpy(h->r + h->n * NRX, both, sizeof(double) * NR);
            memcpy(h->rdot + h->n * NRX, both + NR, sizeof(double) * NR);
            roles_done = 1;
        } else if (NR > 0) {                 /* the rates from the right-hand side */
            pdbfs_eval_txp(h->ev, pdbfs_roles_dot, t, x, h->rdot + h->n * NRX);
        }
        d[0] = none ? t : rk->t_old;
        d[1] = none ? 0.0 : rk->h_old;
        d[2] = none ? DN_NONE : rk->dense_ready ? DN_ROWS : DN_STAGES;
        if (!none) {
            memcpy(d + 3, rk->y_old, sizeof(double) * NXQ);
            if (rk->dense_ready) memcpy(d + 3 + NXQ, rk->dense, sizeof(double) * 7 * NXQ);
            else memcpy(d + 3 + NXQ, rk->k, sizeof(double) * 13 * NXQ);   /* made if needed */
        }
    }
    if (NR > 0 && !roles_done) pdbfs_eval_txp(h->ev, pdbfs_roles, t, x, h->r + h->n * NRX);
    for (j = 0; j < NR; j++)
        if (!isfinite(R(h, h->n, j))) h->bad = 1;
    if (PDBFS_NL > 0 && !h->bad && !h->limit) {   /* a variable out of its declared range: the run stops */
        double g[NLX];
        pdbfs_eval_txp(h->ev, pdbfs_limits, t, x, g);
        for (j = 0; j < PDBFS_NL && !h->limit; j++)
            if (g[j] < 0) {
                h->limit = j + 1;
                h->limit_k = h->n;
            }
    }
    h->n++;
    return h->bad || h->limit;
}

static int add_crossing(Crossings *c, double t, int dir, const double *x) {
    if (c->n == c->cap) {
        long cap = c->cap ? 2 * c->cap : 16;
        double *nt = realloc(c->t, sizeof(double) * cap), *nx = NULL;
        int *nd = NULL;
        if (nt) c->t = nt;
        if (nt) nx = realloc(c->x, sizeof(double) * cap * NXQ);
        if (nx) c->x = nx;
        if (nx) nd = realloc(c->dir, sizeof(int) * cap);
        if (nd) c->dir = nd;
        if (!nd) return -1;
        c->cap = cap;
    }
    c->t[c->n] = t;
    c->dir[c->n] = dir;
    memcpy(c->x + c->n * NXQ, x, sizeof(double) * NXQ);
    c->n++;
    return 0;
}

void pdbfs_free_crossings(Crossings *c) {
    free(c->t);
    free(c->x);
    free(c->dir);
    memset(c, 0, sizeof *c);
}

void pdbfs_summary_settings(PdbfsCvodeSettings *set, int method, int erk, double rtol,
                            double *atolv, double max_step, double t_stop) {
    memset(set, 0, sizeof *set);
    set->method = erk ? PDBFS_ADAMS : PDBFS_CODE_METHOD(method);
    set->nls = erk ? 0 : PDBFS_CODE_NLS(method);
    set->linsol = erk ? 0 : PDBFS_CODE_LINSOL(method);
    set->rtol = rtol;
    set->atol = atolv;
    set->max_step = max_step;
    set->t_stop = t_stop;
}

void pdbfs_free_history(History *H) {
    free(H->t);
    free(H->x);
    free(H->r);
    free(H->rt);
    free(H->rx);
    free(H->rd);
    free(H->dn);
    free(H->rdot);
    H->t = H->x = H->r = H->rt = H->rx = H->dn = H->rdot = NULL;
    H->rd = NULL;
}

/* ------------------------------------------------------------ refinement */

typedef struct {
    PdbfsEval *ev;
    int role, slope;          /* the role, and whether its slope (else value - level) */
    double level;
    int limit;                /* 1 + a limit: its value (role, slope and level unused) */
} Target;

static int target_fn(void *env, double t, const double *x, double *g) {
    Target *q = (Target *)env;
    double r[NRX > NLX ? NRX : NLX];
    if (q->limit) {          /* (only where the rig has limits) */
        pdbfs_eval_txp(q->ev, pdbfs_limits, t, x, r);
        *g = r[q->limit - 1];
        return 0;
    }
    pdbfs_eval_txp(q->ev, q->slope ? pdbfs_roles_dot : pdbfs_roles, t, x, r);
    *g = r[q->role] - (q->slope ? 0.0 : q->level);
    return 0;
}

static int grow_roots(History *H, int cap) {
    double *t = realloc(H->rt, sizeof(double) * cap), *x = NULL;
    int *d = NULL;
    if (t) H->rt = t;
    if (t) x = realloc(H->rx, sizeof(double) * cap * NXQ);
    if (x) H->rx = x;
    if (x) d = realloc(H->rd, sizeof(int) * cap);
    if (d) H->rd = d;
    if (!d) return -1;
    H->rcap = cap;
    return 0;
}

const double *pdbfs_step_dense(History *H, long k) {
    double *d = H->dn + k * DNREC;
    if (d[2] == DN_STAGES) {
        if (pdbfs_erk_rows(H->rk, d[0], d[1], d + 3, H->x + k * NXQ, d + 3 + NXQ, d + 3 + NXQ))
            return NULL;
        d[2] = DN_ROWS;
    }
    return d;
}

/* refine() on an explicit Runge-Kutta run's record: a sign change of the
 * target between two records is located on the dense output of the step
 * that holds them (Illinois, to a few roundoffs); nothing is integrated */
static int refine_dense(History *H, long k0, long k1, Target *q, int dir) {
    int n = 0, it;
    long k;
    double *xs = H->rx;        /* scratch: a root's state is written there anyway */
    for (k = k0; k < k1; k++) {
        const double *d;
        double ta = H->t[k], tb = H->t[k + 1], fa, fb, g;
        int up, side = 0;
        target_fn(q, ta, H->x + k * NXQ, &fa);
        target_fn(q, tb, H->x + (k + 1) * NXQ, &fb);
        up = fa < 0 && fb >= 0;
        if (!up && !(fa > 0 && fb <= 0)) continue;
        if ((dir > 0 && !up) || (dir < 0 && up)) continue;
        d = pdbfs_step_dense(H, k + 1);
        if (!d) return -1;
        if (!(d[1] > 0)) continue;                         /* no step: cannot happen */
        if (n == H->rcap && grow_roots(H, H->rcap ? 2 * H->rcap : MAXR)) return -1;
        xs = H->rx + n * NXQ;
        for (it = 0; it < 100 && tb - ta > 4e-16 * fabs(tb) + 1e-300; it++) {
            double tc = fa != fb ? tb - fb * (tb - ta) / (fb - fa) : 0.5 * (ta + tb);
            if (!(tc > ta && tc < tb)) tc = 0.5 * (ta + tb);
            pdbfs_erk_poly(d + 3, d + 3 + NXQ, NXQ, (tc - d[0]) / d[1], xs);
            target_fn(q, tc, xs, &g);
            if (up ? g >= 0 : g <= 0) {
                tb = tc;
                fb = g;
                if (side == 1) fa *= 0.5;
                side = 1;
            } else {
                ta = tc;
                fa = g;
                if (side == -1) fb *= 0.5;
                side = -1;
            }
        }
        H->rt[n] = tb;
        pdbfs_erk_poly(d + 3, d + 3 + NXQ, NXQ, (tb - d[0]) / d[1], H->rx + n * NXQ);
        H->rd[n] = up ? 1 : -1;
        n++;
    }
    return n;
}

/* every root of the target on record steps k0 .. k1-1, integrated again from
 * record k0 (again with more room while the room fills): times, states and
 * directions in H->rt, rx, rd; their number, or -1 when out of memory */
static int refine(History *H, long k0, long k1, Target *q, int dir) {
    int n;
    if (k0 < 0) k0 = 0;
    if (k1 > H->n - 1) k1 = H->n - 1;
    if (k1 <= k0 || !(H->t[k1] > H->t[k0])) return 0;
    if (H->rk) return refine_dense(H, k0, k1, q, dir);
    for (;;) {
        if (H->rcap == 0 && grow_roots(H, MAXR)) return -1;
        n = pdbfs_cvode_roots(H->cv, H->set, H->t[k0], H->x + k0 * NXQ, H->t[k1], target_fn, q,
                              dir, H->rcap, H->rt, H->rx, H->rd);
        if (n < H->rcap) return n > 0 ? n : 0;
        if (grow_roots(H, 2 * H->rcap)) return -1;
    }
}

static double role_at(const History *H, int j, double t, const double *x) {
    double r[NRX];
    pdbfs_eval_txp(H->ev, pdbfs_roles, t, x, r);
    return r[j];
}

/* the largest value of role j over records k0 .. k1-1, refined where its slope
 * turns; its time, value and (x_pk not NULL) state */
int pdbfs_peak(History *H, int j, long k0, long k1, double *t_pk, double *v_pk, double *x_pk) {
    long k, best = k0;
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
    q.limit = 0;
    if (H->rk) {
        /* long steps: a narrow spike may hold no record near it, so every turn
         * of the role (rate from + to -) is located on the dense output, but
         * for a turn that cannot reach the largest value found so far: its
         * step's larger end plus twice the step times the rate's fall across
         * it (the rate inside a step, resolved to the tolerance, does not rise
         * above its start by as much as it falls; the oscillations that
         * follow a pulse are turns far below its peak) */
        for (k = k0; k + 1 < k1; k++) {
            const double ra = H->rdot[k * NRX + j], rb = H->rdot[(k + 1) * NRX + j];
            if (!(ra > 0 && rb <= 0)) continue;
            if (fmax(R(H, k, j), R(H, k + 1, j)) + 2.0 * (H->t[k + 1] - H->t[k]) * (ra - rb)
                < *v_pk)
                continue;
            n = refine(H, k, k + 1, &q, -1);
            if (n < 0) return -1;
            for (i = 0; i < n; i++) {
                double v = role_at(H, j, H->rt[i], H->rx + i * NXQ);
                if (v > *v_pk) {
                    *v_pk = v;
                    *t_pk = H->rt[i];
                    if (x_pk) memcpy(x_pk, H->rx + i * NXQ, sizeof(double) * NXQ);
                }
            }
        }
        return 0;
    }
    n = refine(H, best > k0 ? best - 1 : k0, best + 1 < k1 ? best + 1 : k1 - 1, &q, -1);
    for (i = 0; i < n; i++) {
        double v = role_at(H, j, H->rt[i], H->rx + i * NXQ);
        if (v > *v_pk) {
            *v_pk = v;
            *t_pk = H->rt[i];
            if (x_pk) memcpy(x_pk, H->rx + i * NXQ, sizeof(double) * NXQ);
        }
    }
    return n < 0 ? -1 : 0;
}

/* every crossing of role j through level (both directions), in time order,
 * appended to c; -1 when out of memory, -2 when a step's crossings do not
 * lead from one side to the other */
int pdbfs_crossings(History *H, int j, double level, Crossings *c) {
    long k;
    Target q;
    q.ev = H->ev;
    q.role = j;
    q.slope = 0;
    q.level = level;
    q.limit = 0;
    for (k = 0; k + 1 < H->n; k++) {
        double a = R(H, k, j) - level, b = R(H, k + 1, j) - level;
        int i, m;
        if (!((a < 0 && b >= 0) || (a > 0 && b <= 0))) continue;
        m = refine(H, k, k + 1, &q, 0);
        if (m < 0) return -1;
        /* the step's crossings lead from a's side to b's: else the integration
         * again from record k does not see what the first did (a signal at
         * the size of the solver's error) */
        if (m % 2 == 0 || H->rd[0] != (a < 0 ? 1 : -1)) return -2;
        for (i = 0; i < m; i++)
            if (add_crossing(c, H->rt[i], H->rd[i], H->rx + i * NXQ)) return -1;
    }
    return 0;
}

int pdbfs_limit_message(History *H, int code, char *msg, size_t len) {
    long k = H->n - 1;
    if (PDBFS_NL == 0) return code;
    if (H->limit) {
        Target q;
        double t = H->t[H->limit_k];
        memset(&q, 0, sizeof q);
        q.ev = H->ev;
        q.limit = H->limit;
        if (H->limit_k > 0 && refine(H, H->limit_k - 1, H->limit_k, &q, -1) > 0)
            t = H->rt[0];        /* located on the step (else the record's time) */
        if (msg && len) snprintf(msg, len, "limit %d crossed at t = %.17g", H->limit - 1, t);
        return RC_LIMIT;
    }
    if (!code || H->oom || H->bad || k < 1) return code;
    if (pdbfs_limit_near(H->ev, H->t[0], H->x, H->t[k], H->x + k * NXQ, msg, len))
        return RC_LIMIT;
    return code;
}

int pdbfs_limit_near(PdbfsEval *ev, double t0, const double *x0, double t, const double *x,
                     char *msg, size_t len) {
    double g0[NLX], g[NLX];
    int j;
    if (PDBFS_NL == 0) return 0;
    pdbfs_eval_txp(ev, pdbfs_limits, t0, x0, g0);
    pdbfs_eval_txp(ev, pdbfs_limits, t, x, g);
    for (j = 0; j < PDBFS_NL; j++)
        if (g0[j] > 0 && g[j] < LIMIT_NEAR * g0[j]) {
            if (msg && len) snprintf(msg, len, "limit %d near at t = %.17g value %.17g", j, t, g[j]);
            return 1;
        }
    return 0;
}

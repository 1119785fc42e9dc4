/* Directional and adjoint derivatives of a pdbfs FMU, for every FMI version:
 * of the state derivatives and the outputs with respect to the states, the
 * inputs (the entries of their values in p) and the tunable parameters,
 * exact, from CasADi's forward (pdbfs_fwd: J v) and reverse (pdbfs_adj:
 * J^T w) AD of J = d[der(x); y] / d[x; p], one evaluation per call
 * (fmu/derivatives.py). A state as an unknown is its own identity.
 *
 * And the outputs' (and states') first and second time derivatives along
 * the solution at the current time (co-simulation's output derivatives),
 * from pdbfs_yder: d/dt = partial d/dt + d/dx der(x), the inputs' slopes in
 * the partial derivative, twice. */
#include <math.h>

#include "fmu_instance.h"

#define NQ (NX + NP)    /* the knowns' space: states, then p (parameters, inputs' entries) */
#define NF (NX + NYV)   /* the unknowns' space: derivatives, then exposed outputs */

/* a known's place in [x; p], or -1 (logged) */
static int known_slot(Inst *m, const char *fn, unsigned r) {
    if (r >= PDBFS_VR_X && r < PDBFS_VR_X + NX) return (int)(r - PDBFS_VR_X);
    if (r >= PDBFS_VR_U && r < PDBFS_VR_U + NU) return NX + PDBFS_P_U0 + (int)(r - PDBFS_VR_U);
    if (r - PDBFS_VR_P < (unsigned)NPAR) {   /* (unsigned: r < PDBFS_VR_P wraps past NPAR) */
        if (PDBFS_P_TUNABLE[r - PDBFS_VR_P]) return NX + (int)(r - PDBFS_VR_P);
        (void)ERR(m, "%s: parameter %s is fixed: derivatives are with respect to states and tunable parameters",
            fn, PDBFS_P_NAME[r - PDBFS_VR_P]);
        return -1;
    }
    (void)ERR(m, "%s: value reference %u is not a state, an input or a tunable parameter", fn, r);
    return -1;
}

/* an unknown's place in [der(x); y], NF + i for state i, or -1 (logged) */
static int unknown_slot(Inst *m, const char *fn, unsigned r) {
    if (r >= PDBFS_VR_DX && r < PDBFS_VR_DX + NX) return (int)(r - PDBFS_VR_DX);
    if (r >= PDBFS_VR_Y && r < PDBFS_VR_Y + NYV) return NX + (int)(r - PDBFS_VR_Y);
    if (r >= PDBFS_VR_X && r < PDBFS_VR_X + NX) return NF + (int)(r - PDBFS_VR_X);
    (void)ERR(m, "%s: value reference %u is not a state derivative, an output or a state", fn, r);
    return -1;
}

/* f(t, x, z, p[, seed]) at the current time and state into out */
static int eval(Inst *m, pdbfs_casadi_fn f, const double *seed, double *out) {
    double t = m->s.time;
    m->arg[0] = &t;
    m->arg[1] = model_x(m);
    m->arg[2] = NULL;
    m->arg[3] = m->s.p;
    m->arg[4] = seed;
    m->res[0] = out;
    return f(m->arg, m->res, m->iw, m->w, 0);
}

static int check(Inst *m, const char *fn, size_t nu, size_t nk, const void *a, const void *b, const void *c,
                 const void *d) {
    if (fmu_check(m, fn, ST_INIT | ST_RUNNING | ST_TERMINATED, -1) != FMU_OK) return FMU_ERROR;
    if ((nu > 0 && (!a || !d)) || (nk > 0 && (!b || !c))) return ERR(m, "%s: NULL argument", fn);
    return FMU_OK;
}

/* sens[i] = sum_j d unknown[i] / d known[j] * seed[j] */
int deriv_forward(Inst *m, const char *fn, const unsigned unknown[], size_t nu, const unsigned known[], size_t nk,
                  const double seed[], double sens[]) {
    double v[NQ + 1] = {0}, jv[NF + 1];
    size_t i;
    int k;
    if (check(m, fn, nu, nk, unknown, known, seed, sens) != FMU_OK) return FMU_ERROR;
    for (i = 0; i < nk; i++) {
        if ((k = known_slot(m, fn, known[i])) < 0) return FMU_ERROR;
        v[k] += seed[i];
    }
    for (i = 0; i < nu; i++)
        if (unknown_slot(m, fn, unknown[i]) < 0) return FMU_ERROR;
    if (eval(m, pdbfs_fwd, v, jv)) return ERR(m, "%s: evaluation failed", fn);
    for (i = 0; i < nu; i++) {
        k = unknown_slot(m, fn, unknown[i]);
        sens[i] = k < NF ? jv[k] : v[k - NF];
        if (!isfinite(sens[i])) return ERR(m, "%s: the derivative is not finite at t=%.17g", fn, m->s.time);
    }
    return FMU_OK;
}

/* sens[j] = sum_i seed[i] * d unknown[i] / d known[j] */
int deriv_adjoint(Inst *m, const char *fn, const unsigned unknown[], size_t nu, const unsigned known[], size_t nk,
                  const double seed[], double sens[]) {
    double w[NF + 1] = {0}, jtw[NQ + 1], x_seed[NX + 1] = {0};
    size_t i;
    int k;
    if (check(m, fn, nu, nk, unknown, known, seed, sens) != FMU_OK) return FMU_ERROR;
    for (i = 0; i < nu; i++) {
        if ((k = unknown_slot(m, fn, unknown[i])) < 0) return FMU_ERROR;
        if (k < NF) w[k] += seed[i];
        else x_seed[k - NF] += seed[i];
    }
    for (i = 0; i < nk; i++)
        if (known_slot(m, fn, known[i]) < 0) return FMU_ERROR;
    if (eval(m, pdbfs_adj, w, jtw)) return ERR(m, "%s: evaluation failed", fn);
    for (i = 0; i < nk; i++) {
        k = known_slot(m, fn, known[i]);
        sens[i] = jtw[k] + (k < NX ? x_seed[k] : 0.0);
        if (!isfinite(sens[i])) return ERR(m, "%s: the derivative is not finite at t=%.17g", fn, m->s.time);
    }
    return FMU_OK;
}

#define NQO (NX + PDBFS_NYO)   /* pdbfs_yder's rows of one order: states, then outputs */

/* v[i] = the order[i]-th time derivative (1 or 2) of the state or output vr[i] now */
int deriv_outputs(Inst *m, const char *fn, const unsigned vr[], size_t n, const int order[], double v[]) {
    double d[2 * NQO + 1];
    int row[64], *rows = row, st = FMU_OK;
    size_t i;
    if (fmu_check(m, fn, ST_STEPDONE | ST_TERMINATED | ST_INTERMEDIATE, FMU_CS) != FMU_OK) return FMU_ERROR;
    if (n == 0) return FMU_OK;
    if (!vr || !order || !v) return ERR(m, "%s: NULL argument", fn);
    if (n > sizeof row / sizeof row[0] && !(rows = (int *)m->host.alloc(n, sizeof(int))))
        return ERR(m, "%s: out of memory", fn);
    for (i = 0; i < n && st == FMU_OK; i++) {
        unsigned r = vr[i];
        if (r >= PDBFS_VR_X && r < PDBFS_VR_X + NX) rows[i] = (int)(r - PDBFS_VR_X);
        else if (r >= PDBFS_VR_Y && r < PDBFS_VR_Y + NYV && PDBFS_YO_ROW[r - PDBFS_VR_Y] >= 0)
            rows[i] = NX + PDBFS_YO_ROW[r - PDBFS_VR_Y];
        else st = ERR(m, "%s: value reference %u is not an output or a state", fn, r);
        if (st == FMU_OK && order[i] != 1 && order[i] != 2)
            st = ERR(m, "%s: order %d: the first and second derivatives are given "
                     "(maxOutputDerivativeOrder=2)", fn, order[i]);
    }
    if (st == FMU_OK && eval(m, pdbfs_yder, NULL, d)) st = ERR(m, "%s: evaluation failed", fn);
    for (i = 0; i < n && st == FMU_OK; i++) {
        v[i] = d[(order[i] - 1) * NQO + rows[i]];
        if (!isfinite(v[i]))
            st = ERR(m, "%s: derivative %d of %s is %g at t=%.17g (the solution is not smooth enough there)", fn,
                     order[i], rows[i] < NX ? PDBFS_X_NAME[rows[i]] : PDBFS_Y_NAME[vr[i] - PDBFS_VR_Y], v[i],
                     m->s.time);
    }
    if (rows != row) m->host.free(rows);
    return st;
}

/* pdbfs_cvode_none: pdbfs_cvode.h's functions for a compiled library built
 * without SUNDIALS (-DPDBFS_NO_CVODE), which runs the explicit method only.
 * The model interface (evaluation, work arrays, the PdbfsCvode the drivers
 * hand to the explicit method) works as in pdbfs_cvode.c; starting CVODE
 * fails with a message, never silently (Python builds the library with
 * CVODE before it asks for Adams or BDF: pdbfs/simulation/compiled.py). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_cvode.h"

#define NO_CVODE (-100)

int pdbfs_eval_txvp(PdbfsEval *ev, pdbfs_casadi_fn f, double t, const double *x, const double *v,
                    double *out) {
    double tt = t;
    ev->arg[0] = &tt;
    ev->arg[1] = x;
    ev->arg[2] = v;
    ev->arg[3] = ev->p;
    ev->res[0] = out;
    return f(ev->arg, ev->res, ev->iw, ev->w, 0);
}

void *pdbfs_eval_alloc(PdbfsEval *ev, long sz_arg, long sz_res, long sz_iw, long sz_w) {
    /* doubles first, then pointers, then integers: each part stays aligned */
    size_t nw = (size_t)sz_w + 1, na = (size_t)sz_arg + 1, nr = (size_t)sz_res + 1;
    char *b = malloc(sizeof(casadi_real) * nw + sizeof(void *) * (na + nr)
                     + sizeof(casadi_int) * ((size_t)sz_iw + 1));
    if (!b) return NULL;
    ev->w = (casadi_real *)b;
    ev->arg = (const casadi_real **)(b + sizeof(casadi_real) * nw);
    ev->res = (casadi_real **)(b + sizeof(casadi_real) * nw + sizeof(void *) * na);
    ev->iw = (casadi_int *)(b + sizeof(casadi_real) * nw + sizeof(void *) * (na + nr));
    return b;
}

void pdbfs_cvode_init(PdbfsCvode *s, int nx, int ne, PdbfsEval *ev, pdbfs_log_fn log, void *env) {
    memset(s, 0, sizeof *s);
    s->nx = nx;
    s->ne = ne;
    s->ev = ev;
    s->ode = pdbfs_ode;
    s->jac = pdbfs_jac;
    s->jac_sp = pdbfs_jac_sparsity_out(0);
    s->log = log;
    s->env = env;
}

void pdbfs_cvode_free(PdbfsCvode *s) {
    free(s->jac_nz);
    s->jac_nz = NULL;
    free(s->g);
    s->g = NULL;
}

int pdbfs_cvode_start(PdbfsCvode *s, const PdbfsCvodeSettings *set, double t0, const double *x0) {
    (void)set; (void)t0; (void)x0;
    if (s->log) s->log(s->env, PDBFS_LOG_ERROR, "this library was built without CVODE "
                       "(the explicit method only)");
    return NO_CVODE;
}

double pdbfs_next_time_event(PdbfsCvode *s, double t, const double *x) {
    (void)s; (void)t; (void)x;
    return INFINITY;
}

int pdbfs_cvode_advance(PdbfsCvode *s, double t_out, double horizon, long max_steps, double *x_out) {
    (void)t_out; (void)horizon; (void)max_steps; (void)x_out;
    return pdbfs_cvode_start(s, NULL, 0.0, NULL);
}

int pdbfs_cvode_roots(PdbfsCvode *s, const PdbfsCvodeSettings *set, double t0, const double *x0,
                      double t1, pdbfs_root_fn g, void *env, int dir, int max, double *t_root,
                      double *x_root, int *dir_root) {
    (void)t1; (void)g; (void)env; (void)dir; (void)max; (void)t_root; (void)x_root; (void)dir_root;
    return pdbfs_cvode_start(s, set, t0, x0);
}

/* pdbfs_eval: the model interface every binary shares, with CVODE or without
 * it (pdbfs_cvode.h, where a CasADi function is evaluated at (t, x, v, p)):
 * the work arrays in one block, and the PdbfsCvode that the drivers hand to
 * both integrators (CVODE's pdbfs_cvode.c, the explicit method's pdbfs_erk.c). */
#include <stdlib.h>
#include <string.h>

#include "pdbfs_cvode.h"

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


/* pdbfs_cvode_none: pdbfs_cvode.h's functions for a compiled library built
 * without SUNDIALS (-DPDBFS_NO_CVODE), which runs the explicit method only.
 * The model interface (evaluation, work arrays, the PdbfsCvode the drivers
 * hand to the explicit method) is pdbfs_eval.c's, as with CVODE; starting CVODE
 * fails with a message, never silently (Python builds the library with
 * CVODE before it asks for Adams or BDF: pdbfs/simulation/compiled.py). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pdbfs_cvode.h"

#define NO_CVODE (-100)

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

/* solver.method "auto" in co-simulation: the compiled backend's choice
 * (pdbfs.simulation.stiffness, with the thresholds of pdbfs.native.stiffness
 * that pdbfs_model.h carries), made at initialisation, when the parameters,
 * the start state and the stop time of this run are known: the explicit
 * Runge-Kutta method for a run of at most PDBFS_ERK_RADIANS radians of the
 * fastest mode, else BDF where a mode decays without oscillating fast enough
 * to cost Adams more than PDBFS_STIFF_STEPS steps, else Adams.  The modes are
 * the eigenvalues of d(ode)/dx at the start (pdbfs_modes.c, the compiled
 * backend's too); a rig of more than PDBFS_DENSE_UP_TO states is given BDF
 * without them. */
#include <stdio.h>

#include "fmu_instance.h"
#include "pdbfs_modes.h"

int stiffness_choose(Inst *m, double span, char *why, size_t len) {
    const int n = NX;
    double *work, fastest = 0.0, rate = 0.0;
    int rc;
    if (n == 0) {
        snprintf(why, len, "no states");
        return METHOD_BDF;
    }
    if (n > PDBFS_DENSE_UP_TO) {
        snprintf(why, len, "%d states: more than the %d whose modes are computed here", n, PDBFS_DENSE_UP_TO);
        return METHOD_BDF;
    }
    work = (double *)m->host.alloc(pdbfs_modes_work(n), sizeof(double));
    if (!work) {
        snprintf(why, len, "no memory for the Jacobian's modes");
        return METHOD_BDF;
    }
    /* a Jacobian not finite at the start: no modes, as the compiled backend takes it */
    rc = pdbfs_modes_at(&m->ev, n, m->s.time, m->s.x, work, &fastest, &rate);
    m->host.free(work);
    if (rc < 0) {
        snprintf(why, len, "the Jacobian's modes did not converge");
        return METHOD_BDF;
    }
    if (rate * span > PDBFS_STIFF_STEPS) {
        snprintf(why, len, "a mode decays at %.3g 1/s without oscillating: Adams would need about %.3g steps",
                 rate, rate * span);
        return METHOD_BDF;
    }
    if (fastest * span <= PDBFS_ERK_RADIANS) {
        snprintf(why, len, "the fastest mode (%.3g rad/s) turns %.3g rad in the %.3g s run: not stiff",
                 fastest, fastest * span, span);
        return METHOD_ERK;
    }
    snprintf(why, len, "the fastest mode (%.3g rad/s) turns %.3g rad in the %.3g s run: too many for "
             "the explicit method, not stiff", fastest, fastest * span, span);
    return METHOD_ADAMS;
}

/* solver.method "auto" in co-simulation: the compiled backend's choice
 * (pdbfs.simulation.stiffness, with the cost model of pdbfs.native.stiffness
 * whose numbers pdbfs_model.h carries as PDBFS_AUTO_*), made at
 * initialisation, when the parameters and the start state are known: the
 * cheapest of the explicit Runge-Kutta method, CVODE Adams and BDF, each
 * (steps the modes allow) x (cost of a step), for the run from the start to
 * the stop time, or, with no stop time, for each second of a long run.  The
 * modes are the eigenvalues of d(ode)/dx at the start (pdbfs_modes.c, the
 * compiled backend's too); a rig of more than PDBFS_AUTO_DENSE_UP_TO states
 * is given BDF without them.  Where the explicit method or BDF is chosen,
 * co-simulation switches between the two as the run goes (cosimulation.c):
 * the start's modes do not tell what a long run will excite. */
#include <math.h>
#include <stdio.h>

#include "fmu_instance.h"
#include "pdbfs_modes.h"

enum { C_ERK, C_ADAMS, C_BDF };

/* pdbfs.native.stiffness.run_costs: ns of a run of ``span`` s (INFINITY: of
 * each second of a long run) with each method, into cost[C_ERK .. C_BDF] */
static void run_costs(double fastest, double rate, double osc, double span, double cost[3]) {
    const int n = NX, long_run = isinf(span);
    const double t = long_run ? 1.0 : span, f = PDBFS_AUTO_EVAL_NS * PDBFS_ODE_INSTRUCTIONS;
    double acc = (long_run ? 0.0 : PDBFS_AUTO_ERK_STEPS_BASE)
                 + PDBFS_AUTO_ERK_STEPS_COEF * t * pow(osc, PDBFS_AUTO_ERK_STEPS_EXP);
    double erk = fmax(acc, fastest * t / PDBFS_AUTO_ERK_STABLE);
    double adams = fmax(fmax(PDBFS_AUTO_ADAMS_STEPS * acc, osc * t / PDBFS_AUTO_ADAMS_STABLE_OSC),
                        rate * t / PDBFS_AUTO_ADAMS_STABLE_DECAY);
    double bdf = PDBFS_AUTO_BDF_STEPS * acc;
    cost[C_ERK] = erk * (PDBFS_AUTO_ERK_EVALS * f + PDBFS_AUTO_ERK_STEP_NS + PDBFS_AUTO_ERK_STATE_NS * n);
    cost[C_ADAMS] = n >= PDBFS_AUTO_NEWTON_FROM
        ? adams * (PDBFS_AUTO_ADAMS_NEWTON_EVALS * f + PDBFS_AUTO_ADAMS_NEWTON_STEP_NS
                   + PDBFS_AUTO_ADAMS_NEWTON_STATE_NS * n)
        : adams * (PDBFS_AUTO_ADAMS_EVALS * f + PDBFS_AUTO_ADAMS_STEP_NS + PDBFS_AUTO_ADAMS_STATE_NS * n);
    cost[C_BDF] = bdf * (PDBFS_AUTO_BDF_EVALS * f + PDBFS_AUTO_BDF_STEP_NS + PDBFS_AUTO_BDF_STATE_NS * n);
}

int stiffness_choose(Inst *m, double span, char *why, size_t len) {
    static const int methods[3] = {METHOD_ERK, METHOD_ADAMS, METHOD_BDF};
    const int n = NX;
    double *work, fastest = 0.0, rate = 0.0, osc = 0.0, cost[3];
    int rc, best = C_ERK, i, k;
    m->switching = 0;
    m->lambda_ref = 0.0;
    if (n == 0) {
        snprintf(why, len, "no states");
        return METHOD_BDF;
    }
    if (n > PDBFS_AUTO_DENSE_UP_TO) {
        snprintf(why, len, "%d states: more than the %d whose modes are computed here", n,
                 PDBFS_AUTO_DENSE_UP_TO);
        return METHOD_BDF;
    }
    work = (double *)m->host.alloc(pdbfs_modes_work(n), sizeof(double));
    if (!work) {
        snprintf(why, len, "no memory for the Jacobian's modes");
        return METHOD_BDF;
    }
    /* a Jacobian not finite at the start: no modes, as the compiled backend takes it */
    rc = pdbfs_modes_at(&m->ev, n, m->s.time, m->s.x, work, &fastest, &rate, &osc);
    m->host.free(work);
    if (rc < 0) {
        snprintf(why, len, "the Jacobian's modes did not converge");
        return METHOD_BDF;
    }
    run_costs(fastest, rate, osc, span, cost);
    for (i = C_ADAMS; i <= C_BDF; i++)
        if (cost[i] < cost[best]) best = i;      /* (a tie: the first) */
    m->switching = best != C_ADAMS;
    m->lambda_ref = fastest;
    k = snprintf(why, len, "the cheapest by the estimate (erk %.3g, adams %.3g, bdf %.3g ns%s): the fastest mode "
                 "(%.3g rad/s), the fastest oscillating %.3g rad/s", cost[C_ERK], cost[C_ADAMS], cost[C_BDF],
                 isinf(span) ? " a second: no stop time" : "", fastest, osc);
    if (rate > 0 && k > 0 && (size_t)k < len)
        k += snprintf(why + k, len - (size_t)k, ", a mode decays at %.3g 1/s without oscillating", rate);
    if (m->switching && k > 0 && (size_t)k < len)
        snprintf(why + k, len - (size_t)k, "; switching to BDF where the explicit method's steps are held by "
                 "stability, back where BDF's are short");
    return methods[best];
}

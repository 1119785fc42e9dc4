/*
 * One instance of a pdbfs FMU: what the generic FMI 2.0 files share.
 *
 *   fmi2_functions.c   life cycle, variables, logging (generic FMI plumbing)
 *   fmi2_state.c       FMU state: get, set, serialise (generic)
 *   model.c            the model on the CasADi-generated functions: start
 *                      values, derivatives, outputs, parameter checks
 *   model_exchange.c   the Model Exchange calls
 *   cosimulation.c     the Co-Simulation calls: CVODE through the events
 *                      (native/c/pdbfs_cvode.c)
 *
 * Everything model-specific comes from two generated files: pdbfs_model.h
 * (sizes, value references, parameter table, GUID) and pdbfs_model_funcs.c
 * (CasADi's C of ode, Jacobian, outputs, start values, event indicators,
 * calculated parameters).
 *
 * Value references (Real): [params | solver.rtol, solver.max_step |
 *   calculated params | states | derivatives | other outputs/locals],
 * Integer: solver.method, solver.max_num_steps (after the reals).
 */
#ifndef PDBFS_FMU_INSTANCE_H
#define PDBFS_FMU_INSTANCE_H

#include "fmi2Functions.h"
#include "pdbfs_cvode.h"
#include "pdbfs_model.h"

/* zero-size arrays are not C: every model-sized array is padded by one */
#define NX PDBFS_NX
#define NP PDBFS_NP
#define NC PDBFS_NC
#define NY PDBFS_NY
#define NYV PDBFS_NYV
#define NE PDBFS_NE

/* solver.method, as in modelDescription.xml */
#define METHOD_BDF 1
#define METHOD_ADAMS 2

typedef enum {
    ST_INSTANTIATED = 1 << 0,
    ST_INIT = 1 << 1,
    ST_EVENT = 1 << 2,       /* ME */
    ST_CONT = 1 << 3,        /* ME */
    ST_STEPDONE = 1 << 4,    /* CS */
    ST_TERMINATED = 1 << 5,
    ST_ERROR = 1 << 6
} Mode;

#define ST_ANY (ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_CONT | ST_STEPDONE | ST_TERMINATED | ST_ERROR)
#define ST_RUNNING (ST_EVENT | ST_CONT | ST_STEPDONE)

#define SNAP_MAGIC 0x70646266u /* "pdbf" */

/* Everything that is the FMU state: plain data, copied by fmi2GetFMUstate and
 * serialised byte for byte. */
typedef struct {
    unsigned magic;
    unsigned size;
    char token[64];
    int mode;
    int type;
    double time;
    double p[NP + 1];
    double rtol;
    double max_step;
    int method;
    int max_num_steps;       /* internal steps allowed in one fmi2DoStep */
    int rtol_user;           /* solver.rtol set explicitly: wins over SetupExperiment */
    int tol_defined;
    double tol;
    double t_start;
    int stop_defined;
    double t_stop;
    double x[NX + 1];
    int x_fixed;             /* x holds the state (else x0(p) on demand) */
} Snapshot;

typedef struct {
    Snapshot s;
    fmi2CallbackFunctions cb;
    char *name;
    int logging;
    /* derived quantities at (time, x, p) */
    double xdot[NX + 1], y[NY + 1], e[NE + 1], c[NC + 1];
    int derived_ok;
    /* co-simulation */
    PdbfsCvode solver;
    int need_restart;        /* restart CVODE from (time, x) before integrating */
    /* CasADi work memory */
    PdbfsEval ev;
    const double *arg[PDBFS_SZ_ARG + 1];
    double *res[PDBFS_SZ_RES + 1];
    casadi_int iw[PDBFS_SZ_IW + 1];
    double w[PDBFS_SZ_W + 1];
} Inst;

/* fmi2_functions.c */
void fmu_log(Inst *m, fmi2Status st, const char *cat, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
fmi2Status fmu_check(Inst *m, const char *fn, int allowed, int needType);
#define ERR(m, ...) (fmu_log((m), fmi2Error, "logStatusError", __VA_ARGS__), fmi2Error)

/* model.c */
void model_defaults(Inst *m);
int model_start(Inst *m, double *x0);
const double *model_x(Inst *m);
void model_update(Inst *m);
double model_rtol(const Inst *m);
fmi2Status model_check_param(Inst *m, int k, double v);
int fmu_all_finite(const double *v, int n);

/* cosimulation.c */
fmi2Status cosim_start(Inst *m);
void cosim_free(Inst *m);

#endif

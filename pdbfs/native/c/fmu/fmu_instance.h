/*
 * One instance of a pdbfs FMU, independent of the FMI version.
 *
 *   lifecycle.c        the life cycle: instantiate, set up, initialise,
 *                      terminate, reset, free
 *   values.c           variables by value reference
 *   snapshot.c         the FMU state: get, set, serialise
 *   model_exchange.c   what Model Exchange asks of the model
 *   derivatives.c      directional and adjoint derivatives (exact: CasADi's AD)
 *   cosimulation.c     the co-simulation loop: CVODE or the explicit
 *                      Runge-Kutta method through the events
 *                      (native/c/pdbfs_cvode.c, native/c/pdbfs_erk.c)
 *   stiffness.c        solver.method "auto": which of them suits the run
 *   model.c            the model on the CasADi-generated functions, logging,
 *                      the state machine's check
 *
 * Calls run one way, down this list: the life cycle calls the interface
 * parts (cosimulation.c) and the model; the interface parts call the model;
 * model.c calls none of them.
 *
 * These files know no FMI header: they return FMU_* status codes (the
 * numbers of fmi2Status and fmi3Status) and log through the hook the
 * version's wrapper sets (fmi2_*.c, fmi3_*.c), which call into them and
 * never the reverse.
 *
 * Everything model-specific comes from two generated files: pdbfs_model.h
 * (sizes, value references, parameter table, token) and pdbfs_model_funcs.c
 * (CasADi's C of ode, Jacobian, outputs, start values, event indicators,
 * calculated parameters, the components' conditions, the declared starts of
 * states index reduction made algebraic).
 *
 * Value references (Real): [params | solver.rtol, solver.max_step |
 *   calculated params | states | derivatives | other outputs/locals | inputs],
 * Integer: solver.method, solver.max_num_steps (after the reals); FMI 3.0
 * adds time and the event indicators after these (pdbfs_model.h defines
 * PDBFS_VR_TIME and PDBFS_VR_E then).
 */
#ifndef PDBFS_FMU_INSTANCE_H
#define PDBFS_FMU_INSTANCE_H

#include <stddef.h>

#include "pdbfs_cvode.h"
#include "pdbfs_erk.h"
#include "pdbfs_model.h"

/* zero-size arrays are not C: every model-sized array is padded by one */
#define NX PDBFS_NX
#define NP PDBFS_NP       /* all of p: the parameters, then (a rig with inputs) the inputs' entries */
#define NPAR PDBFS_NPAR   /* the free parameters, p[0 .. NPAR) */
#define NU PDBFS_NU       /* the inputs: input k is p[U0 + k] + p[DU0 + k] * (t - p[TREF]) */
#define NC PDBFS_NC
#define NY PDBFS_NY
#define NYV PDBFS_NYV
#define NE PDBFS_NE

/* status codes: the numbers of fmi2Status and fmi3Status */
#define FMU_OK 0
#define FMU_WARNING 1
#define FMU_DISCARD 2
#define FMU_ERROR 3

/* interface types: the numbers of fmi2Type (FMI 3.0 has one call per type) */
#define FMU_ME 0
#define FMU_CS 1

/* solver.method, as in modelDescription.xml (auto: decided at initialisation) */
#define METHOD_AUTO 0
#define METHOD_BDF 1
#define METHOD_ADAMS 2
#define METHOD_ERK 3
#define METHOD_VALID(v) ((v) >= METHOD_AUTO && (v) <= METHOD_ERK)

typedef enum {
    ST_INSTANTIATED = 1 << 0,
    ST_INIT = 1 << 1,
    ST_EVENT = 1 << 2,       /* ME */
    ST_CONT = 1 << 3,        /* ME */
    ST_STEPDONE = 1 << 4,    /* CS */
    ST_TERMINATED = 1 << 5,
    ST_ERROR = 1 << 6,
    ST_INTERMEDIATE = 1 << 7 /* CS, FMI 3.0: inside fmi3DoStep, the importer's intermediate update */
} Mode;

#define ST_ANY (ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_CONT | ST_STEPDONE | ST_TERMINATED | ST_ERROR)
#define ST_RUNNING (ST_EVENT | ST_CONT | ST_STEPDONE)
/* the FMI state tables' modes for setting a Real (Float64) and a discrete
 * (Integer, Boolean, String) variable; reading is refused in Instantiated
 * (FMI 2.0), or allowed there for start values only (FMI 3.0): values.c */
#define ST_SET_REAL (ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_CONT | ST_STEPDONE)
#define ST_SET_DISCRETE (ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_STEPDONE)

#define SNAP_MAGIC 0x70646266u /* "pdbf" */

/* why co-simulation restarts its solver (Inst.need_restart): afresh (a new
 * run, a state set, a failure), or because an input or a tunable parameter
 * changed between steps, a jump of the right-hand side in a smooth solution
 * (cosimulation.c: the explicit method keeps its step size across it, and
 * auto's switching takes the explicit method there, as at an event) */
#define RESTART_FRESH 1
#define RESTART_CHANGED 2

/* Everything that is the FMU state: plain data, copied by GetFMUstate and
 * serialised byte for byte. */
typedef struct {
    unsigned magic;
    unsigned size;
    char token[64];
    int mode;
    int type;
    double time;
    double p[NP + 1];        /* parameters, then the inputs' values, slopes and t_ref */
    double rtol;
    double max_step;
    int method;
    int method_used;         /* the method co-simulation integrates with (auto resolved) */
    int max_num_steps;       /* internal steps allowed in one DoStep */
    int rtol_user;           /* solver.rtol set explicitly: wins over the experiment's tolerance */
    int tol_defined;
    double tol;
    double t_start;
    int stop_defined;
    double t_stop;
    double x[NX + 1];
    int x_fixed;             /* x holds the state (else x0(p) on demand) */
    double slope_time[NU + 1]; /* when each input's slope was last given (-INFINITY: never): a value
                              * set at that same time keeps it (values.c) */
} Snapshot;

typedef struct Inst Inst;

/* The host as the version's wrapper sees it: memory, and a hook that hands
 * one formatted message to the host's logger (kept as a plain function
 * pointer: its type belongs to the FMI version). */
typedef struct {
    void *(*alloc)(size_t n, size_t size);   /* zeroed, as calloc */
    void (*free)(void *p);
    void (*hook)(const Inst *m, int status, const char *category, const char *message);
    void (*logger)(void);
    void *env;
    /* FMI 3.0 co-simulation: the importer's intermediate update (NULL: none),
     * called after each internal step inside a DoStep at the step's end t
     * (Intermediate Update Mode: the outputs readable there); 1 where the
     * importer asks to return early, at *early_time (s). ``update``: the
     * importer's callback as the wrapper keeps it; ``early_allowed``: the
     * importer allows an early return (earlyReturnAllowed) */
    int (*intermediate)(const Inst *m, double t, int can_return_early, double *early_time);
    void (*update)(void);
    int early_allowed;
} FmuHost;

struct Inst {
    Snapshot s;
    FmuHost host;
    char *name;
    int logging;
    /* derived quantities at (time, x, p) */
    double xdot[NX + 1], y[NY + 1], e[NE + 1], c[NC + 1];
    int derived_ok;
    /* co-simulation */
    PdbfsCvode solver;       /* CVODE (its time events also serve the explicit method) */
    PdbfsErk rk;             /* the explicit Runge-Kutta method (rk.y: allocated) */
    double atol[NX + 1];     /* absolute tolerances (the explicit method keeps a pointer) */
    double t_break;          /* the explicit method stops and restarts here (a time event) */
    int need_restart;        /* restart the solver from (time, x) before integrating: RESTART_* */
    /* solver.method auto in co-simulation: switching between the explicit
     * method and BDF as the run goes (stiffness.c, cosimulation.c) */
    int switching;           /* on: auto chose one of the two */
    double lambda_ref;       /* 1/s, the start's fastest mode: explicit steps longer than
                              * PDBFS_AUTO_SWITCH_TO_BDF / lambda_ref are held by stability, BDF
                              * steps shorter than PDBFS_AUTO_SWITCH_TO_ERK / lambda_ref resolve it
                              * (0: no switching) */
    int bdf_short;           /* such BDF steps in a row, and their length (s) */
    double bdf_short_time;
    int switch_pending;      /* BDF paused at t_switch (x_switch) to switch, past the last
                              * communication point: its dense output serves up to there */
    double t_switch, x_switch[NX + 1];
    /* a DoStep's intermediate updates (host.intermediate): its end, the last
     * point reported, and an early return asked for (early: to t_early) */
    double t_end, t_seen, t_early;
    int early;
    int watch_bdf;           /* CVODE's steps watched for auto's switch back (bdf_watch) */
    /* CasADi work memory */
    PdbfsEval ev;
    const double *arg[PDBFS_SZ_ARG + 1];
    double *res[PDBFS_SZ_RES + 1];
    casadi_int iw[PDBFS_SZ_IW + 1];
    double w[PDBFS_SZ_W + 1];
};

/* model.c: logging, the state machine's check */
void fmu_log(Inst *m, int st, const char *cat, const char *fmt, ...) PDBFS_PRINTF(4, 5);
int fmu_check(Inst *m, const char *fn, int allowed, int needType);
#define ERR(m, ...) (fmu_log((m), FMU_ERROR, "logStatusError", __VA_ARGS__), FMU_ERROR)

/* lifecycle.c */
Inst *fmu_new(const char *name, int type, const FmuHost *host, int logging);
void fmu_free(Inst *m);
int fmu_set_logging(Inst *m, const char *fn, int on, size_t n, const char *const categories[]);
int fmu_setup(Inst *m, const char *fn, int tol_defined, double tol, double start, int stop_defined, double stop);
int fmu_enter_init(Inst *m, const char *fn);
int fmu_exit_init(Inst *m, const char *fn);
int fmu_terminate(Inst *m, const char *fn);
int fmu_reset(Inst *m, const char *fn);

/* model.c: the model */
void model_defaults(Inst *m);
int model_start(Inst *m, double *x0);
const double *model_x(Inst *m);
void model_update(Inst *m);
double model_rtol(const Inst *m);
int model_check_param(Inst *m, int k, double v);
int model_failed_condition(Inst *m, const double *p);
int model_finite(Inst *m);
int model_check_reduced(Inst *m, const char *fn);
int model_check_finite(Inst *m, const char *fn);
int fmu_all_finite(const double *v, int n);

/* values.c: variables by value reference (a rejected set changes nothing);
 * ``starts``: Instantiated answers the start values (FMI 3.0), else nothing (FMI 2.0) */
int values_check_get(Inst *m, const char *fn, const unsigned vr[], size_t n, int starts);
int values_get_real(Inst *m, const char *fn, const unsigned vr[], size_t n, double v[], int starts);
int values_set_real(Inst *m, const char *fn, const unsigned vr[], size_t n, const double v[]);
int values_get_int(Inst *m, const char *fn, unsigned vr, long long *v);
int values_check_int(Inst *m, const char *fn, unsigned vr, long long v);
void values_set_int(Inst *m, unsigned vr, long long v);
int values_none(Inst *m, const char *fn, const unsigned vr[], size_t n, int allowed);
/* an intermediate variable (FMI 3.0: intermediateUpdate="true"): an output */
int values_intermediate(unsigned vr);
/* the inputs' first derivatives (FMI 2.0 Co-Simulation: fmi2SetRealInputDerivatives):
 * each input then runs linearly from its value at the current time */
int values_set_input_slopes(Inst *m, const char *fn, const unsigned vr[], size_t n, const int order[],
                            const double v[]);
/* input k's value at the current time */
double values_input(const Inst *m, int k);

/* snapshot.c: the FMU state */
int snapshot_get(Inst *m, const char *fn, void **state);
int snapshot_set(Inst *m, const char *fn, const void *state);
int snapshot_free(Inst *m, void **state);
int snapshot_size(Inst *m, const char *fn, const void *state, size_t *size);
int snapshot_serialize(Inst *m, const char *fn, const void *state, unsigned char *bytes, size_t size);
int snapshot_deserialize(Inst *m, const char *fn, const unsigned char *bytes, size_t size, void **state);

/* model_exchange.c */
int me_enter_event_mode(Inst *m, const char *fn);
int me_enter_continuous_mode(Inst *m, const char *fn);
int me_new_discrete_states(Inst *m, const char *fn);
double me_next_event_time(Inst *m);
int me_completed_step(Inst *m, const char *fn, int *enter_event, int *terminate);
int me_set_time(Inst *m, const char *fn, double t);
int me_set_states(Inst *m, const char *fn, const double x[], size_t nx);
int me_get_derivatives(Inst *m, const char *fn, double dx[], size_t nx);
int me_get_event_indicators(Inst *m, const char *fn, double e[], size_t ne);
int me_get_states(Inst *m, const char *fn, double x[], size_t nx);
int me_get_nominals(Inst *m, const char *fn, double nominals[], size_t nx);

/* derivatives.c: d[der(x); y] / d[x; p] times a seed (forward) or a seed times it (adjoint) */
int deriv_forward(Inst *m, const char *fn, const unsigned unknown[], size_t nu, const unsigned known[], size_t nk,
                  const double seed[], double sens[]);
int deriv_adjoint(Inst *m, const char *fn, const unsigned unknown[], size_t nu, const unsigned known[], size_t nk,
                  const double seed[], double sens[]);

/* derivatives.c: the order[i]-th time derivative (1 or 2) of the output or state vr[i] now,
 * along the solution (co-simulation) */
int deriv_outputs(Inst *m, const char *fn, const unsigned vr[], size_t n, const int order[], double v[]);

/* stiffness.c: solver.method "auto" resolved for a run of ``span`` s from
 * (time, x, p) (INFINITY: a run of unknown length): METHOD_ERK, METHOD_ADAMS
 * or METHOD_BDF, the reason in why; sets switching and lambda_ref */
int stiffness_choose(Inst *m, double span, char *why, size_t n);

/* cosimulation.c */
int cosim_start(Inst *m);
void cosim_free(Inst *m);
/* one communication step from t to t + h; *early (may be NULL): it ended short of
 * t + h where the importer asked (intermediate update), at m->s.time */
int cosim_do_step(Inst *m, const char *fn, double t, double h, int *early);

#endif

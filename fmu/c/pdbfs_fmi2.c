/*
 * pdbfs generic FMI 2.0 wrapper (Model Exchange + Co-Simulation).
 *
 * This file is the same for every rig.  Everything model-specific comes from
 * two generated files:
 *   pdbfs_model.h        sizes, value-reference layout, parameter table
 *   pdbfs_model_funcs.c  CasADi-generated C of the model functions
 *                        (ode, jacobian, outputs, start values, event
 *                        indicators, calculated parameters)
 *
 * Co-simulation integrates with CVODE (SUNDIALS, linked statically): BDF +
 * Newton + dense LU with the CasADi Jacobian, or Adams + fixed point.  The
 * event indicators are CVODE root functions; the integrator is re-initialised
 * at every root.  Communication points are served from CVODE's dense output,
 * so the trajectory does not depend on the communication step.
 *
 * Value references (Real): [params | solver.rtol, solver.max_step |
 *   calculated params | states | derivatives | other outputs/locals],
 * Integer: solver.method (its own value reference after the reals).
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "pdbfs_model.h"
#include "pdbfs_model_funcs.h"

/* zero-size arrays are not C: pad every model-sized array by one */
#define NX PDBFS_NX
#define NP PDBFS_NP
#define NC PDBFS_NC
#define NY PDBFS_NY
#define NYV PDBFS_NYV
#define NE PDBFS_NE

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
    /* CVODE */
    SUNContext ctx;
    void *cv;
    N_Vector nv, tmp;
    SUNMatrix A;
    SUNLinearSolver LS;
    SUNNonlinearSolver NLS;
    int cv_method;
    int need_reinit;         /* restart CVODE from (time, x) before integrating */
    double tn;               /* time CVODE has integrated to */
    int steps_since_init;
    int root_pending;
    double t_root;
    int in_solver;           /* 1 while CVODE runs (errors go to its handler) */
    /* CasADi work memory */
    const double *arg[PDBFS_SZ_ARG + 1];
    double *res[PDBFS_SZ_RES + 1];
    casadi_int iw[PDBFS_SZ_IW + 1];
    double w[PDBFS_SZ_W + 1];
} Inst;

/* ------------------------------------------------------------------ logging */

static void logmsg(Inst *m, fmi2Status st, const char *cat, const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    if (!m || !m->cb.logger) return;
    if (st == fmi2OK && !m->logging) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    m->cb.logger(m->cb.componentEnvironment, m->name ? m->name : "?", st, cat, "%s", buf);
}

#define ERR(m, ...) (logmsg((m), fmi2Error, "logStatusError", __VA_ARGS__), fmi2Error)

static const char *mode_name(int mode) {
    switch (mode) {
    case ST_INSTANTIATED: return "instantiated";
    case ST_INIT: return "initialization mode";
    case ST_EVENT: return "event mode";
    case ST_CONT: return "continuous-time mode";
    case ST_STEPDONE: return "step complete";
    case ST_TERMINATED: return "terminated";
    case ST_ERROR: return "error";
    default: return "unknown";
    }
}

/* check the instance pointer, the interface type and the state machine */
static fmi2Status check(Inst *m, const char *fn, int allowed, int needType) {
    if (!m) return fmi2Error;
    if (m->s.magic != SNAP_MAGIC) return fmi2Error;
    if (needType >= 0 && m->s.type != needType) {
        return ERR(m, "%s: not available for %s", fn,
                   m->s.type == fmi2CoSimulation ? "Co-Simulation" : "Model Exchange");
    }
    if (!(m->s.mode & allowed)) {
        return ERR(m, "%s: must not be called in state '%s'", fn, mode_name(m->s.mode));
    }
    return fmi2OK;
}

/* -------------------------------------------------------- model evaluation */

static double eff_rtol(const Inst *m) {
    if (m->s.rtol_user) return m->s.rtol;
    if (m->s.tol_defined) return m->s.tol;
    return m->s.rtol;
}

static int call_start(Inst *m, double *x0) {
    m->arg[0] = m->s.p;
    m->res[0] = x0;
    return pdbfs_start(m->arg, m->res, m->iw, m->w, 0);
}

static int call_txp(Inst *m, int (*f)(const casadi_real **, casadi_real **, casadi_int *, casadi_real *, int),
                    double t, const double *x, double *out) {
    double tt = t;
    m->arg[0] = &tt;
    m->arg[1] = x;
    m->arg[2] = NULL;
    m->arg[3] = m->s.p;
    m->res[0] = out;
    return f(m->arg, m->res, m->iw, m->w, 0);
}

static const double *current_x(Inst *m) {
    if (!m->s.x_fixed) call_start(m, m->s.x);
    return m->s.x;
}

static void update(Inst *m) {
    const double *x;
    if (m->derived_ok) return;
    x = current_x(m);
    call_txp(m, pdbfs_ode, m->s.time, x, m->xdot);
    call_txp(m, pdbfs_out, m->s.time, x, m->y);
    if (NE > 0) call_txp(m, pdbfs_events, m->s.time, x, m->e);
    if (NC > 0) {
        m->arg[0] = m->s.p;
        m->res[0] = m->c;
        pdbfs_calc(m->arg, m->res, m->iw, m->w, 0);
    }
    m->derived_ok = 1;
}

static int all_finite(const double *v, int n) {
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

/* ------------------------------------------------------------------ CVODE */

static int cv_rhs(realtype t, N_Vector y, N_Vector ydot, void *ud) {
    Inst *m = (Inst *)ud;
    double *yd = N_VGetArrayPointer(ydot);
    call_txp(m, pdbfs_ode, t, N_VGetArrayPointer(y), yd);
    return all_finite(yd, NX) ? 0 : 1;
}

static int cv_jac(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *ud,
                  N_Vector t1, N_Vector t2, N_Vector t3) {
    Inst *m = (Inst *)ud;
    double *jd = SUNDenseMatrix_Data(J); /* column major, like CasADi */
    (void)fy; (void)t1; (void)t2; (void)t3;
    call_txp(m, pdbfs_jac, t, N_VGetArrayPointer(y), jd);
    return all_finite(jd, NX * NX) ? 0 : 1;
}

static int cv_root(realtype t, N_Vector y, realtype *g, void *ud) {
    Inst *m = (Inst *)ud;
    call_txp(m, pdbfs_events, t, N_VGetArrayPointer(y), g);
    return 0;
}

static void cv_err(int code, const char *module, const char *function, char *msg, void *ud) {
    Inst *m = (Inst *)ud;
    logmsg(m, code < 0 ? fmi2Error : fmi2Warning, code < 0 ? "logStatusError" : "logStatusWarning",
           "%s %s (flag %d): %s", module ? module : "", function ? function : "", code, msg ? msg : "");
}

static void solver_free(Inst *m) {
    if (m->cv) CVodeFree(&m->cv);
    if (m->LS) SUNLinSolFree(m->LS);
    if (m->NLS) SUNNonlinSolFree(m->NLS);
    if (m->A) SUNMatDestroy(m->A);
    if (m->nv) N_VDestroy(m->nv);
    if (m->tmp) N_VDestroy(m->tmp);
    if (m->ctx) SUNContext_Free(&m->ctx);
    m->cv = NULL; m->LS = NULL; m->NLS = NULL; m->A = NULL;
    m->nv = NULL; m->tmp = NULL; m->ctx = NULL;
    m->need_reinit = 1;
}

/* (Re)start CVODE at (time, x).  A new CVODE memory is built when there is
 * none or the method changed; otherwise CVodeReInit. */
static fmi2Status solver_start(Inst *m) {
    int flag = 0, i;
    double rtol = eff_rtol(m);
    if (m->cv && m->cv_method != m->s.method) solver_free(m);
    if (!m->ctx) {
        if (SUNContext_Create(NULL, &m->ctx) != 0) return ERR(m, "SUNContext_Create failed");
    }
    if (!m->nv) m->nv = N_VNew_Serial(NX, m->ctx);
    if (!m->tmp) m->tmp = N_VNew_Serial(NX, m->ctx);
    if (!m->nv || !m->tmp) return ERR(m, "out of memory (N_Vector)");
    for (i = 0; i < NX; i++) NV_Ith_S(m->nv, i) = m->s.x[i];
    if (!m->cv) {
        m->cv = CVodeCreate(m->s.method == METHOD_ADAMS ? CV_ADAMS : CV_BDF, m->ctx);
        if (!m->cv) return ERR(m, "CVodeCreate failed");
        m->cv_method = m->s.method;
        CVodeSetErrHandlerFn(m->cv, cv_err, m);
        flag = CVodeInit(m->cv, cv_rhs, m->s.time, m->nv);
        if (flag == CV_SUCCESS) flag = CVodeSetUserData(m->cv, m);
        if (flag == CV_SUCCESS) {
            if (m->s.method == METHOD_ADAMS) {
                m->NLS = SUNNonlinSol_FixedPoint(m->nv, 0, m->ctx);
                if (!m->NLS) return ERR(m, "SUNNonlinSol_FixedPoint failed");
                flag = CVodeSetNonlinearSolver(m->cv, m->NLS);
            } else {
                m->A = SUNDenseMatrix(NX, NX, m->ctx);
                m->LS = m->A ? SUNLinSol_Dense(m->nv, m->A, m->ctx) : NULL;
                if (!m->LS) return ERR(m, "dense linear solver creation failed");
                flag = CVodeSetLinearSolver(m->cv, m->LS, m->A);
                if (flag == CV_SUCCESS) flag = CVodeSetJacFn(m->cv, cv_jac);
            }
        }
        if (flag == CV_SUCCESS && NE > 0) {
            flag = CVodeRootInit(m->cv, NE, cv_root);
            if (flag == CV_SUCCESS) flag = CVodeSetNoInactiveRootWarn(m->cv);
        }
    } else {
        flag = CVodeReInit(m->cv, m->s.time, m->nv);
    }
    if (flag == CV_SUCCESS) {
        double atol[NX + 1];
        for (i = 0; i < NX; i++) atol[i] = rtol * PDBFS_X_NOMINAL[i];
        for (i = 0; i < NX; i++) NV_Ith_S(m->tmp, i) = atol[i];
        flag = CVodeSVtolerances(m->cv, rtol, m->tmp);
    }
    if (flag == CV_SUCCESS) flag = CVodeSetMaxStep(m->cv, m->s.max_step > 0 ? m->s.max_step : 0.0);
    if (flag == CV_SUCCESS) flag = CVodeSetMaxNumSteps(m->cv, 100000);
    if (flag != CV_SUCCESS) return ERR(m, "CVODE setup failed (flag %d)", flag);
    m->tn = m->s.time;
    m->steps_since_init = 0;
    m->root_pending = 0;
    m->need_reinit = 0;
    return fmi2OK;
}

/* a time beyond the step to come, the same whatever the communication step:
 * CVODE uses it only to bound its first step */
static double horizon(const Inst *m) {
    if (m->s.stop_defined && m->s.t_stop > m->tn) return m->s.t_stop;
    return m->tn + 1.0;
}

/* integrate to tEnd; on success m->s.x is the state at tEnd */
static fmi2Status integrate_to(Inst *m, double tEnd) {
    int flag, i;
    long nsteps = 0;
    double tret;
    if (m->need_reinit) {
        fmi2Status st = solver_start(m);
        if (st != fmi2OK) return st;
    }
    for (;;) {
        if (m->root_pending && m->t_root <= tEnd) {
            /* restart at the root: the right-hand side is not smooth there */
            if (m->t_root > m->s.time) {
                flag = CVodeGetDky(m->cv, m->t_root, 0, m->nv);
                if (flag != CV_SUCCESS) return ERR(m, "CVodeGetDky failed at root t=%.17g", m->t_root);
            }
            m->root_pending = 0;
            flag = CVodeReInit(m->cv, m->t_root, m->nv);
            if (flag != CV_SUCCESS) return ERR(m, "CVodeReInit failed at t=%.17g", m->t_root);
            logmsg(m, fmi2OK, "logEvents", "event at t=%.17g, CVODE restarted", m->t_root);
            m->tn = m->t_root;
            m->steps_since_init = 0;
        }
        if (m->tn >= tEnd || (m->root_pending && m->t_root > tEnd)) break;
        if (++nsteps > m->s.max_num_steps) {
            m->need_reinit = 1;
            return ERR(m, "CVODE failed (too much work: solver.max_num_steps = %d internal steps) at t=%.17g "
                       "while integrating to t=%.17g", m->s.max_num_steps, m->tn, tEnd);
        }
        m->in_solver = 1;
        flag = CVode(m->cv, horizon(m), m->nv, &tret, CV_ONE_STEP);
        m->in_solver = 0;
        if (flag < 0) {
            double tc = m->tn;
            CVodeGetCurrentTime(m->cv, &tc);
            m->need_reinit = 1;
            return ERR(m, "CVODE failed (flag %d) at t=%.17g while integrating to t=%.17g", flag, tc, tEnd);
        }
        m->steps_since_init++;
        if (flag == CV_ROOT_RETURN) {
            m->root_pending = 1;
            m->t_root = tret;
            CVodeGetCurrentTime(m->cv, &m->tn);
        } else {
            m->tn = tret;
        }
    }
    if (m->steps_since_init == 0) {
        /* tEnd is the restart point itself */
        for (i = 0; i < NX; i++) m->s.x[i] = NV_Ith_S(m->nv, i);
    } else {
        flag = CVodeGetDky(m->cv, tEnd, 0, m->tmp);
        if (flag != CV_SUCCESS) return ERR(m, "CVodeGetDky failed at t=%.17g (flag %d)", tEnd, flag);
        for (i = 0; i < NX; i++) m->s.x[i] = NV_Ith_S(m->tmp, i);
        /* restore the absolute tolerances vector used as scratch above */
    }
    return fmi2OK;
}

/* --------------------------------------------------------------- life cycle */

static void set_defaults(Inst *m) {
    int i;
    for (i = 0; i < NP; i++) m->s.p[i] = PDBFS_P_DEFAULT[i];
    m->s.rtol = PDBFS_DEFAULT_RTOL;
    m->s.max_step = PDBFS_DEFAULT_MAXSTEP;
    m->s.method = PDBFS_DEFAULT_METHOD;
    m->s.max_num_steps = PDBFS_DEFAULT_MAXNUMSTEPS;
    m->s.rtol_user = 0;
    m->s.tol_defined = 0;
    m->s.tol = PDBFS_DEFAULT_RTOL;
    m->s.t_start = 0.0;
    m->s.stop_defined = 0;
    m->s.t_stop = 0.0;
    m->s.time = 0.0;
    m->s.x_fixed = 0;
    for (i = 0; i < NX; i++) m->s.x[i] = 0.0;
    m->s.mode = ST_INSTANTIATED;
    m->derived_ok = 0;
    m->need_reinit = 1;
    m->root_pending = 0;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    Inst *m;
    size_t n;
    (void)fmuResourceLocation; (void)visible;
    if (!functions || !functions->allocateMemory || !functions->freeMemory) {
        if (functions && functions->logger)
            functions->logger(functions->componentEnvironment, instanceName ? instanceName : "?", fmi2Error,
                              "logStatusError", "fmi2Instantiate: allocateMemory and freeMemory are required");
        return NULL;
    }
#define EARLY_ERR(msg)                                                                         \
    do {                                                                                       \
        if (functions->logger)                                                                 \
            functions->logger(functions->componentEnvironment, instanceName ? instanceName : "?", \
                              fmi2Error, "logStatusError", "%s", msg);                          \
        return NULL;                                                                           \
    } while (0)
    if (!instanceName || !instanceName[0]) EARLY_ERR("fmi2Instantiate: missing instance name");
    if (fmuType != fmi2ModelExchange && fmuType != fmi2CoSimulation)
        EARLY_ERR("fmi2Instantiate: unknown fmuType");
    if (!fmuGUID || strcmp(fmuGUID, PDBFS_GUID) != 0)
        EARLY_ERR("fmi2Instantiate: GUID does not match this binary (" PDBFS_GUID ")");
    m = (Inst *)functions->allocateMemory(1, sizeof(Inst));
    if (!m) EARLY_ERR("fmi2Instantiate: out of memory");
    memset(m, 0, sizeof(Inst));
    m->cb = *functions;
    n = strlen(instanceName) + 1;
    m->name = (char *)functions->allocateMemory(n, 1);
    if (!m->name) {
        functions->freeMemory(m);
        EARLY_ERR("fmi2Instantiate: out of memory");
    }
    memcpy(m->name, instanceName, n);
    m->logging = loggingOn ? 1 : 0;
    m->s.magic = SNAP_MAGIC;
    m->s.size = (unsigned)sizeof(Snapshot);
    strncpy(m->s.token, PDBFS_GUID, sizeof m->s.token - 1);
    m->s.type = fmuType;
    set_defaults(m);
    logmsg(m, fmi2OK, "logAll", "instantiated %s (%s)", PDBFS_MODEL_IDENTIFIER,
           fmuType == fmi2CoSimulation ? "CoSimulation" : "ModelExchange");
    return m;
#undef EARLY_ERR
}

void fmi2FreeInstance(fmi2Component c) {
    Inst *m = (Inst *)c;
    fmi2CallbackFreeMemory freeMemory;
    if (!m || m->s.magic != SNAP_MAGIC) return;
    solver_free(m);
    freeMemory = m->cb.freeMemory;
    m->s.magic = 0;
    freeMemory(m->name);
    freeMemory(m);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (check(m, "fmi2SetDebugLogging", ST_ANY, -1) != fmi2OK) return fmi2Error;
    for (i = 0; i < nCategories; i++) {
        const char *k = categories ? categories[i] : NULL;
        if (!k || (strcmp(k, "logEvents") && strcmp(k, "logStatusWarning") && strcmp(k, "logStatusError") &&
                   strcmp(k, "logAll")))
            return ERR(m, "fmi2SetDebugLogging: unknown log category '%s'", k ? k : "(null)");
    }
    m->logging = loggingOn ? 1 : 0;
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2SetupExperiment", ST_INSTANTIATED, -1) != fmi2OK) return fmi2Error;
    if (toleranceDefined && !(isfinite(tolerance) && tolerance > 0 && tolerance < 1))
        return ERR(m, "fmi2SetupExperiment: tolerance %g must be in (0, 1)", tolerance);
    if (!isfinite(startTime)) return ERR(m, "fmi2SetupExperiment: startTime is not finite");
    if (stopTimeDefined && !(isfinite(stopTime) && stopTime >= startTime))
        return ERR(m, "fmi2SetupExperiment: stopTime %g must be finite and >= startTime %g", stopTime, startTime);
    m->s.tol_defined = toleranceDefined ? 1 : 0;
    if (toleranceDefined) m->s.tol = tolerance;
    m->s.t_start = startTime;
    m->s.time = startTime;
    m->s.stop_defined = stopTimeDefined ? 1 : 0;
    m->s.t_stop = stopTime;
    m->derived_ok = 0;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2EnterInitializationMode", ST_INSTANTIATED, -1) != fmi2OK) return fmi2Error;
    m->s.mode = ST_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2ExitInitializationMode", ST_INIT, -1) != fmi2OK) return fmi2Error;
    call_start(m, m->s.x);
    if (!all_finite(m->s.x, NX)) return ERR(m, "start values are not finite: check the parameters");
    m->s.x_fixed = 1;
    m->derived_ok = 0;
    m->need_reinit = 1;
    m->s.mode = m->s.type == fmi2CoSimulation ? ST_STEPDONE : ST_EVENT;
    if (m->s.type == fmi2CoSimulation) return solver_start(m);
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2Terminate", ST_RUNNING, -1) != fmi2OK) return fmi2Error;
    m->s.mode = ST_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2Reset", ST_ANY, -1) != fmi2OK) return fmi2Error;
    solver_free(m); /* a fresh CVODE: the second run is the first again */
    set_defaults(m);
    return fmi2OK;
}

/* --------------------------------------------------------- getters/setters */

#define VR_P_END (PDBFS_VR_P + NP)
#define VR_C_END (PDBFS_VR_C + NC)
#define VR_X_END (PDBFS_VR_X + NX)
#define VR_DX_END (PDBFS_VR_DX + NX)
#define VR_Y_END (PDBFS_VR_Y + NYV)

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (check(m, "fmi2GetReal", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2GetReal: NULL argument");
    for (i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r < VR_P_END) {
            value[i] = m->s.p[r - PDBFS_VR_P];
        } else if (r == PDBFS_VR_RTOL) {
            value[i] = eff_rtol(m);
        } else if (r == PDBFS_VR_MAXSTEP) {
            value[i] = m->s.max_step;
        } else if (r >= PDBFS_VR_C && r < VR_C_END) {
            update(m);
            value[i] = m->c[r - PDBFS_VR_C];
        } else if (r >= PDBFS_VR_X && r < VR_X_END) {
            value[i] = current_x(m)[r - PDBFS_VR_X];
        } else if (r >= PDBFS_VR_DX && r < VR_DX_END) {
            update(m);
            value[i] = m->xdot[r - PDBFS_VR_DX];
        } else if (r >= PDBFS_VR_Y && r < VR_Y_END) {
            update(m);
            value[i] = m->y[PDBFS_Y_INDEX[r - PDBFS_VR_Y]];
        } else {
            return ERR(m, "fmi2GetReal: unknown value reference %u", r);
        }
    }
    return fmi2OK;
}

static fmi2Status check_param(Inst *m, int k, double v) {
    if (!isfinite(v)) return ERR(m, "parameter %s: value %g is not finite", PDBFS_P_NAME[k], v);
    if (PDBFS_P_POSITIVE[k] && !(v > 0))
        return ERR(m, "parameter %s: value %g must be positive", PDBFS_P_NAME[k], v);
    if (v < PDBFS_P_MIN[k] || v > PDBFS_P_MAX[k])
        return ERR(m, "parameter %s: value %g outside [%g, %g]", PDBFS_P_NAME[k], v, PDBFS_P_MIN[k],
                   PDBFS_P_MAX[k]);
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    int before_init, tunable_ok, changed = 0;
    if (check(m, "fmi2SetReal", ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_CONT | ST_STEPDONE, -1) != fmi2OK)
        return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2SetReal: NULL argument");
    before_init = (m->s.mode & (ST_INSTANTIATED | ST_INIT)) != 0;
    tunable_ok = before_init || (m->s.mode & (ST_EVENT | ST_STEPDONE)) != 0;
    /* validate everything first: a rejected call changes nothing */
    for (i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        double v = value[i];
        if (r < VR_P_END) {
            int k = (int)(r - PDBFS_VR_P);
            if (!before_init && !PDBFS_P_TUNABLE[k])
                return ERR(m, "fmi2SetReal: parameter %s is fixed and cannot be changed after initialization",
                           PDBFS_P_NAME[k]);
            if (!tunable_ok)
                return ERR(m, "fmi2SetReal: tunable parameter %s can only be changed in %s", PDBFS_P_NAME[k],
                           m->s.type == fmi2CoSimulation ? "between steps" : "event mode");
            if (check_param(m, k, v) != fmi2OK) return fmi2Error;
        } else if (r == PDBFS_VR_RTOL || r == PDBFS_VR_MAXSTEP) {
            const char *nm = r == PDBFS_VR_RTOL ? "solver.rtol" : "solver.max_step";
            if (!before_init)
                return ERR(m, "fmi2SetReal: %s is fixed and cannot be changed after initialization", nm);
            if (!isfinite(v)) return ERR(m, "fmi2SetReal: %s = %g is not finite", nm, v);
            if (r == PDBFS_VR_RTOL && !(v > 0 && v < 1))
                return ERR(m, "fmi2SetReal: solver.rtol = %g must be in (0, 1)", v);
            if (r == PDBFS_VR_MAXSTEP && v < 0)
                return ERR(m, "fmi2SetReal: solver.max_step = %g must be >= 0 (0: no limit)", v);
        } else if (r < VR_Y_END) {
            return ERR(m, "fmi2SetReal: variable with value reference %u is not settable", r);
        } else {
            return ERR(m, "fmi2SetReal: unknown value reference %u", r);
        }
    }
    for (i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r < VR_P_END) {
            if (m->s.p[r - PDBFS_VR_P] != value[i]) changed = 1;
            m->s.p[r - PDBFS_VR_P] = value[i];
        } else if (r == PDBFS_VR_RTOL) {
            m->s.rtol = value[i];
            m->s.rtol_user = 1;
        } else if (r == PDBFS_VR_MAXSTEP) {
            m->s.max_step = value[i];
        }
    }
    m->derived_ok = 0;
    if (changed && !before_init) m->need_reinit = 1; /* restart: the right-hand side changed */
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (check(m, "fmi2GetInteger", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2GetInteger: NULL argument");
    for (i = 0; i < nvr; i++) {
        if (vr[i] == PDBFS_VR_METHOD) value[i] = m->s.method;
        else if (vr[i] == PDBFS_VR_MAXNUMSTEPS) value[i] = m->s.max_num_steps;
        else return ERR(m, "fmi2GetInteger: unknown value reference %u", vr[i]);
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (check(m, "fmi2SetInteger", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2SetInteger: NULL argument");
    for (i = 0; i < nvr; i++) {
        const char *nm = vr[i] == PDBFS_VR_METHOD ? "solver.method" : "solver.max_num_steps";
        if (vr[i] != PDBFS_VR_METHOD && vr[i] != PDBFS_VR_MAXNUMSTEPS)
            return ERR(m, "fmi2SetInteger: unknown value reference %u", vr[i]);
        if (!(m->s.mode & (ST_INSTANTIATED | ST_INIT)))
            return ERR(m, "fmi2SetInteger: %s is fixed and cannot be changed after initialization", nm);
        if (vr[i] == PDBFS_VR_METHOD && value[i] != METHOD_BDF && value[i] != METHOD_ADAMS)
            return ERR(m, "fmi2SetInteger: solver.method = %d must be 1 (BDF) or 2 (Adams)", value[i]);
        if (vr[i] == PDBFS_VR_MAXNUMSTEPS && value[i] < 1)
            return ERR(m, "fmi2SetInteger: solver.max_num_steps = %d must be >= 1", value[i]);
    }
    for (i = 0; i < nvr; i++) {
        if (vr[i] == PDBFS_VR_METHOD) m->s.method = value[i];
        else m->s.max_num_steps = value[i];
    }
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (check(m, "fmi2GetBoolean", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2GetBoolean: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (check(m, "fmi2SetBoolean", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2SetBoolean: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (check(m, "fmi2GetString", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2GetString: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (check(m, "fmi2SetString", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2SetString: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

/* -------------------------------------------------------------- FMU state */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    Inst *m = (Inst *)c;
    Snapshot *s;
    if (check(m, "fmi2GetFMUstate", ST_ANY & ~ST_ERROR, -1) != fmi2OK) return fmi2Error;
    if (!state) return ERR(m, "fmi2GetFMUstate: NULL argument");
    s = (Snapshot *)*state;
    if (!s) {
        s = (Snapshot *)m->cb.allocateMemory(1, sizeof(Snapshot));
        if (!s) return ERR(m, "fmi2GetFMUstate: out of memory");
    } else if (s->magic != SNAP_MAGIC) {
        return ERR(m, "fmi2GetFMUstate: invalid FMU state");
    }
    current_x(m);
    *s = m->s;
    *state = s;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    Inst *m = (Inst *)c;
    const Snapshot *s = (const Snapshot *)state;
    if (check(m, "fmi2SetFMUstate", ST_ANY & ~ST_ERROR, -1) != fmi2OK) return fmi2Error;
    if (!s || s->magic != SNAP_MAGIC || s->size != sizeof(Snapshot) || strcmp(s->token, PDBFS_GUID) != 0)
        return ERR(m, "fmi2SetFMUstate: invalid FMU state");
    if (s->type != m->s.type) return ERR(m, "fmi2SetFMUstate: state belongs to another interface type");
    m->s = *s;
    m->derived_ok = 0;
    m->need_reinit = 1;
    m->root_pending = 0;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    Inst *m = (Inst *)c;
    if (!m || m->s.magic != SNAP_MAGIC) return fmi2Error;
    if (!state || !*state) return fmi2OK;
    ((Snapshot *)*state)->magic = 0;
    m->cb.freeMemory(*state);
    *state = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2SerializedFMUstateSize", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (!state || !size) return ERR(m, "fmi2SerializedFMUstateSize: NULL argument");
    *size = sizeof(Snapshot);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size) {
    Inst *m = (Inst *)c;
    const Snapshot *s = (const Snapshot *)state;
    if (check(m, "fmi2SerializeFMUstate", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (!s || !bytes || s->magic != SNAP_MAGIC) return ERR(m, "fmi2SerializeFMUstate: invalid argument");
    if (size < sizeof(Snapshot)) return ERR(m, "fmi2SerializeFMUstate: buffer too small");
    memcpy(bytes, s, sizeof(Snapshot));
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state) {
    Inst *m = (Inst *)c;
    Snapshot tmp;
    if (check(m, "fmi2DeSerializeFMUstate", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (!bytes || !state) return ERR(m, "fmi2DeSerializeFMUstate: NULL argument");
    if (size != sizeof(Snapshot)) return ERR(m, "fmi2DeSerializeFMUstate: wrong size %zu", size);
    memcpy(&tmp, bytes, sizeof tmp);
    tmp.token[sizeof tmp.token - 1] = 0;
    if (tmp.magic != SNAP_MAGIC || tmp.size != sizeof(Snapshot) || strcmp(tmp.token, PDBFS_GUID) != 0)
        return ERR(m, "fmi2DeSerializeFMUstate: not a state of this FMU");
    if (!*state) {
        *state = m->cb.allocateMemory(1, sizeof(Snapshot));
        if (!*state) return ERR(m, "fmi2DeSerializeFMUstate: out of memory");
    }
    memcpy(*state, &tmp, sizeof tmp);
    return fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    Inst *m = (Inst *)c;
    (void)vUnknown_ref; (void)nUnknown; (void)vKnown_ref; (void)nKnown; (void)dvKnown; (void)dvUnknown;
    if (check(m, "fmi2GetDirectionalDerivative", ST_ANY, -1) != fmi2OK) return fmi2Error;
    return ERR(m, "fmi2GetDirectionalDerivative is not provided (providesDirectionalDerivative=false)");
}

/* --------------------------------------------------------- Model Exchange */

fmi2Status fmi2EnterEventMode(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2EnterEventMode", ST_EVENT | ST_CONT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    m->s.mode = ST_EVENT;
    logmsg(m, fmi2OK, "logEvents", "event mode at t=%.17g", m->s.time);
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2NewDiscreteStates", ST_EVENT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (!info) return ERR(m, "fmi2NewDiscreteStates: NULL argument");
    /* no discrete states: the event indicators only mark kinks */
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2EnterContinuousTimeMode", ST_EVENT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    m->s.mode = ST_CONT;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    Inst *m = (Inst *)c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (check(m, "fmi2CompletedIntegratorStep", ST_CONT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (!enterEventMode || !terminateSimulation) return ERR(m, "fmi2CompletedIntegratorStep: NULL argument");
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2SetTime", ST_EVENT | ST_CONT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (!isfinite(time)) return ERR(m, "fmi2SetTime: time is not finite");
    m->s.time = time;
    m->derived_ok = 0;
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Inst *m = (Inst *)c;
    size_t i;
    if (check(m, "fmi2SetContinuousStates", ST_EVENT | ST_CONT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (nx != NX) return ERR(m, "fmi2SetContinuousStates: nx = %zu, expected %d", nx, NX);
    if (!x) return ERR(m, "fmi2SetContinuousStates: NULL argument");
    if (!all_finite(x, NX)) return ERR(m, "fmi2SetContinuousStates: state is not finite");
    for (i = 0; i < NX; i++) m->s.x[i] = x[i];
    m->derived_ok = 0;
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    Inst *m = (Inst *)c;
    size_t i;
    if (check(m, "fmi2GetDerivatives", ST_ANY & ~ST_INSTANTIATED, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (nx != NX) return ERR(m, "fmi2GetDerivatives: nx = %zu, expected %d", nx, NX);
    if (!derivatives) return ERR(m, "fmi2GetDerivatives: NULL argument");
    update(m);
    for (i = 0; i < NX; i++) derivatives[i] = m->xdot[i];
    if (!all_finite(m->xdot, NX)) return ERR(m, "fmi2GetDerivatives: derivatives are not finite at t=%g", m->s.time);
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real ind[], size_t ni) {
    Inst *m = (Inst *)c;
    size_t i;
    if (check(m, "fmi2GetEventIndicators", ST_ANY & ~ST_INSTANTIATED, fmi2ModelExchange) != fmi2OK)
        return fmi2Error;
    if (ni != NE) return ERR(m, "fmi2GetEventIndicators: ni = %zu, expected %d", ni, NE);
    if (ni > 0 && !ind) return ERR(m, "fmi2GetEventIndicators: NULL argument");
    update(m);
    for (i = 0; i < ni; i++) ind[i] = m->e[i];
    return fmi2OK;
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Inst *m = (Inst *)c;
    size_t i;
    const double *xs;
    if (check(m, "fmi2GetContinuousStates", ST_ANY & ~ST_INSTANTIATED, fmi2ModelExchange) != fmi2OK)
        return fmi2Error;
    if (nx != NX) return ERR(m, "fmi2GetContinuousStates: nx = %zu, expected %d", nx, NX);
    if (!x) return ERR(m, "fmi2GetContinuousStates: NULL argument");
    xs = current_x(m);
    for (i = 0; i < NX; i++) x[i] = xs[i];
    return fmi2OK;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real nominals[], size_t nx) {
    Inst *m = (Inst *)c;
    size_t i;
    if (check(m, "fmi2GetNominalsOfContinuousStates", ST_ANY, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (nx != NX) return ERR(m, "fmi2GetNominalsOfContinuousStates: nx = %zu, expected %d", nx, NX);
    if (!nominals) return ERR(m, "fmi2GetNominalsOfContinuousStates: NULL argument");
    for (i = 0; i < NX; i++) nominals[i] = PDBFS_X_NOMINAL[i];
    return fmi2OK;
}

/* ------------------------------------------------------------ Co-Simulation */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    Inst *m = (Inst *)c;
    (void)order; (void)value;
    if (check(m, "fmi2SetRealInputDerivatives", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2SetRealInputDerivatives: the model has no inputs (vr %u)", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    Inst *m = (Inst *)c;
    (void)vr; (void)order; (void)value;
    if (check(m, "fmi2GetRealOutputDerivatives", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder=0)");
    return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Inst *m = (Inst *)c;
    fmi2Status st;
    double tol;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (check(m, "fmi2DoStep", ST_STEPDONE, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    if (!(h > 0) || !isfinite(h))
        return ERR(m, "fmi2DoStep: communicationStepSize %g must be positive and finite", h);
    tol = 1e-9 * h + 64 * DBL_EPSILON * fabs(m->s.time);
    if (!isfinite(t) || fabs(t - m->s.time) > tol)
        return ERR(m, "fmi2DoStep: currentCommunicationPoint %.17g does not match the FMU time %.17g", t,
                   m->s.time);
    if (m->s.stop_defined && t + h > m->s.t_stop * (1 + 1e-12) + 1e-12 * h)
        logmsg(m, fmi2Warning, "logStatusWarning", "fmi2DoStep: stepping beyond stopTime %g", m->s.t_stop);
    st = integrate_to(m, t + h);
    m->derived_ok = 0;
    if (st != fmi2OK) {
        m->s.mode = ST_ERROR;
        return fmi2Error;
    }
    m->s.time = t + h;
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2CancelStep", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    return ERR(m, "fmi2CancelStep: fmi2DoStep never runs asynchronously");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    Inst *m = (Inst *)c;
    (void)s; (void)value;
    if (check(m, "fmi2GetStatus", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    return fmi2Discard;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2GetRealStatus", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    if (s == fmi2LastSuccessfulTime && value) {
        *value = m->s.time;
        return fmi2OK;
    }
    return fmi2Discard;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    Inst *m = (Inst *)c;
    (void)s; (void)value;
    if (check(m, "fmi2GetIntegerStatus", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    return fmi2Discard;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    Inst *m = (Inst *)c;
    if (check(m, "fmi2GetBooleanStatus", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    if (s == fmi2Terminated && value) {
        *value = fmi2False;
        return fmi2OK;
    }
    return fmi2Discard;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    Inst *m = (Inst *)c;
    (void)s; (void)value;
    if (check(m, "fmi2GetStringStatus", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    return fmi2Discard;
}

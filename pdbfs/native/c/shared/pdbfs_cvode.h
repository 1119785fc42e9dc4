/*
 * pdbfs_cvode: CVODE driven through a rig's non-smooth points, shared by the
 * compiled simulation backend (simulation/c/pdbfs_batch.c) and the FMU's
 * co-simulation (fmu/c/cosimulation.c).
 *
 * The model is the CasADi-generated C of pdbfs_ode, pdbfs_jac (d ode / dx,
 * sparse: its nonzeros, pattern from pdbfs_jac_sparsity_out) and
 * pdbfs_events, all functions of (t, x, z, p).
 * CVODE runs in one-step mode; the event indicators are its root functions
 * and, on rigs of fewer than PDBFS_RESTART_BELOW states, it is restarted at
 * every root (the right-hand side is not smooth there); larger rigs are
 * integrated through their roots under error control, as CasADi's CVODES
 * does; states at requested times come from CVODE's dense output
 * (CVodeGetDky), so they do not depend on which times are requested.
 *
 * Methods: Adams-Moulton with fixed-point iteration, or Adams or BDF with
 * Newton on the CasADi Jacobian: a band LU when the Jacobian is banded (a
 * chain of masses: cost linear in the number of states), else dense LU.
 */
#ifndef PDBFS_CVODE_H
#define PDBFS_CVODE_H

#ifdef PDBFS_NO_CVODE
#include <stddef.h>
/* a compiled library of the explicit method alone (simulation/c/pdbfs_cvode_none.c):
 * built without SUNDIALS, whose handles are then opaque pointers of the same size */
typedef void *SUNContext;
typedef void *N_Vector;
typedef void *SUNMatrix;
typedef void *SUNLinearSolver;
typedef void *SUNNonlinearSolver;
#else
#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>
#endif

#include "pdbfs_model_funcs.h"

/* printf checks of log messages where the compiler has them (GCC, clang);
 * other compilers (MSVC) build the same code without */
#ifdef __GNUC__
#define PDBFS_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define PDBFS_PRINTF(fmt, args)
#endif

#define PDBFS_ADAMS 0
#define PDBFS_BDF 1

/* nonlinear iteration of Adams (BDF always uses Newton) */
#define PDBFS_NLS_AUTO 0          /* Newton from PDBFS_NEWTON_FROM states on */
#define PDBFS_NLS_FIXED_POINT 1
#define PDBFS_NLS_NEWTON 2
#define PDBFS_NEWTON_FROM 40      /* measured: below, fixed point is cheaper per step */

/* Restart at roots below this many states. Measured: a restart costs a
 * small rig a few steps and buys accuracy at the kink (paper rig: 1.4e-7 of
 * the peak against 5e-7 through it); a ringing chain climbs back to its
 * step only slowly after one (split piston, N = 200: 98,600 steps with its
 * 4 restarts, 42,200 through them). */
#define PDBFS_RESTART_BELOW 40

/* linear solver of Newton */
#define PDBFS_LS_AUTO 0           /* band if the band is narrow (see pdbfs_cvode.c), else dense */
#define PDBFS_LS_DENSE 1
#define PDBFS_LS_BAND 2

/* pdbfs_cvode_advance's own failures (CVODE's are its negative flags) */
#define PDBFS_CV_TOO_MUCH_WORK 3
#define PDBFS_CV_STOPPED 5        /* the step callback asked to stop */
/* the step callback's answer that stops pdbfs_cvode_advance without an error
 * (co-simulation switching methods): s->y is the state at s->tn, where the
 * step ended, and CVODE's dense output still covers that step */
#define PDBFS_STEP_PAUSE 2

/* what the log callback is told */
#define PDBFS_LOG_ERROR 0
#define PDBFS_LOG_WARNING 1
#define PDBFS_LOG_EVENT 2

typedef int (*pdbfs_casadi_fn)(const casadi_real **, casadi_real **, casadi_int *, casadi_real *, int);
/* the version of model function f made for the parameters p, the same
 * numbers as f with them (the generated C's, native/codegen.py): the
 * straight-line functions test p's usual values at every call, a driver asks
 * once per run instead */
pdbfs_casadi_fn pdbfs_for_params(pdbfs_casadi_fn f, const casadi_real *p);
typedef void (*pdbfs_log_fn)(void *env, int kind, const char *text);
typedef int (*pdbfs_step_fn)(void *env, double t, const double *x);
typedef int (*pdbfs_root_fn)(void *env, double t, const double *x, double *g);

/* How to evaluate the model: the parameters and CasADi work arrays (owned by
 * the caller, sized by the generated PDBFS_SZ_* of its header). */
typedef struct {
    const double *p;
    const casadi_real **arg;
    casadi_real **res;
    casadi_int *iw;
    casadi_real *w;
} PdbfsEval;

typedef struct {
    int method;           /* PDBFS_ADAMS or PDBFS_BDF */
    double rtol;
    const double *atol;   /* nx absolute tolerances */
    double max_step;      /* largest internal step, 0: no limit */
    double t_stop;        /* CVODE never steps past this time, if finite */
    int nls;              /* PDBFS_NLS_* (0: auto) */
    int linsol;           /* PDBFS_LS_* (0: auto) */
} PdbfsCvodeSettings;

typedef struct {
    int nx, ne;
    PdbfsEval *ev;
    /* the right-hand side and its sparse Jacobian with CasADi's pattern of it
     * (default pdbfs_ode, pdbfs_jac, pdbfs_jac_sparsity_out(0)) */
    pdbfs_casadi_fn ode, jac;
    const casadi_int *jac_sp;
    pdbfs_log_fn log;     /* may be NULL */
    void *env;
    /* CVODE and its memory */
    SUNContext ctx;
    void *cv;
    N_Vector y, tmp, atol;
    SUNMatrix A;
    SUNLinearSolver LS;
    SUNNonlinearSolver NLS;
    double *jac_nz;       /* the Jacobian's nonzeros */
    int method, nls, linsol;  /* of the CVODE memory in cv (linsol: the one chosen) */
    int ml, mu;           /* the Jacobian's lower and upper bandwidths (of its first nlead states) */
    int nlead;            /* the states before a tail that feeds nothing (nx: none) */
    double t_stop;        /* of the settings it was started with */
    /* where the integration is */
    double tn;            /* time CVODE has integrated to */
    int root_pending;     /* a root at t_root, not yet restarted from */
    double t_root;
    long steps_since_start;
    /* called after every internal step with its end (a root where the step
     * stopped at one); a nonzero return stops the integration */
    pdbfs_step_fn on_step;
    void *step_env;
    /* a user root function while pdbfs_cvode_roots runs (else the events) */
    pdbfs_root_fn user_root;
    void *root_env;
    int roots_changed;
    /* time events: the first nte event indicators are t - t_i, t_i switch
     * times known in advance (set by the caller after pdbfs_cvode_init);
     * CVODE stops at each (tstop) and restarts, so that no step jumps over one */
    int nte;
    double t_break;       /* the time event CVODE stops at next (INFINITY: none) */
    double *g;            /* ne event values */
    /* statistics since pdbfs_cvode_init (the steps of pdbfs_cvode_roots included) */
    long steps, roots, rhs_evals, jac_evals;
} PdbfsCvode;

/* The solver code the compiled drivers take: method | nls << 4 | linsol << 8. */
#define PDBFS_CODE_METHOD(c) ((c) & 15)
#define PDBFS_CODE_NLS(c) (((c) >> 4) & 15)
#define PDBFS_CODE_LINSOL(c) (((c) >> 8) & 15)
#define PDBFS_CODE_VALID(c) ((c) >= 0 && (c) < 4096 && PDBFS_CODE_METHOD(c) <= PDBFS_BDF \
                             && PDBFS_CODE_NLS(c) <= PDBFS_NLS_NEWTON \
                             && PDBFS_CODE_LINSOL(c) <= PDBFS_LS_BAND)

/* The CasADi work arrays of the given sizes (a generated header's
 * PDBFS_SZ_ARG, _RES, _IW, _W), in one block bound to ``ev`` (ev->p is the
 * caller's).  The block to free(), or NULL when out of memory. */
void *pdbfs_eval_alloc(PdbfsEval *ev, long sz_arg, long sz_res, long sz_iw, long sz_w);

/* Prepare ``s`` (no allocation yet). */
void pdbfs_cvode_init(PdbfsCvode *s, int nx, int ne, PdbfsEval *ev, pdbfs_log_fn log, void *env);

/* (Re)start at (t0, x0): a new CVODE memory if there is none or the method
 * changed, else CVodeReInit.  0 on success, else a CVODE flag (<0) or -100
 * for memory, with a message through the log callback; after a failure all
 * of CVODE's memory is freed (the next start builds it anew). */
int pdbfs_cvode_start(PdbfsCvode *s, const PdbfsCvodeSettings *set, double t0, const double *x0);

/* The next time event after t (INFINITY if none), from the event
 * indicators at (t, x); s->nte of them are time events. */
double pdbfs_next_time_event(PdbfsCvode *s, double t, const double *x);

/* Integrate to t_out (restarting at every root and time event on the way, at most
 * max_steps internal steps) and write the state at t_out into x_out.
 * ``horizon`` >= t_out is how far CVODE may look ahead (INFINITY: 1 s beyond
 * each (re)start, whatever t_out).  0 on success,
 * PDBFS_CV_TOO_MUCH_WORK, or CVODE's negative flag; s->tn is then the
 * time reached. */
int pdbfs_cvode_advance(PdbfsCvode *s, double t_out, double horizon, long max_steps, double *x_out);

/* Roots of g(t, x) on (t0, t1], integrating from (t0, x0): at most max,
 * with direction dir (-1 falling, +1 rising, 0 both), their times in
 * t_root, states in x_root (max x nx) and directions (+1 rising, -1
 * falling) in dir_root (may be NULL).  The number found, or a CVODE flag
 * (< 0).  The rig's own events are not roots here: pass an interval free of
 * them (a step of an earlier integration). */
int pdbfs_cvode_roots(PdbfsCvode *s, const PdbfsCvodeSettings *set, double t0, const double *x0,
                      double t1, pdbfs_root_fn g, void *env, int dir, int max, double *t_root,
                      double *x_root, int *dir_root);

/* Free CVODE's memory; ``s`` may be started again. */
void pdbfs_cvode_free(PdbfsCvode *s);

/* Newton's linear algebra (pdbfs_cvode_ls.c): the nonzeros of a CasADi
 * pattern; the pattern's nlead, ml and mu into s; the linear solver for the
 * settings' choice (band or dense LU); CVODE's Jacobian callback; the band
 * solver of s->A (the tail after nlead solved after the band LU) */
#ifndef PDBFS_NO_CVODE
casadi_int pdbfs_pattern_nnz(const casadi_int *sp, int nx);
void pdbfs_cvode_bandwidths(PdbfsCvode *s);
int pdbfs_cvode_choose_linsol(const PdbfsCvode *s, int asked);
int pdbfs_cvode_jac(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *ud,
                    N_Vector t1, N_Vector t2, N_Vector t3);
SUNLinearSolver pdbfs_cvode_band_solver(PdbfsCvode *s);
#endif

/* Call a generated function of (t, x, v, p) (v: z, or a rate); of (t, x, z, p) with z empty
 * (inline: the explicit method calls it at every stage) */
static inline int pdbfs_eval_txvp(PdbfsEval *ev, pdbfs_casadi_fn f, double t, const double *x,
                                  const double *v, double *out) {
    ev->arg[0] = &t;
    ev->arg[1] = x;
    ev->arg[2] = v;
    ev->arg[3] = ev->p;
    ev->res[0] = out;
    return f(ev->arg, ev->res, ev->iw, ev->w, 0);
}
static inline int pdbfs_eval_txp(PdbfsEval *ev, pdbfs_casadi_fn f, double t, const double *x,
                                 double *out) {
    return pdbfs_eval_txvp(ev, f, t, x, NULL, out);
}

#endif

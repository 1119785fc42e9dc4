/*
 * pdbfs_erk: an explicit Runge-Kutta integrator of order 8 (Dormand &
 * Prince's 8(5,3) pair, pdbfs_erk_table.h) with 7th-order dense output,
 * for rigs that are not stiff at the tolerances asked (method "erk").
 *
 * The rig's event indicators (contact onset and separation, a slack oil
 * column, a valve switching) are watched after every step; where one
 * changes sign its root is located on the step's dense output and the
 * integration restarts just past it (the right-hand side is not smooth
 * there), so no step straddles a kink.  The interface follows pdbfs_cvode.h
 * (start, advance to an output time, a callback after every step, the
 * same statistics), so the drivers use either.
 */
#ifndef PDBFS_ERK_H
#define PDBFS_ERK_H

#include <float.h>
#include <math.h>

#include "pdbfs_cvode.h"

/* the method code of the drivers (pdbfs_cvode.h has 0 Adams, 1 BDF) */
#define PDBFS_ERK 2

/* t_out within roundoff past t (a restart at a root just short of an output
 * time): no step is that short, the output is taken where the run is */
#define PDBFS_ERK_NEAR(t_out, t) ((t_out) - (t) <= 16.0 * DBL_EPSILON * fabs(t_out))

/* pdbfs_erk_advance's failure when the step size falls below roundoff (a
 * force blowing up, a rig too stiff for an explicit method); the drivers
 * report it as CVODE's CV_ERR_FAILURE (-3), its nearest cause */
#define PDBFS_ERK_STEP_UNDERFLOW (-30)

/* pdbfs_erk_advance's stop where the steps were held by stability
 * (PdbfsErk.stiff_after): s->t and s->y are where it stopped, short of t_out */
#define PDBFS_ERK_STIFF 7

typedef struct {
    int nx, ne;
    int nq;                   /* the last nq states are quadratures: integrals the
                               * right-hand side does not read, left out of the error
                               * test (their absolute tolerance must be huge) */
    PdbfsEval *ev;
    pdbfs_casadi_fn ode;      /* default pdbfs_ode */
    /* ode, the indicators and their rates in their versions for the run's
     * parameters (pdbfs_for_params): chosen at every start, not at every call */
    pdbfs_casadi_fn rhs, events, events_both;
    double rtol;
    const double *atol;       /* nx absolute tolerances */
    double max_step, t_stop;  /* 0: no limit; never steps past t_stop if finite */
    /* where the integration is: t, y, f(t, y); h the next step to try */
    double t, h, *y, *f;
    /* the last accepted step [t_old, t_old + h_old] (cut at a root: it ends
     * at t): its dense output */
    double t_old, h_old, *y_old, *dense;
    int dense_ready, fresh;   /* fresh: nothing integrated since the (re)start */
    int quiet;                /* the indicator restarted at (its sign is not looked at in the
                               * first step after: it is at its root, roundoff either side) */
    /* the indicators: where the step begins and where it ends (each ne values,
     * then their ne rates), at a point inside, and at two parts' ends */
    double *k, *ynew, *tmp, *acc, *g_old, *g_new, *g_tmp, *g_a, *g_b;
    pdbfs_step_fn on_step;    /* after every step (and at every restart), as pdbfs_cvode */
    void *step_env;
    int substeps;             /* > 1: on_step also sees substeps - 1 points inside each
                               * step, from the dense output (records as fine as CVODE's) */
    int lazy;                 /* 1: no dense output unless an indicator nears a root (or
                               * t_out is reached): on_step finds the step's stages in k
                               * (13 nx, pdbfs_erk_rows) when dense_ready is 0 (sweeps) */
    double err_prev;          /* the error of the step before (step control) */
    /* stiffness (co-simulation's method "auto"; stiff_after 0: off):
     * pdbfs_erk_advance stops (PDBFS_ERK_STIFF) once stiff_after steps in a
     * row were at least stiff_h long, a length at which the fastest mode's
     * |h lambda| is near the edge of the stability region: steps held by
     * stability rather than accuracy (a fast mode at rest, a fast decay) */
    int stiff_after, stiff_steps;
    double stiff_h;
    int kink_steps;           /* steps after a (re)start at a kink: step control for low order,
                               * their error checked by two half steps (the embedded estimate
                               * misses a force growing as d^1.5 from its onset) */
    /* a (re)start at a kink whose first step showed a law of low order (a
     * contact's onset): no step is longer than KINK_GRADE (pdbfs_erk.c) times its
     * distance from t_kink, up to which the embedded estimate holds (-inf: none) */
    double t_kink;
    double stiff_z;           /* |lambda| of the fastest mode, as the last step estimated it */
    double *half;             /* 17 nx: the two half steps' check (state, f and end; the
                               * step's end and stages meanwhile) */
    long steps, roots, rhs_evals, rejected;
    char msg[256];            /* the reason of the last failure */
} PdbfsErk;

/* Prepare ``s`` and allocate its memory; 0, or -100 when out of memory. */
int pdbfs_erk_init(PdbfsErk *s, int nx, int ne, PdbfsEval *ev);

/* (Re)start at (t0, x0) with these tolerances (set->rtol, set->atol,
 * set->max_step, set->t_stop; method and solvers are not used).  0, or
 * RC 1 when f(t0, x0) is not finite. */
int pdbfs_erk_start(PdbfsErk *s, const PdbfsCvodeSettings *set, double t0, const double *x0);

/* Integrate to t_out (at most max_steps steps) and write the state at t_out
 * into x_out (from the dense output).  0, PDBFS_CV_TOO_MUCH_WORK,
 * PDBFS_CV_STOPPED, PDBFS_ERK_STIFF, PDBFS_ERK_STEP_UNDERFLOW, or -3 (the
 * solution stopped being finite); s->t is then the time reached and s->msg
 * says why. */
int pdbfs_erk_advance(PdbfsErk *s, double t_out, long max_steps, double *x_out);

/* One step towards t_out (the dense output is made when the step reaches it),
 * then whoever watches the steps (on_step, substeps) sees it: 0,
 * PDBFS_ERK_AGAIN (no step taken: call again), or a failure as
 * pdbfs_erk_advance's.  pdbfs_erk_advance's loop, for drivers of their own
 * (pdbfs_erk_grid.c). */
#define PDBFS_ERK_AGAIN 1
int pdbfs_erk_step_watched(PdbfsErk *s, double t_out);

/* A step's dense output at theta in [0, 1]: y_old and the 7 x n polynomial
 * rows of the step (PdbfsErk.dense), n states, into out. */
void pdbfs_erk_poly(const double *y_old, const double *r, int n, double th, double *out);

/* The 7 x nx rows of a step's dense output (as PdbfsErk.dense) from its start
 * (t_old, y_old), length h, end state y_end and 13 stages k13 (as a lazy
 * run's k after the step): three more stages.  Uses s's memory, so only
 * after the integration.  0, or 1 when a stage is not finite. */
int pdbfs_erk_rows(PdbfsErk *s, double t_old, double h, const double *y_old,
                   const double *y_end, const double *k13, double *rows);

/* The state at time t in the last step (t_old <= t <= t), into out. */
void pdbfs_erk_dense(const PdbfsErk *s, double t, double *out);

void pdbfs_erk_free(PdbfsErk *s);

/* pdbfs_batch_run (pdbfs_batch.c) with the explicit Runge-Kutta method, its
 * arguments checked there (pdbfs_batch_erk.c); nx states (the rig's, or one
 * more: the contact force's impulse) */
int pdbfs_batch_run_erk(int nx, const double *p, const double *x0, long long nt, const double *t,
                        double *X, double rtol, double atol, double max_step,
                        long long max_num_steps, double *info, char *msg, long long msglen);

/* The dense output (y_old, rows: as pdbfs_erk_poly's, n states) of a step
 * [t_old, t_old + h_old] at the times t[k0 .. k1-1] (theta clipped to [0, 1]),
 * the first nout states into X[i * ld + k]: pdbfs_erk_poly's numbers,
 * computed for many times at once.  0, or the first k whose state is not
 * finite, + 1 (pdbfs_erk_grid.c) */
long pdbfs_erk_poly_times(const double *y_old, const double *rows, int n, int nout, double t_old,
                          double h_old, const double *t, long k0, long k1, double *X, long ld);

/* The integration from where s started (t[0]) over the output grid t[1 ..
 * nt-1] (strictly increasing), the first nout states at t[k] written into
 * X[i * ld + k]: the numbers and the steps of pdbfs_erk_advance at every
 * output time, with at most max_steps steps between two of them.  Returns
 * as pdbfs_erk_advance; *reached: the outputs written (k < *reached).
 * X NULL: the same steps, nothing written (and no dense output asked for)
 * (pdbfs_erk_grid.c, with the drivers of one simulation) */
int pdbfs_erk_grid(PdbfsErk *s, long nt, const double *t, int nout, double *X, long ld,
                   long max_steps, long *reached);

#endif

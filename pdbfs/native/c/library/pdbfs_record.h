/*
 * The solution's record of a summary (pdbfs_summary.c) and the refinements
 * on it: the state and the roles after every internal CVODE step, and the
 * roots of a quantity on a recorded step, integrated again from its start
 * with CVODE's root finding.  Everything on the heap, grown as needed.
 */
#ifndef PDBFS_RECORD_H
#define PDBFS_RECORD_H

#include "pdbfs_batch_model.h"
#include "pdbfs_cvode.h"
#include "pdbfs_erk.h"

#define NR PDBFS_NR
#define NRX (NR > 0 ? NR : 1)
#define NQ (PDBFS_ROLE_FORCE >= 0 ? 1 : 0)   /* the contact force's integral */
#define NXQ (PDBFS_NX + NQ)
#define MAXR 8                                /* roots of one refined step, to start with */
#define NLX (PDBFS_NL > 0 ? PDBFS_NL : 1)     /* the variables' limits (pdbfs_limits) */
/* a limit reached (the run's code, pdbfs.simulation.compiled.RC_LIMIT): a variable
 * declared with min or max left its range; the message is pdbfs_limit_message's */
#define RC_LIMIT 8
/* a failed run whose last record has a limit within this fraction of its value
 * at the start: the solver failed as the variable reached its bound */
#define LIMIT_NEAR 1e-3
/* a record growing past RECORD_ASK bytes asks the memory probe (set by
 * pdbfs_set_memory_probe: bytes this process may still take, < 0 unknown) and
 * grows only within RECORD_SHARE of it: else the run stops, out of memory,
 * before the system would kill the process (its allocations succeed on credit) */
#define RECORD_ASK (64.0 * 1048576.0)
#define RECORD_SHARE 0.8
typedef double (*pdbfs_probe_fn)(void);
/* per record of an explicit Runge-Kutta run: its step's t_old, h_old, what
 * follows (DN_*), y_old (NXQ), and its dense output (7 NXQ) or, for a lazy
 * run, its 13 stages (13 NXQ: the dense output made from them when needed) */
#define DNREC (3 + 14 * NXQ)
#define DN_NONE 0.0
#define DN_ROWS 1.0
#define DN_STAGES 2.0

typedef struct {
    double *t, *x, *r;        /* per record: time, state (NXQ), roles (NR) */
    long n, cap;
    int oom, bad;             /* out of memory; a role not finite */
    PdbfsEval *ev;
    PdbfsCvode *cv;           /* for the refinements */
    const PdbfsCvodeSettings *set;
    /* the roots of the last refinement: times, states (NXQ each), directions; room for rcap */
    double *rt, *rx;
    int *rd, rcap;
    /* an explicit Runge-Kutta run (else NULL): each record keeps its step's dense
     * output (dn, DNREC per record), and refinements are root finding on it, not
     * integrations again */
    PdbfsErk *rk;
    double *dn;
    double *rdot;             /* with rk: the roles' rates per record (NR each) */
    int limit;                /* 0, or 1 + the limit record limit_k is outside of */
    long limit_k;
} History;

/* record k's step with its dense output (made now from its stages, on the
 * integrator's memory, for a lazy run's step): the record's DNREC entries;
 * NULL when a stage is not finite */
const double *pdbfs_step_dense(History *H, long k);

/* a run kept for its trajectory (pdbfs_run_summary.c, pdbfs_run_trajectory.c):
 * its evaluation memory, integrator (its memory makes dense output from a
 * record's stages) and record; mem: tolerances, states and p */
typedef struct {
    PdbfsEval ev;
    void *work;
    PdbfsErk rk;
    History H;
    double *mem;
} Kept;

void pdbfs_kept_free(Kept *K);

/* crossings of a level: times, directions (+1 up, -1 down), states (NXQ each) */
typedef struct {
    double *t, *x;
    int *dir;
    long n, cap;
} Crossings;

#define R(H, k, j) ((H)->r[(k) * NRX + (j)])

/* the step callback of pdbfs_cvode (env: a History): keep (t, x) and its roles */
int pdbfs_record_step(void *env, double t, const double *x);

/* A run that stopped (code != 0) with a limit reached (H->limit, set by
 * pdbfs_record_step) or nearly reached at its last record (within LIMIT_NEAR
 * of its value at the first): msg (len) gets "limit <j> crossed at t = <t>",
 * the crossing located on the recorded step, or "limit <j> near at t = <t>
 * value <g>", and RC_LIMIT is returned; else code. */
int pdbfs_limit_message(History *H, int code, char *msg, size_t len);

/* A run that failed at (t, x), started at (t0, x0): a limit within LIMIT_NEAR of
 * its value at the start writes "limit <j> near at t = <t> value <g>" to msg
 * (len) and gives 1; else 0 (the drivers without a record, pdbfs_batch*.c) */
int pdbfs_limit_near(PdbfsEval *ev, double t0, const double *x0, double t, const double *x,
                     char *msg, size_t len);

/* the largest value of role j over records k0 .. k1-1, refined where its slope
 * turns: its time, value and (x_pk not NULL) state; -1 when out of memory */
int pdbfs_peak(History *H, int j, long k0, long k1, double *t_pk, double *v_pk, double *x_pk);

/* every crossing of role j through level (both directions), in time order,
 * appended to c; -1 when out of memory, -2 when a step's crossings do not
 * lead from one side to the other (integrated again, the step shows others) */
int pdbfs_crossings(History *H, int j, double level, Crossings *c);

void pdbfs_free_crossings(Crossings *c);

/* CVODE's settings for a summary run of ``method`` (a pdbfs method code); with
 * the explicit method (erk) those of the refinements' Adams */
void pdbfs_summary_settings(PdbfsCvodeSettings *set, int method, int erk, double rtol,
                            double *atolv, double max_step, double t_stop);

/* the history's arrays, freed (the History itself is the caller's) */
void pdbfs_free_history(History *H);

/* a new record (arrays NULL, H->rk set) starts with the memory of the record
 * a run of this library released last, if any (pdbfs_record_pool.c) */
void pdbfs_record_adopt(History *H);

/* the record's arrays kept for the next run (not freed up to a size); NULL after */
void pdbfs_record_release(History *H);

#endif

/*
 * A rig's sizes as the library's drivers read them.  The drivers are the
 * same for every rig and compiled once per machine (simulation/run/
 * compiled_build.py); a rig's library links them with the rig's own model
 * functions (pdbfs_model_funcs.c) and with pdbfs_rig, its sizes, generated
 * beside them (pdbfs_batch_model.c).  So the names below are run-time
 * values of the rig at hand, not constants of the compilation.
 */
#ifndef PDBFS_BATCH_MODEL_H
#define PDBFS_BATCH_MODEL_H

typedef struct {
    int nx, np, ne;       /* states, parameters, event indicators */
    int nr;               /* the summary's roles the rig has */
    /* the output index of each role among them, -1 when the rig lacks it */
    int role_pressure, role_force, role_disp, role_velocity;
    int nl;               /* the variables' declared ranges (pdbfs_limits) */
    int nte;              /* the first nte events are time events: t - t_i */
    /* how the summary follows a pulse cut off at t_end (summary_run.py's grid
     * and look-ahead): its step (s), window (samples), horizons and windows */
    double summary_step;
    int follow_window;
    double follow_horizons;
    int follow_windows;
    long sz_arg, sz_res, sz_iw, sz_w;    /* the CasADi work arrays the functions need */
} PdbfsRig;

/* hidden: the library's own (its drivers reach it without indirection) */
extern const PdbfsRig pdbfs_rig __attribute__((visibility("hidden")));

#define PDBFS_NX (pdbfs_rig.nx)
#define PDBFS_NP (pdbfs_rig.np)
#define PDBFS_NE (pdbfs_rig.ne)
#define PDBFS_NR (pdbfs_rig.nr)
#define PDBFS_ROLE_PRESSURE (pdbfs_rig.role_pressure)
#define PDBFS_ROLE_FORCE (pdbfs_rig.role_force)
#define PDBFS_ROLE_DISP (pdbfs_rig.role_disp)
#define PDBFS_ROLE_VELOCITY (pdbfs_rig.role_velocity)
#define PDBFS_NL (pdbfs_rig.nl)
#define PDBFS_NTE (pdbfs_rig.nte)
#define PDBFS_SUMMARY_STEP (pdbfs_rig.summary_step)
#define PDBFS_FOLLOW_WINDOW (pdbfs_rig.follow_window)
#define PDBFS_FOLLOW_HORIZONS (pdbfs_rig.follow_horizons)
#define PDBFS_FOLLOW_WINDOWS (pdbfs_rig.follow_windows)
#define PDBFS_SZ_ARG (pdbfs_rig.sz_arg)
#define PDBFS_SZ_RES (pdbfs_rig.sz_res)
#define PDBFS_SZ_IW (pdbfs_rig.sz_iw)
#define PDBFS_SZ_W (pdbfs_rig.sz_w)

#endif

/*
 * pdbfs_modes: the modes of a rig at a state, for method "auto": the
 * eigenvalues of d(ode)/dx (pdbfs_jac, dense for any pattern), reduced to
 * Hessenberg form by Householder reflections, then Francis' double-shift QR.
 * Shared by the compiled backend (its method choice, as fast as a run) and
 * the FMU (its co-simulation's choice at initialisation).
 */
#ifndef PDBFS_MODES_H
#define PDBFS_MODES_H

#include <stddef.h>

#include "pdbfs_cvode.h"

/* doubles of work pdbfs_modes_at needs for the rig's n states */
size_t pdbfs_modes_work(int n);

/* The modes of d(ode)/dx at (t, x), n states: *fastest the largest modulus
 * of an eigenvalue, *rate the fastest decay of a mode that does not
 * oscillate (-Re lambda where |Re lambda| > |Im lambda|, else 0), *osc the
 * largest modulus of a mode that does (|Im lambda| >= |Re lambda|).  0; 1
 * when the Jacobian is not finite there (no modes: all 0); -1 when the
 * eigenvalues did not converge.  work: pdbfs_modes_work(n) doubles. */
int pdbfs_modes_at(PdbfsEval *ev, int n, double t, const double *x, double *work,
                   double *fastest, double *rate, double *osc);

#endif

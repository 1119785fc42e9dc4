/* pdbfs_cvode_ls: Newton's linear algebra for pdbfs_cvode.c: the Jacobian
 * from CasADi's sparse pattern into a dense or band matrix, the choice
 * between them, and a band solver for a Jacobian whose last states feed
 * nothing (the summary's impulse: its row couples it to the contact's
 * states, far from the diagonal, and its column is empty).  Such a tail is
 * left out of the band and solved exactly after it: with M = I - gamma J,
 * its rows read x_r = b_r + gamma sum_j J_rj x_j over states j before it. */
#include <math.h>
#include <stdlib.h>

#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "pdbfs_cvode.h"

/* CasADi writes a dense pattern compressed, {nrow, ncol, 1}, where a sparse
 * one starts its column offsets with 0: the nonzeros then run column by column */
static int dense_pattern(const casadi_int *sp) { return sp[2] == 1; }

casadi_int pdbfs_pattern_nnz(const casadi_int *sp, int nx) {
    return dense_pattern(sp) ? (casadi_int)nx * nx : sp[2 + nx];
}

/* row of the k-th nonzero, which lies in column j */
static casadi_int pattern_row(const casadi_int *sp, int nx, casadi_int j, casadi_int k) {
    return dense_pattern(sp) ? k - j * nx : sp[3 + nx + k];
}

static casadi_int col_start(const casadi_int *sp, int nx, casadi_int j) {
    return dense_pattern(sp) ? j * nx : sp[2 + j];
}

int pdbfs_cvode_jac(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *ud,
                    N_Vector t1, N_Vector t2, N_Vector t3) {
    PdbfsCvode *s = (PdbfsCvode *)ud;
    const casadi_int *sp = s->jac_sp;
    casadi_int j, k, nnz = pdbfs_pattern_nnz(sp, s->nx);
    int band = SUNMatGetID(J) == SUNMATRIX_BAND;
    const double *yd = N_VGetArrayPointer(y);
    (void)fy; (void)t1; (void)t2; (void)t3;
    s->jac_evals++;
    if (pdbfs_eval_txp(s->ev, s->jac, t, yd, s->jac_nz)) return -1;
    for (k = 0; k < nnz; k++)
        if (!isfinite(s->jac_nz[k])) return 1;
    SUNMatZero(J);
    for (j = 0; j < s->nx; j++)
        for (k = col_start(sp, s->nx, j); k < col_start(sp, s->nx, j + 1); k++) {
            casadi_int r = pattern_row(sp, s->nx, j, k);
            if (!band) SM_ELEMENT_D(J, r, j) = s->jac_nz[k];
            else if (r < s->nlead) SM_ELEMENT_B(J, r, j) = s->jac_nz[k];   /* the tail: after the band */
        }
    return 0;
}

/* nlead: the states before the tail whose columns are empty (nx: no
 * tail); ml, mu: the bandwidths of the rest */
void pdbfs_cvode_bandwidths(PdbfsCvode *s) {
    const casadi_int *sp = s->jac_sp;
    casadi_int j, k;
    s->ml = s->mu = 0;
    for (s->nlead = s->nx; s->nlead > 0; s->nlead--)
        if (col_start(sp, s->nx, s->nlead) > col_start(sp, s->nx, s->nlead - 1)) break;
    for (j = 0; j < s->nlead; j++)
        for (k = col_start(sp, s->nx, j); k < col_start(sp, s->nx, j + 1); k++) {
            casadi_int r = pattern_row(sp, s->nx, j, k);
            if (r >= s->nlead) continue;
            if (r - j > s->ml) s->ml = (int)(r - j);
            if (j - r > s->mu) s->mu = (int)(j - r);
        }
}

/* band LU costs about nx*ml*(ml+mu) against nx^3/3 dense, and stores
 * nx*(2*ml+mu+1) numbers against nx^2: band when it stores under half */
int pdbfs_cvode_choose_linsol(const PdbfsCvode *s, int asked) {
    if (asked == PDBFS_LS_DENSE || asked == PDBFS_LS_BAND) return asked;
    return 2 * (2 * s->ml + s->mu + 1) < s->nx ? PDBFS_LS_BAND : PDBFS_LS_DENSE;
}

/* ---------------------------------------- band LU, then the tail's rows */
typedef struct {
    SUNLinearSolver band;
    PdbfsCvode *s;
    double gamma;            /* of the matrix the band LU factored */
} Tailed;

#define TAILED(LS) ((Tailed *)(LS)->content)

static SUNLinearSolver_Type tailed_type(SUNLinearSolver LS) { (void)LS; return SUNLINEARSOLVER_DIRECT; }
static SUNLinearSolver_ID tailed_id(SUNLinearSolver LS) { (void)LS; return SUNLINEARSOLVER_CUSTOM; }
static SUNErrCode tailed_init(SUNLinearSolver LS) { return SUNLinSolInitialize(TAILED(LS)->band); }
static sunindextype tailed_lastflag(SUNLinearSolver LS) { return SUNLinSolLastFlag(TAILED(LS)->band); }

static int tailed_setup(SUNLinearSolver LS, SUNMatrix A) {
    Tailed *c = TAILED(LS);
    /* CVODE forms M = I - gamma J with its current gamma just before this */
    if (CVodeGetCurrentGamma(c->s->cv, &c->gamma) != CV_SUCCESS) return -1;
    return SUNLinSolSetup(c->band, A);
}

static int tailed_solve(SUNLinearSolver LS, SUNMatrix A, N_Vector x, N_Vector b, sunrealtype tol) {
    Tailed *c = TAILED(LS);
    PdbfsCvode *s = c->s;
    const casadi_int *sp = s->jac_sp;
    casadi_int j, k;
    double *xv = N_VGetArrayPointer(x);
    int flag = SUNLinSolSolve(c->band, A, x, b, tol);
    if (flag) return flag;
    for (j = 0; j < s->nlead; j++)
        for (k = col_start(sp, s->nx, j); k < col_start(sp, s->nx, j + 1); k++) {
            casadi_int r = pattern_row(sp, s->nx, j, k);
            if (r >= s->nlead) xv[r] += c->gamma * s->jac_nz[k] * xv[j];
        }
    return 0;
}

static SUNErrCode tailed_free(SUNLinearSolver LS) {
    if (!LS) return SUN_SUCCESS;
    if (LS->content) {
        SUNLinSolFree(TAILED(LS)->band);
        free(LS->content);
        LS->content = NULL;
    }
    SUNLinSolFreeEmpty(LS);
    return SUN_SUCCESS;
}

/* the band solver of s->A, with the tail solved after it when there is one;
 * NULL when out of memory */
SUNLinearSolver pdbfs_cvode_band_solver(PdbfsCvode *s) {
    SUNLinearSolver band = SUNLinSol_Band(s->y, s->A, s->ctx), LS;
    Tailed *c;
    if (!band || s->nlead == s->nx) return band;
    LS = SUNLinSolNewEmpty(s->ctx);
    c = LS ? malloc(sizeof *c) : NULL;
    if (!c) {
        if (LS) SUNLinSolFreeEmpty(LS);
        SUNLinSolFree(band);
        return NULL;
    }
    c->band = band;
    c->s = s;
    c->gamma = 0.0;
    LS->content = c;
    LS->ops->gettype = tailed_type;
    LS->ops->getid = tailed_id;
    LS->ops->initialize = tailed_init;
    LS->ops->setup = tailed_setup;
    LS->ops->solve = tailed_solve;
    LS->ops->lastflag = tailed_lastflag;
    LS->ops->free = tailed_free;
    return LS;
}

/* The SUNDIALS backends' nonlinear and linear solvers, chosen at creation: Adams' fixed-point
 * iteration; BDF's and ark-imex's Newton iteration (ARKStep's default nonlinear solver) with a
 * dense, Krylov or sparse (cvode_sparse.c) linear solver, attached through tb__sundials_ops. */
#include "ode/cvode_internal.h"

#include "core/detail.h"

#include <cvode/cvode.h>
#include <cvode/cvode_bandpre.h>
#include <cvode/cvode_ls.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_spgmr.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

/* TB_LINEAR_SOLVER_AUTO picks the dense solver up to this many unknowns, and up to the coupled
 * limit for a system without blocks, whose Krylov solver gets only a banded preconditioner: a
 * box on a box on the ground with its contact's friction states (78 unknowns, the states at the
 * end of y coupled to the bodies outside the band) took it 80000 steps for 0.01 s, and the
 * dense solver 4400 for 1 s; the four head-on pairs of examples/scenes/head_on_pairs.json (248
 * unknowns) drifted 6.6e-4 in momentum over 16368 steps, dense: 260 steps, momentum to 5e-16. */
#define TB__DENSE_LIMIT 64
#define TB__DENSE_LIMIT_COUPLED 512

/* Adams: fixed-point iteration, no linear algebra. BDF, ark-imex: Newton with a dense, Krylov or
 * sparse linear solver. */
tb_status tb__cvode_set_solvers(tb_integrator *integrator, const tb_integrator_def *def,
                                tb_error *error)
{
    tb__cvode *cvode = integrator->cvode;
    const size_t n = integrator->system.n;
    if (integrator->method == TB_METHOD_CVODE_ADAMS) {
        cvode->nonlinear = SUNNonlinSol_FixedPoint(cvode->y, 0, cvode->context);
        if (cvode->nonlinear == NULL) {
            return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "fixed-point solver");
        }
        const int flag = CVodeSetNonlinearSolver(cvode->mem, cvode->nonlinear);
        return flag == CV_SUCCESS
                   ? TB_STATUS_OK
                   : tb__cvode_setup_failed(cvode, "CVodeSetNonlinearSolver", flag, error);
    }
    const bool dense =
        def->linear_solver == TB_LINEAR_SOLVER_DENSE ||
        (def->linear_solver == TB_LINEAR_SOLVER_AUTO &&
         n <= (integrator->system.blocks.size > 0 ? TB__DENSE_LIMIT : TB__DENSE_LIMIT_COUPLED));
    const int band =
        def->preconditioner_half_bandwidth < 0 ? 0 : def->preconditioner_half_bandwidth;
    if (def->linear_solver == TB_LINEAR_SOLVER_SPARSE) {
        const tb_status status = tb__cvode_sparse_create(integrator, error);
        if (status != TB_STATUS_OK) {
            return status;
        }
    } else if (dense) {
        cvode->matrix = SUNDenseMatrix((sunindextype)n, (sunindextype)n, cvode->context);
        cvode->linear =
            cvode->matrix == NULL ? NULL : SUNLinSol_Dense(cvode->y, cvode->matrix, cvode->context);
    } else {
        cvode->linear = SUNLinSol_SPGMR(cvode->y, SUN_PREC_LEFT, 0, cvode->context);
    }
    if (cvode->linear == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "linear solver for n = %zu", n);
    }
    const tb__sundials_ops *ops = cvode->ops;
    int flag = ops->set_linear_solver(cvode->mem, cvode->linear, cvode->matrix);
    const size_t block_size = integrator->system.blocks.size;
    if (flag == CV_SUCCESS && (dense || block_size > 0)) {
        cvode->weights = N_VClone(cvode->y);
        flag = cvode->weights == NULL ? CV_MEM_FAIL : CV_SUCCESS;
    }
    if (flag == CV_SUCCESS && cvode->sparse != NULL) {
        flag = ops->set_jac_fn(cvode->mem, tb__cvode_sparse_jacobian);
    } else if (flag == CV_SUCCESS && dense) {
        flag = ops->set_jac_fn(cvode->mem, tb__cvode_dense_jacobian);
    } else if (flag == CV_SUCCESS && block_size > 0) {
        cvode->block_preconditioner = tb__block_preconditioner_create(n, block_size);
        flag =
            cvode->block_preconditioner == NULL
                ? CV_MEM_FAIL
                : ops->set_preconditioner(cvode->mem, tb__cvode_block_setup, tb__cvode_block_solve);
    } else if (flag == CV_SUCCESS) {
        flag = ops->band_prec_init(cvode->mem, (sunindextype)n, band, band);
        cvode->band_preconditioner = flag == CV_SUCCESS;
    }
    return flag == CV_SUCCESS ? TB_STATUS_OK
                              : tb__cvode_setup_failed(cvode, "SetLinearSolver", flag, error);
}

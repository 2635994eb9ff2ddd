/* Adaptive, error-controlled integration with SUNDIALS CVODE (Adams and BDF) as a backend of
 * the generic ODE layer: CVODE's memory, its calls in the shared table (tb__sundials_ops) and its
 * counters; the stepping is shared with ARKStep (cvode_run.c), and so are the callbacks
 * (cvode_callbacks.c). The cvode_* and arkode_* files are the only ones that include SUNDIALS
 * headers. SUNDIALS 6.x (what Debian 12 ships) is the target; 7.x differences sit behind
 * SUNDIALS_VERSION_MAJOR. */
#include "ode/cvode_internal.h"

#include "core/detail.h"

#include <cvode/cvode.h>
#include <cvode/cvode_bandpre.h>
#include <cvode/cvode_ls.h>
#include <cvode/cvode_proj.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>

#include <stdbool.h>
#include <stdlib.h>

static int cvode_reinit(tb_integrator *integrator)
{
    return CVodeReInit(integrator->cvode->mem, 0.0, integrator->cvode->y);
}

static void cvode_free(void **mem)
{
    CVodeFree(mem);
}

/* CVODE's counters since its last (re)start. */
static void read_counters(const tb_integrator *integrator, tb_integrator_stats *out)
{
    const tb__cvode *cvode = integrator->cvode;
    void *mem = cvode->mem;
    long rhs = 0, linear_rhs = 0, band_rhs = 0;
    sunrealtype last = 0, current = 0;
    CVodeGetNumSteps(mem, &out->steps);
    CVodeGetNumRhsEvals(mem, &rhs);
    CVodeGetNumErrTestFails(mem, &out->error_test_failures);
    CVodeGetNumNonlinSolvConvFails(mem, &out->nonlinear_failures);
    CVodeGetLastStep(mem, &last);
    CVodeGetCurrentStep(mem, &current);
    CVodeGetLastOrder(mem, &out->last_order);
    CVodeGetCurrentOrder(mem, &out->current_order);
    if (cvode->linear != NULL) {
        CVodeGetNumLinRhsEvals(mem, &linear_rhs);
        CVodeGetNumLinIters(mem, &out->linear_iterations);
    }
    if (cvode->band_preconditioner) {
        CVBandPrecGetNumRhsEvals(mem, &band_rhs);
    }
    out->jacobian_derivative_evals = linear_rhs + band_rhs;
    out->derivative_evals = rhs + out->jacobian_derivative_evals;
    out->last_step = last;
    out->current_step = current;
    CVodeGetNumNonlinSolvIters(mem, &out->nonlinear_iterations);
    if (cvode->matrix != NULL) {
        CVodeGetNumJacEvals(mem, &out->jacobian_evals);
    }
}

static const tb__sundials_ops cvode_ops = {
    .name = "CVODE",
    .evolve = CVode,
    .get_dky = CVodeGetDky,
    .current_time = CVodeGetCurrentTime,
    .current_step = CVodeGetCurrentStep,
    .err_weights = CVodeGetErrWeights,
    .set_stop_time = CVodeSetStopTime,
    .root_init = CVodeRootInit,
    .no_inactive_root_warn = CVodeSetNoInactiveRootWarn,
    .root_info = CVodeGetRootInfo,
    .ss_tolerances = CVodeSStolerances,
    .sv_tolerances = CVodeSVtolerances,
    .set_max_num_steps = CVodeSetMaxNumSteps,
    .set_init_step = CVodeSetInitStep,
    .set_max_step = CVodeSetMaxStep,
    .set_linear_solver = CVodeSetLinearSolver,
    .set_jac_fn = CVodeSetJacFn,
    .set_preconditioner = CVodeSetPreconditioner,
    .band_prec_init = CVBandPrecInit,
    .band_prec_rhs_evals = CVBandPrecGetNumRhsEvals,
    .flag_name = CVodeGetReturnFlagName,
    .hook_flags = {CV_PROJFUNC_FAIL, CV_REPTD_PROJFUNC_ERR},
    .reinit = cvode_reinit,
    .read_counters = read_counters,
    .free_mem = cvode_free,
};

static tb_status create_memory(tb_integrator *integrator, const tb_integrator_def *def,
                               tb_error *error)
{
    tb__cvode *cvode = integrator->cvode;
    cvode->mem =
        CVodeCreate(integrator->method == TB_METHOD_CVODE_BDF ? CV_BDF : CV_ADAMS, cvode->context);
    if (cvode->mem == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "CVODE memory for n = %zu",
                             integrator->system.n);
    }
#if SUNDIALS_VERSION_MAJOR < 7
    CVodeSetErrHandlerFn(cvode->mem, tb__sundials_capture_message, cvode);
#endif
    /* before CVodeInit, which allocates the history for the largest order */
    int flag = def->max_order > 0 ? CVodeSetMaxOrd(cvode->mem, def->max_order) : CV_SUCCESS;
    if (flag != CV_SUCCESS) {
        return tb__cvode_setup_failed(cvode, "CVodeSetMaxOrd", flag, error);
    }
    cvode->implicit_rhs = tb__cvode_derivative;
    flag = CVodeInit(cvode->mem, tb__cvode_derivative, 0.0, cvode->y);
    if (flag == CV_SUCCESS) {
        flag = CVodeSetUserData(cvode->mem, integrator);
    }
    return flag == CV_SUCCESS ? TB_STATUS_OK
                              : tb__cvode_setup_failed(cvode, "CVodeInit", flag, error);
}

/* SUNDIALS 6 projects with BDF only; Adams outputs are renormalised instead. */
static tb_status set_projection(tb_integrator *integrator, const tb_integrator_def *def,
                                tb_error *error)
{
    (void)def;
    tb__cvode *cvode = integrator->cvode;
    if (integrator->system.post_step == NULL || integrator->method != TB_METHOD_CVODE_BDF) {
        return TB_STATUS_OK;
    }
    int flag = CVodeSetProjFn(cvode->mem, tb__cvode_project);
    if (flag == CV_SUCCESS) {
        flag = CVodeSetProjErrEst(cvode->mem, SUNFALSE);
    }
    return flag == CV_SUCCESS ? TB_STATUS_OK
                              : tb__cvode_setup_failed(cvode, "CVodeSetProjFn", flag, error);
}

static tb_status cvode_create(tb_integrator *integrator, const tb_integrator_def *def,
                              tb_error *error)
{
    return tb__sundials_make(integrator, def, &cvode_ops, create_memory, set_projection, error);
}

const tb__backend tb__cvode_backend = {
    cvode_create,       tb__sundials_advance,   tb__sundials_step,
    tb__sundials_reset, tb__sundials_get_stats, tb__sundials_destroy,
};

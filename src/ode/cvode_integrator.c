/* Adaptive, error-controlled integration with SUNDIALS CVODE (Adams and BDF) as a backend of
 * the generic ODE layer: creation, stepping, statistics (callbacks in cvode_callbacks.c). The
 * cvode_* files are the only ones that include SUNDIALS headers. SUNDIALS 6.x (what Debian 12
 * ships) is the target; 7.x differences sit behind SUNDIALS_VERSION_MAJOR. */
#include "ode/cvode_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <cvode/cvode.h>
#include <cvode/cvode_bandpre.h>
#include <cvode/cvode_ls.h>
#include <cvode/cvode_proj.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_spgmr.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* --- messages ----------------------------------------------------------------------------- */

#if SUNDIALS_VERSION_MAJOR >= 7
static void capture_message(int line, const char *function, const char *file, const char *msg,
                            SUNErrCode code, void *data, SUNContext context)
{
    (void)line, (void)file, (void)code, (void)context;
    tb__cvode *cvode = data;
    snprintf(cvode->message, sizeof cvode->message, "%s: %s", function, msg);
}
#else
static void capture_message(int code, const char *module, const char *function, char *msg,
                            void *data)
{
    (void)code, (void)module;
    tb__cvode *cvode = data;
    snprintf(cvode->message, sizeof cvode->message, "%s: %s", function, msg);
}
#endif

/* --- creation ----------------------------------------------------------------------------- */

/* The system's right-hand-side generation; 0 for a system that does not have one. */
static unsigned long long rhs_generation(const tb_ode_system *system)
{
    return system->lifetime.rhs_generation != NULL ? system->lifetime.rhs_generation(system->ctx)
                                                   : 0;
}

/* Formats CVODE's name for a return flag (CVodeGetReturnFlagName allocates it). */
static void flag_name(int flag, char *out, size_t size)
{
    char *name = CVodeGetReturnFlagName(flag);
    snprintf(out, size, "%s", name != NULL ? name : "unknown CVODE flag");
    free(name);
}

tb_status tb__cvode_setup_failed(tb__cvode *cvode, const char *call, int flag, tb_error *error)
{
    char name[64];
    flag_name(flag, name, sizeof name);
    return tb__set_error(error, TB_STATUS_SOLVER_FAILED, "CVODE set-up: %s returned %s%s%s", call,
                         name, cvode->message[0] ? ": " : "", cvode->message);
}

/* A finite value >= minimum (> minimum when strict); names the field. */
static tb_status check_bound(double value, double minimum, bool strict, const char *field,
                             tb_error *error)
{
    if (!isfinite(value)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE, "def.%s: must be finite, got %g", field,
                             value);
    }
    if (strict ? !(value > minimum) : !(value >= minimum)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT, "def.%s: must be %s %g, got %g",
                             field, strict ? ">" : ">=", minimum, value);
    }
    return TB_STATUS_OK;
}

static tb_status validate_tolerances(const tb_integrator *integrator, const tb_integrator_def *def,
                                     tb_error *error)
{
    if (!isfinite(def->rtol)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE, "def.rtol: must be finite, got %g",
                             def->rtol);
    }
    if (!(def->rtol >= 1e-15 && def->rtol < 1.0)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.rtol: must be in [1e-15, 1), got %g", def->rtol);
    }
    tb_status status = check_bound(def->atol, 0.0, false, "atol", error);
    for (size_t i = 0;
         status == TB_STATUS_OK && def->atol_vector != NULL && i < integrator->system.n; ++i) {
        char field[48];
        snprintf(field, sizeof field, "atol_vector[%zu]", i);
        status = check_bound(def->atol_vector[i], 0.0, false, field, error);
    }
    return status;
}

static tb_status validate(const tb_integrator *integrator, const tb_integrator_def *def,
                          tb_error *error)
{
    const size_t n = integrator->system.n;
    const int max_order = integrator->entry->info.order;
    tb_status status = validate_tolerances(integrator, def, error);
    if (status == TB_STATUS_OK) {
        status = check_bound(def->initial_step, 0.0, false, "initial_step", error);
    }
    if (status == TB_STATUS_OK) {
        status = check_bound(def->max_step, 0.0, false, "max_step", error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (def->max_order < 0 || def->max_order > max_order) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.max_order: must be in [0, %d] for %s, got %d", max_order,
                             integrator->entry->info.name, def->max_order);
    }
    if ((int)def->linear_solver < 0 || def->linear_solver > TB_LINEAR_SOLVER_SPARSE) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.linear_solver: unknown solver %d", (int)def->linear_solver);
    }
    if (def->preconditioner_half_bandwidth >= (long)n) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.preconditioner_half_bandwidth: must be < n = %zu, got %d", n,
                             def->preconditioner_half_bandwidth);
    }
    return TB_STATUS_OK;
}

static tb_status set_tolerances(tb__cvode *cvode, const tb_integrator_def *def, size_t n,
                                tb_error *error)
{
    int flag;
    if (def->atol_vector != NULL) {
        N_Vector atol = N_VNew_Serial((sunindextype)n, cvode->context);
        if (atol == NULL) {
            return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "tolerance vector");
        }
        memcpy(N_VGetArrayPointer(atol), def->atol_vector, n * sizeof(double));
        flag = CVodeSVtolerances(cvode->mem, def->rtol, atol);
        N_VDestroy(atol); /* CVODE keeps a copy of its own */
    } else {
        const double atol = def->atol > 0 ? def->atol : 1e-3 * def->rtol;
        flag = CVodeSStolerances(cvode->mem, def->rtol, atol);
    }
    return flag == CV_SUCCESS ? TB_STATUS_OK
                              : tb__cvode_setup_failed(cvode, "CVodeSetTolerances", flag, error);
}

static tb_status set_options(tb__cvode *cvode, const tb_integrator_def *def, tb_error *error)
{
    int flag = CVodeSetMaxNumSteps(cvode->mem, def->max_steps);
    if (flag == CV_SUCCESS && def->initial_step > 0) {
        flag = CVodeSetInitStep(cvode->mem, def->initial_step);
    }
    if (flag == CV_SUCCESS && def->max_step > 0) {
        flag = CVodeSetMaxStep(cvode->mem, def->max_step);
    }
    return flag == CV_SUCCESS ? TB_STATUS_OK
                              : tb__cvode_setup_failed(cvode, "CVodeSetOptions", flag, error);
}

static void cvode_destroy(tb_integrator *integrator)
{
    tb__cvode *cvode = integrator->cvode;
    if (cvode == NULL) {
        return;
    }
    CVodeFree(&cvode->mem);
    SUNNonlinSolFree(cvode->nonlinear);
    SUNLinSolFree(cvode->linear);
    SUNMatDestroy(cvode->matrix);
    if (cvode->weights != NULL) {
        N_VDestroy(cvode->weights);
    }
    tb__block_preconditioner_destroy(cvode->block_preconditioner);
    tb__cvode_sparse_free(cvode);
    tb__cvode_events_free(cvode);
    if (cvode->y != NULL) {
        N_VDestroy(cvode->y); /* made with N_VMake_Serial: the caller's data is not freed */
    }
    if (cvode->context != NULL) {
        SUNContext_Free(&cvode->context);
    }
    free(cvode->y_seen);
    free(cvode);
    integrator->cvode = NULL;
}

static tb_status create_memory(tb_integrator *integrator, const tb_integrator_def *def,
                               tb_error *error)
{
    tb__cvode *cvode = integrator->cvode;
    const size_t n = integrator->system.n;
#if SUNDIALS_VERSION_MAJOR >= 7
    int flag = SUNContext_Create(SUN_COMM_NULL, &cvode->context);
#else
    int flag = SUNContext_Create(NULL, &cvode->context);
#endif
    if (flag != 0) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "SUNContext");
    }
#if SUNDIALS_VERSION_MAJOR >= 7
    SUNContext_ClearErrHandlers(cvode->context);
    SUNContext_PushErrHandler(cvode->context, capture_message, cvode);
#endif
    cvode->y = N_VMake_Serial((sunindextype)n, integrator->y, cvode->context);
    cvode->mem =
        CVodeCreate(integrator->method == TB_METHOD_CVODE_BDF ? CV_BDF : CV_ADAMS, cvode->context);
    cvode->y_seen = tb__malloc_array(n, sizeof(double));
    if (cvode->y == NULL || cvode->mem == NULL || cvode->y_seen == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "CVODE memory for n = %zu", n);
    }
#if SUNDIALS_VERSION_MAJOR < 7
    CVodeSetErrHandlerFn(cvode->mem, capture_message, cvode);
#endif
    /* before CVodeInit, which allocates the history for the largest order */
    flag = def->max_order > 0 ? CVodeSetMaxOrd(cvode->mem, def->max_order) : CV_SUCCESS;
    if (flag != CV_SUCCESS) {
        return tb__cvode_setup_failed(cvode, "CVodeSetMaxOrd", flag, error);
    }
    cvode->t_origin = integrator->t;
    flag = CVodeInit(cvode->mem, tb__cvode_derivative, 0.0, cvode->y);
    if (flag == CV_SUCCESS) {
        flag = CVodeSetUserData(cvode->mem, integrator);
    }
    return flag == CV_SUCCESS ? TB_STATUS_OK
                              : tb__cvode_setup_failed(cvode, "CVodeInit", flag, error);
}

static tb_status cvode_create(tb_integrator *integrator, const tb_integrator_def *def,
                              tb_error *error)
{
    tb_status status = validate(integrator, def, error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    integrator->cvode = calloc(1, sizeof(tb__cvode));
    if (integrator->cvode == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "CVODE integrator");
    }
    tb__cvode *cvode = integrator->cvode;
    status = create_memory(integrator, def, error);
    if (status == TB_STATUS_OK) {
        status = set_tolerances(cvode, def, integrator->system.n, error);
    }
    if (status == TB_STATUS_OK) {
        status = set_options(cvode, def, error);
    }
    if (status == TB_STATUS_OK) {
        status = tb__cvode_set_solvers(integrator, def, error);
    }
    if (status == TB_STATUS_OK) {
        status = tb__cvode_events_init(integrator, error);
    }
    if (status == TB_STATUS_OK && integrator->system.post_step != NULL &&
        integrator->method == TB_METHOD_CVODE_BDF) {
        /* SUNDIALS 6 projects only with BDF; Adams outputs are renormalised instead. */
        int flag = CVodeSetProjFn(cvode->mem, tb__cvode_project);
        if (flag == CV_SUCCESS) {
            flag = CVodeSetProjErrEst(cvode->mem, SUNFALSE);
        }
        status = flag == CV_SUCCESS ? TB_STATUS_OK
                                    : tb__cvode_setup_failed(cvode, "CVodeSetProjFn", flag, error);
    }
    if (status != TB_STATUS_OK) {
        cvode_destroy(integrator);
        return status;
    }
    memcpy(cvode->y_seen, integrator->y, integrator->system.n * sizeof(double));
    cvode->rhs_generation = rhs_generation(&integrator->system);
    return TB_STATUS_OK;
}

/* --- statistics --------------------------------------------------------------------------- */

static void read_counters(const tb_integrator *integrator, tb_integrator_stats *out)
{
    const tb__cvode *cvode = integrator->cvode;
    void *mem = cvode->mem;
    long steps = 0, rhs = 0, error_fails = 0, nonlinear_fails = 0, linear_rhs = 0, iterations = 0,
         band_rhs = 0;
    sunrealtype last = 0, current = 0;
    CVodeGetNumSteps(mem, &steps);
    CVodeGetNumRhsEvals(mem, &rhs);
    CVodeGetNumErrTestFails(mem, &error_fails);
    CVodeGetNumNonlinSolvConvFails(mem, &nonlinear_fails);
    CVodeGetLastStep(mem, &last);
    CVodeGetCurrentStep(mem, &current);
    CVodeGetLastOrder(mem, &out->last_order);
    CVodeGetCurrentOrder(mem, &out->current_order);
    if (cvode->linear != NULL) {
        CVodeGetNumLinRhsEvals(mem, &linear_rhs);
        CVodeGetNumLinIters(mem, &iterations);
    }
    if (cvode->band_preconditioner) {
        CVBandPrecGetNumRhsEvals(mem, &band_rhs);
    }
    const tb_integrator_stats *base = &cvode->base;
    out->steps = base->steps + steps;
    const long jacobian = linear_rhs + band_rhs;
    out->derivative_evals = base->derivative_evals + rhs + jacobian + cvode->jacobian_evals;
    out->jacobian_derivative_evals =
        base->jacobian_derivative_evals + jacobian + cvode->jacobian_evals;
    out->error_test_failures = base->error_test_failures + error_fails;
    out->nonlinear_failures = base->nonlinear_failures + nonlinear_fails;
    out->failed_steps = out->error_test_failures + out->nonlinear_failures;
    out->linear_iterations = base->linear_iterations + iterations;
    out->last_step = last;
    out->current_step = current;
    out->reinitializations = base->reinitializations;
    long iterations_nl = 0, jacobians = 0;
    CVodeGetNumNonlinSolvIters(mem, &iterations_nl);
    if (cvode->matrix != NULL) {
        CVodeGetNumJacEvals(mem, &jacobians);
    }
    out->nonlinear_iterations = base->nonlinear_iterations + iterations_nl;
    out->jacobian_evals = base->jacobian_evals + jacobians;
}

static void cvode_get_stats(const tb_integrator *integrator, tb_integrator_stats *stats)
{
    read_counters(integrator, stats);
}

/* --- stepping ----------------------------------------------------------------------------- */

static tb_status restart(tb_integrator *integrator, double t)
{
    tb__cvode *cvode = integrator->cvode;
    read_counters(integrator, &cvode->base); /* CVodeReInit zeroes CVODE's counters */
    cvode->jacobian_evals = 0;               /* now part of base */
    cvode->base.reinitializations++;
    const int flag = CVodeReInit(cvode->mem, 0.0, cvode->y);
    if (flag != CV_SUCCESS) {
        char name[64];
        flag_name(flag, name, sizeof name);
        return tb__set_detail(integrator->detail, TB_STATUS_SOLVER_FAILED,
                              "CVODE restart at t = %.17g: CVodeReInit returned %s: %s", t, name,
                              cvode->message);
    }
    integrator->t = t;
    cvode->t_origin = t;
    cvode->rhs_generation = rhs_generation(&integrator->system);
    cvode->started = false;
    cvode->stale = false;
    memcpy(cvode->y_seen, integrator->y, integrator->system.n * sizeof(double));
    return TB_STATUS_OK;
}

/* A state the caller changed since the last output means CVODE's history is stale; so do a
 * refused output and a changed right-hand side. */
static tb_status restart_if_changed(tb_integrator *integrator)
{
    tb__cvode *cvode = integrator->cvode;
    if (cvode->stale || rhs_generation(&integrator->system) != cvode->rhs_generation ||
        memcmp(cvode->y_seen, integrator->y, integrator->system.n * sizeof(double)) != 0) {
        return restart(integrator, integrator->t);
    }
    return TB_STATUS_OK;
}

/* Refuses an output with a non-finite component (CVODE can return success with one, and
 * interpolation can overflow): y goes back to the last output, and CVODE restarts from it
 * before the next step. stage says which output. */
static tb_status check_output(tb_integrator *integrator, double t, const char *stage)
{
    const size_t n = integrator->system.n;
    const size_t bad = tb__first_non_finite(integrator->y, n);
    if (bad == n) {
        return TB_STATUS_OK;
    }
    tb__cvode *cvode = integrator->cvode;
    const double value = integrator->y[bad];
    memcpy(integrator->y, cvode->y_seen, n * sizeof(double));
    cvode->stale = true;
    return tb__set_detail(integrator->detail, TB_STATUS_STATE_NOT_FINITE,
                          "y[%zu] became %g in %s's output at t = %.17g%s; kept the state at t = "
                          "%.17g",
                          bad, value, integrator->entry->info.name, t, stage, integrator->t);
}

/* Hands out y at time t: checks it, applies the hook to it (CVODE's history is untouched by
 * this), checks it again and remembers it so a change from outside can be detected. On
 * failure y and the time stay at the last output. */
static tb_status hand_out(tb_integrator *integrator, double t)
{
    const tb_ode_system *system = &integrator->system;
    tb__cvode *cvode = integrator->cvode;
    tb_status status = check_output(integrator, t, "");
    if (status != TB_STATUS_OK) {
        return status;
    }
    const int rc = system->post_step != NULL ? system->post_step(t, integrator->y, system->ctx) : 0;
    status = check_output(integrator, t,
                          rc != 0 ? " (from the post-step hook, which failed)"
                                  : " (from the post-step hook)");
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (rc != 0) {
        memcpy(integrator->y, cvode->y_seen, system->n * sizeof(double));
        cvode->stale = true;
        return tb__set_detail(integrator->detail, TB_STATUS_HOOK_FAILED,
                              "post-step hook returned %d on the output at t = %.17g", rc, t);
    }
    integrator->t = t;
    memcpy(cvode->y_seen, integrator->y, system->n * sizeof(double));
    return TB_STATUS_OK;
}

static tb_status failure_status(int flag, const tb__cvode *cvode, size_t n)
{
    /* the root cause, whatever CVODE made of it */
    if (cvode->derivative_status != 0) {
        return TB_STATUS_DERIVATIVE_FAILED;
    }
    if (cvode->non_finite_index < n) {
        return TB_STATUS_STATE_NOT_FINITE;
    }
    switch (flag) {
    case CV_TOO_MUCH_WORK:
        return TB_STATUS_TOO_MANY_STEPS;
    case CV_RHSFUNC_FAIL:
    case CV_FIRST_RHSFUNC_ERR:
    case CV_REPTD_RHSFUNC_ERR:
    case CV_UNREC_RHSFUNC_ERR:
        return TB_STATUS_DERIVATIVE_FAILED;
    case CV_PROJFUNC_FAIL:
    case CV_REPTD_PROJFUNC_ERR:
        return TB_STATUS_HOOK_FAILED;
    default:
        return TB_STATUS_SOLVER_FAILED;
    }
}

/* CVODE failed: it left y at its last successful step (tau_reached). Keep that state if it is
 * a good output, else the last output; say what happened. */
static tb_status fail(tb_integrator *integrator, int flag, double tau_reached, double t_target)
{
    tb__cvode *cvode = integrator->cvode;
    const double t_reached = cvode->t_origin + tau_reached;
    if (!(isfinite(t_reached) && t_reached >= integrator->t &&
          hand_out(integrator, t_reached) == TB_STATUS_OK)) {
        memcpy(integrator->y, cvode->y_seen, integrator->system.n * sizeof(double));
    }
    const size_t n = integrator->system.n;
    char name[64], derivative_note[96] = "";
    flag_name(flag, name, sizeof name);
    if (cvode->derivative_status != 0) {
        snprintf(derivative_note, sizeof derivative_note, "; derivative returned %d at t = %.17g",
                 cvode->derivative_status, cvode->derivative_time);
    } else if (cvode->non_finite_index < n) {
        snprintf(derivative_note, sizeof derivative_note,
                 "; derivative gave dydt[%zu] = %g at t = %.17g", cvode->non_finite_index,
                 cvode->non_finite_value, cvode->non_finite_time);
    }
    return tb__set_detail(integrator->detail, failure_status(flag, cvode, n),
                          "CVODE %s on the way to t = %.17g, stopped at t = %.17g%s: %s", name,
                          t_target, integrator->t, derivative_note, cvode->message);
}

/* CVODE's first-step estimate is capped at a tenth of the distance to the first output time,
 * so the frame rate would choose the first step and, through it, every later one. Instead the
 * first step after creation or a restart is taken in one-step mode towards a fixed horizon of
 * one time unit; an output time it overshoots is then interpolated. */
#define TB__FIRST_STEP_HORIZON 1.0

/* CVODE's own stepping to tau_out (CV_NORMAL) or for one step (CV_ONE_STEP), for a system
 * without events or step limits. */
static int step_freely(tb__cvode *cvode, double tau_out, int mode, double horizon,
                       sunrealtype *tau_reached)
{
    int flag = CV_SUCCESS;
    bool stepped = false;
    if (!cvode->started) {
        cvode->started = true;
        stepped = true;
        flag = CVode(cvode->mem, horizon, cvode->y, tau_reached, CV_ONE_STEP);
    }
    if (flag >= 0 && mode == CV_NORMAL) {
        flag = *tau_reached >= tau_out
                   ? CVodeGetDky(cvode->mem, tau_out, 0, cvode->y)
                   : CVode(cvode->mem, tau_out, cvode->y, tau_reached, CV_NORMAL);
    } else if (flag >= 0 && !stepped) {
        flag = CVode(cvode->mem, horizon, cvode->y, tau_reached, CV_ONE_STEP);
    }
    return flag;
}

static tb_status run(tb_integrator *integrator, double t_out, int mode)
{
    tb__cvode *cvode = integrator->cvode;
    tb_status status = restart_if_changed(integrator);
    if (status != TB_STATUS_OK) {
        return status;
    }
    cvode->derivative_status = 0;
    cvode->non_finite_index = integrator->system.n;
    cvode->message[0] = '\0';
    for (;;) { /* CVODE's times are tau = t - t_origin */
        const double tau_now = integrator->t - cvode->t_origin, tau_out = t_out - cvode->t_origin;
        const double horizon = tau_now + TB__FIRST_STEP_HORIZON;
        sunrealtype tau_reached = tau_now;
        const int flag = tb__cvode_marches(integrator)
                             ? tb__cvode_march(integrator, tau_out, mode, horizon, &tau_reached)
                             : step_freely(cvode, tau_out, mode, horizon, &tau_reached);
        /* the rhs changed at an event: restart there, go on (one step: the next call does) */
        const bool go_on = flag == TB__CV_EVENT_RESTART && mode == CV_NORMAL;
        status = flag < 0 ? fail(integrator, flag, tau_reached, t_out)
                 : go_on  ? restart(integrator, cvode->t_origin + tau_reached)
                          : hand_out(integrator,
                                    mode == CV_NORMAL ? t_out : cvode->t_origin + tau_reached);
        cvode->stale = cvode->stale || (flag == TB__CV_EVENT_RESTART && !go_on);
        if (!go_on || status != TB_STATUS_OK) {
            return status;
        }
    }
}

static tb_status cvode_advance(tb_integrator *integrator, double t_target)
{
    return run(integrator, t_target, CV_NORMAL);
}

static tb_status cvode_step(tb_integrator *integrator)
{
    return run(integrator, INFINITY, CV_ONE_STEP);
}

static tb_status cvode_reset(tb_integrator *integrator, double t)
{
    return restart(integrator, t);
}

const tb__backend tb__cvode_backend = {
    cvode_create, cvode_advance, cvode_step, cvode_reset, cvode_get_stats, cvode_destroy,
};

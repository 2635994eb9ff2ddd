/* Creation pieces both SUNDIALS backends share (CVODE, ARKStep): the context and the vector
 * over the caller's array, validation of the def, tolerances and step options through the
 * backend's calls (tb__sundials_ops), messages captured instead of printed, and freeing. */
#include "ode/cvode_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* --- messages ----------------------------------------------------------------------------- */

#if SUNDIALS_VERSION_MAJOR >= 7
void tb__sundials_capture_message(int line, const char *function, const char *file, const char *msg,
                                  SUNErrCode code, void *data, SUNContext context)
{
    (void)line, (void)file, (void)code, (void)context;
    tb__cvode *cvode = data;
    snprintf(cvode->message, sizeof cvode->message, "%s: %s", function, msg);
}
#else
void tb__sundials_capture_message(int code, const char *module, const char *function, char *msg,
                                  void *data)
{
    (void)code, (void)module;
    tb__cvode *cvode = data;
    snprintf(cvode->message, sizeof cvode->message, "%s: %s", function, msg);
}
#endif

/* --- creation ----------------------------------------------------------------------------- */

/* The system's right-hand-side generation; 0 for a system that does not have one. */
unsigned long long tb__sundials_rhs_generation(const tb_ode_system *system)
{
    return system->lifetime.rhs_generation != NULL ? system->lifetime.rhs_generation(system->ctx)
                                                   : 0;
}

void tb__sundials_flag_name(const tb__cvode *cvode, int flag, char *out, size_t size)
{
    char *name = cvode->ops->flag_name(flag);
    snprintf(out, size, "%s", name != NULL ? name : "unknown flag");
    free(name);
}

tb_status tb__cvode_setup_failed(tb__cvode *cvode, const char *call, int flag, tb_error *error)
{
    char name[64];
    tb__sundials_flag_name(cvode, flag, name, sizeof name);
    return tb__set_error(error, TB_STATUS_SOLVER_FAILED, "%s set-up: %s returned %s%s%s",
                         cvode->ops->name, call, name, cvode->message[0] ? ": " : "",
                         cvode->message);
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
        char typed[32];
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.rtol: must be in [1e-15, 1), got %s",
                             tb__shortest(def->rtol, typed));
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

tb_status tb__sundials_validate(const tb_integrator *integrator, const tb_integrator_def *def,
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
        flag = cvode->ops->sv_tolerances(cvode->mem, def->rtol, atol);
        N_VDestroy(atol); /* CVODE keeps a copy of its own */
    } else {
        const double atol = def->atol > 0 ? def->atol : 1e-3 * def->rtol;
        flag = cvode->ops->ss_tolerances(cvode->mem, def->rtol, atol);
    }
    return flag == 0 ? TB_STATUS_OK : tb__cvode_setup_failed(cvode, "SetTolerances", flag, error);
}

static tb_status set_options(tb__cvode *cvode, const tb_integrator_def *def, tb_error *error)
{
    const tb__sundials_ops *ops = cvode->ops;
    int flag = ops->set_max_num_steps(cvode->mem, def->max_steps);
    if (flag == 0 && def->initial_step > 0) {
        flag = ops->set_init_step(cvode->mem, def->initial_step);
    }
    if (flag == 0 && def->max_step > 0) {
        flag = ops->set_max_step(cvode->mem, def->max_step);
    }
    return flag == 0 ? TB_STATUS_OK : tb__cvode_setup_failed(cvode, "SetOptions", flag, error);
}

tb_status tb__sundials_set_tolerances_and_options(tb_integrator *integrator,
                                                  const tb_integrator_def *def, tb_error *error)
{
    tb__cvode *cvode = integrator->cvode;
    const tb_status status = set_tolerances(cvode, def, integrator->system.n, error);
    return status == TB_STATUS_OK ? set_options(cvode, def, error) : status;
}

void tb__sundials_destroy(tb_integrator *integrator)
{
    tb__cvode *cvode = integrator->cvode;
    if (cvode == NULL) {
        return;
    }
    if (cvode->mem != NULL) {
        cvode->ops->free_mem(&cvode->mem);
    }
    if (cvode->split_work != NULL) {
        N_VDestroy(cvode->split_work);
    }
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

tb_status tb__sundials_create(tb_integrator *integrator, const tb__sundials_ops *ops,
                              tb_error *error)
{
    integrator->cvode = calloc(1, sizeof(tb__cvode));
    if (integrator->cvode == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "%s integrator", ops->name);
    }
    tb__cvode *cvode = integrator->cvode;
    cvode->ops = ops;
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
    SUNContext_PushErrHandler(cvode->context, tb__sundials_capture_message, cvode);
#endif
    cvode->y = N_VMake_Serial((sunindextype)n, integrator->y, cvode->context);
    cvode->y_seen = tb__malloc_array(n, sizeof(double));
    cvode->t_origin = integrator->t;
    cvode->break_at = INFINITY;
    if (cvode->y == NULL || cvode->y_seen == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "%s memory for n = %zu", ops->name, n);
    }
    return TB_STATUS_OK;
}

void tb__sundials_created(tb_integrator *integrator)
{
    tb__cvode *cvode = integrator->cvode;
    memcpy(cvode->y_seen, integrator->y, integrator->system.n * sizeof(double));
    cvode->rhs_generation = tb__sundials_rhs_generation(&integrator->system);
}

tb_status tb__sundials_make(tb_integrator *integrator, const tb_integrator_def *def,
                            const tb__sundials_ops *ops, tb__sundials_stage memory,
                            tb__sundials_stage finish, tb_error *error)
{
    tb_status status = tb__sundials_validate(integrator, def, error);
    if (status == TB_STATUS_OK) {
        status = tb__sundials_create(integrator, ops, error);
    }
    if (status == TB_STATUS_OK) {
        status = memory(integrator, def, error);
    }
    if (status == TB_STATUS_OK) {
        status = tb__sundials_set_tolerances_and_options(integrator, def, error);
    }
    if (status == TB_STATUS_OK) {
        status = tb__cvode_set_solvers(integrator, def, error);
    }
    if (status == TB_STATUS_OK) {
        status = tb__cvode_events_init(integrator, error);
    }
    if (status == TB_STATUS_OK && finish != NULL) {
        status = finish(integrator, def, error);
    }
    if (status != TB_STATUS_OK) {
        tb__sundials_destroy(integrator);
        return status;
    }
    tb__sundials_created(integrator);
    return TB_STATUS_OK;
}

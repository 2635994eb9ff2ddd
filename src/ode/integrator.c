/* The integrator object: definitions, validation and dispatch to the fixed-step or CVODE
 * backend named by the method's row (methods.c). */
#include "ode/integrator.h"

#include "core/detail.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Distinguishes defs made by tb_integrator_def_default from uninitialised memory. */
#define TB__INTEGRATOR_COOKIE 0x7b1d0de

tb_integrator_def tb_integrator_def_default(void)
{
    tb_integrator_def def;
    memset(&def, 0, sizeof def);
    def.method = TB_METHOD_RK4;
    def.dt = 1.0 / 240.0;
    def.rtol = 1e-6;
    def.atol = 0.0;
    def.max_steps = 100000;
    def.linear_solver = TB_LINEAR_SOLVER_AUTO;
    def.preconditioner_half_bandwidth = -1;
    def.internal_cookie = TB__INTEGRATOR_COOKIE;
    return def;
}

static tb_status validate(const tb_ode_system *system, const tb_integrator_def *def, double t0,
                          const double *y, tb_error *error)
{
    if (system == NULL || def == NULL || y == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             system == NULL ? "system"
                             : def == NULL  ? "def"
                                            : "y");
    }
    if (def->internal_cookie != TB__INTEGRATOR_COOKIE) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def: not initialised by tb_integrator_def_default()");
    }
    if (system->n == 0 || system->n > SIZE_MAX / (4 * sizeof(double))) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "system.n: must be > 0 and fit in memory, got %zu", system->n);
    }
    if (system->derivative == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER, "system.derivative is NULL");
    }
    if (system->block_size > 0) {
        if (system->n % system->block_size != 0) {
            return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                                 "system.block_size: %zu does not divide n = %zu",
                                 system->block_size, system->n);
        }
        if (system->block_derivative == NULL) {
            return tb__set_error(error, TB_STATUS_NULL_POINTER,
                                 "system.block_derivative is NULL but block_size is %zu",
                                 system->block_size);
        }
        if (system->post_step != NULL && system->block_post_step == NULL) {
            return tb__set_error(error, TB_STATUS_NULL_POINTER,
                                 "system.block_post_step is NULL but post_step and block_size "
                                 "are set");
        }
    }
    if ((int)def->method < 0 || def->method >= TB_METHOD_COUNT) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT, "def.method: unknown method %d",
                             (int)def->method);
    }
    if (!isfinite(t0)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE, "t0: must be finite, got %g", t0);
    }
    return TB_STATUS_OK;
}

tb_status tb_integrator_create(const tb_ode_system *system, const tb_integrator_def *def, double t0,
                               double *y, tb_integrator **out_integrator, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (out_integrator == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "out_integrator is NULL");
    }
    *out_integrator = NULL;
    tb_status status = validate(system, def, t0, y, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb_integrator *integrator = calloc(1, sizeof *integrator);
    if (integrator == NULL) {
        return tb__set_error(out_error, TB_STATUS_OUT_OF_MEMORY, "integrator");
    }
    integrator->system = *system;
    integrator->method = def->method;
    integrator->entry = &tb__methods[def->method];
    integrator->t = t0;
    integrator->y = y;
    status = integrator->entry->backend->create(integrator, def, out_error);
    if (status != TB_STATUS_OK) {
        free(integrator);
        return status;
    }
    *out_integrator = integrator;
    return TB_STATUS_OK;
}

void tb_integrator_destroy(tb_integrator *integrator)
{
    if (integrator != NULL) {
        integrator->entry->backend->destroy(integrator);
        free(integrator);
    }
}

tb_status tb_integrator_advance(tb_integrator *integrator, double t_target)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    integrator->detail[0] = '\0';
    if (!isfinite(t_target) || t_target < integrator->t) {
        return tb__set_detail(integrator->detail, TB_STATUS_INVALID_ARGUMENT,
                              "t_target: must be finite and >= current time %.17g, got %.17g",
                              integrator->t, t_target);
    }
    if (t_target == integrator->t) {
        return TB_STATUS_OK;
    }
    return integrator->entry->backend->advance(integrator, t_target);
}

tb_status tb_integrator_step(tb_integrator *integrator)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    integrator->detail[0] = '\0';
    return integrator->entry->backend->step(integrator);
}

double tb_integrator_time(const tb_integrator *integrator)
{
    return integrator == NULL ? NAN : integrator->t;
}

tb_status tb_integrator_reset(tb_integrator *integrator, double t)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    integrator->detail[0] = '\0';
    if (!isfinite(t)) {
        return tb__set_detail(integrator->detail, TB_STATUS_NOT_FINITE, "t: must be finite, got %g",
                              t);
    }
    return integrator->entry->backend->reset(integrator, t);
}

tb_status tb_integrator_get_stats(const tb_integrator *integrator, tb_integrator_stats *out_stats)
{
    if (integrator == NULL || out_stats == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    integrator->entry->backend->get_stats(integrator, out_stats);
    return TB_STATUS_OK;
}

tb_method tb_integrator_method(const tb_integrator *integrator)
{
    return integrator == NULL ? TB_METHOD_COUNT : integrator->method;
}

const char *tb_integrator_detail(const tb_integrator *integrator)
{
    return integrator == NULL ? "integrator is NULL" : integrator->detail;
}

/* The integrator object: creation, advancing to a target time, statistics. */
#include "integrator.h"

#include "detail.h"
#include "tb_math.h"

#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Distinguishes defs made by tb_integrator_def_default from uninitialised memory. */
#define TB__INTEGRATOR_COOKIE 0x7b1d0de

/* The last step of an advance may be stretched by this fraction of dt rather than leaving a
 * sliver step of round-off size. */
#define TB__LANDING_SLACK 1e-9

const char *tb_method_name(tb_method method)
{
    if ((int)method < 0 || method >= TB_METHOD_COUNT) {
        return NULL;
    }
    return tb__steppers[method].name;
}

tb_status tb_method_from_name(const char *name, tb_method *out_method)
{
    if (name == NULL || out_method == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        if (strcmp(name, tb__steppers[m].name) == 0) {
            *out_method = (tb_method)m;
            return TB_STATUS_OK;
        }
    }
    return TB_STATUS_INVALID_ARGUMENT;
}

int tb_method_order(tb_method method)
{
    if ((int)method < 0 || method >= TB_METHOD_COUNT) {
        return 0;
    }
    return tb__steppers[method].order;
}

tb_integrator_def tb_integrator_def_default(void)
{
    tb_integrator_def def;
    memset(&def, 0, sizeof def);
    def.method = TB_METHOD_RK4;
    def.dt = 1.0 / 240.0;
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
    if ((int)def->method < 0 || def->method >= TB_METHOD_COUNT) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT, "def.method: unknown method %d",
                             (int)def->method);
    }
    if (!(def->dt > 0) || !isfinite(def->dt)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.dt: must be finite and > 0, got %g", def->dt);
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
    double *buffer = malloc(3 * system->n * sizeof(double));
    if (integrator == NULL || buffer == NULL) {
        free(integrator);
        free(buffer);
        return tb__set_error(out_error, TB_STATUS_OUT_OF_MEMORY,
                             "integrator workspace of %zu doubles", 3 * system->n);
    }
    integrator->system = *system;
    integrator->method = def->method;
    integrator->stepper = &tb__steppers[def->method];
    integrator->dt = def->dt;
    integrator->t = t0;
    integrator->y = y;
    integrator->y_new = buffer;
    integrator->work = buffer + system->n;
    *out_integrator = integrator;
    return TB_STATUS_OK;
}

void tb_integrator_destroy(tb_integrator *integrator)
{
    if (integrator != NULL) {
        free(integrator->y_new);
        free(integrator);
    }
}

/* Index of the first non-finite component, or n if all are finite. */
static size_t first_non_finite(const double *y, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(y[i])) {
            return i;
        }
    }
    return n;
}

/* One step of size h from the integrator's time; commits to y only if everything succeeded. */
static tb_status take_step(tb_integrator *integrator, double h, double t_end)
{
    const tb_ode_system *system = &integrator->system;
    const double t = integrator->t;
    int rc = integrator->stepper->step(system, t, h, integrator->y, integrator->y_new,
                                       integrator->work, &integrator->stats.derivative_evals);
    if (rc != 0) {
        ++integrator->stats.failed_steps;
        return tb__set_detail(integrator->detail, TB_STATUS_DERIVATIVE_FAILED,
                              "derivative returned %d in the %s step from t = %.17g (h = %g)", rc,
                              integrator->stepper->name, t, h);
    }
    if (system->post_step != NULL) {
        rc = system->post_step(t_end, integrator->y_new, system->ctx);
        if (rc != 0) {
            ++integrator->stats.failed_steps;
            return tb__set_detail(integrator->detail, TB_STATUS_HOOK_FAILED,
                                  "post-step hook returned %d at t = %.17g", rc, t_end);
        }
    }
    size_t bad = first_non_finite(integrator->y_new, system->n);
    if (bad < system->n) {
        ++integrator->stats.failed_steps;
        return tb__set_detail(integrator->detail, TB_STATUS_STATE_NOT_FINITE,
                              "y[%zu] became %g in the %s step from t = %.17g (h = %g); the "
                              "step size is beyond the method's stability limit or the "
                              "system blew up",
                              bad, integrator->y_new[bad], integrator->stepper->name, t, h);
    }
    memcpy(integrator->y, integrator->y_new, system->n * sizeof(double));
    integrator->t = t_end;
    integrator->stats.steps++;
    integrator->stats.last_step = h;
    return TB_STATUS_OK;
}

tb_status tb_integrator_step(tb_integrator *integrator)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    integrator->detail[0] = '\0';
    return take_step(integrator, integrator->dt, integrator->t + integrator->dt);
}

tb_status tb_integrator_advance(tb_integrator *integrator, double t_target)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    integrator->detail[0] = '\0';
    const double t_start = integrator->t, dt = integrator->dt;
    if (!isfinite(t_target) || t_target < t_start) {
        return tb__set_detail(integrator->detail, TB_STATUS_INVALID_ARGUMENT,
                              "t_target: must be finite and >= current time %.17g, got %.17g",
                              t_start, t_target);
    }
    /* Step times are t_start + i dt rather than a running sum, so round-off does not
     * accumulate over long runs. */
    for (long i = 1; integrator->t < t_target; ++i) {
        double t_end = t_start + (double)i * dt;
        if (t_end >= t_target - TB__LANDING_SLACK * dt) {
            t_end = t_target;
        }
        tb_status status = take_step(integrator, t_end - integrator->t, t_end);
        if (status != TB_STATUS_OK) {
            return status;
        }
    }
    return TB_STATUS_OK;
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
    if (!isfinite(t)) {
        return tb__set_detail(integrator->detail, TB_STATUS_NOT_FINITE, "t: must be finite, got %g",
                              t);
    }
    integrator->t = t;
    return TB_STATUS_OK;
}

tb_status tb_integrator_get_stats(const tb_integrator *integrator, tb_integrator_stats *out_stats)
{
    if (integrator == NULL || out_stats == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    *out_stats = integrator->stats;
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

/* The integrator object: definitions, validation and dispatch to the fixed-step or CVODE
 * backend named by the method's row (methods.c). */
#include "ode/integrator.h"

#include "core/detail.h"

#include <limits.h>
#include <math.h>
#include <stdbool.h>
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
    def.threads = 1;
    def.internal_cookie = TB__INTEGRATOR_COOKIE;
    return def;
}

/* A field a method does not read (the method table's rule, tb__method_reads), set away from its
 * default, was meant for another method (rtol given to rk4, dt to cvode-bdf): refused rather
 * than ignored. */
static tb_status validate_unread_fields(const tb_integrator_def *def, tb_error *error)
{
    const tb_integrator_def d = tb_integrator_def_default();
    const struct {
        const char *field;
        bool set;
    } fields[] = {
        {"dt", !(def->dt == d.dt)},
        {"threads", def->threads != d.threads},
        {"rtol", !(def->rtol == d.rtol)},
        {"atol", !(def->atol == d.atol)},
        {"atol_vector", def->atol_vector != NULL},
        {"initial_step", !(def->initial_step == d.initial_step)},
        {"max_step", !(def->max_step == d.max_step)},
        {"max_order", def->max_order != d.max_order},
        {"linear_solver", def->linear_solver != d.linear_solver},
    };
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; ++i) {
        if (fields[i].set && !tb__method_reads(def->method, fields[i].field)) {
            char readers[160];
            tb__setting_readers(def->method, fields[i].field, readers, sizeof readers);
            return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                                 "def.%s: %s does not read it (it %s); leave it at its default, "
                                 "or switch methods with tb_integrator_def_set_method",
                                 fields[i].field, tb__methods[def->method].info.name, readers);
        }
    }
    return TB_STATUS_OK;
}

tb_status tb_integrator_def_set_method(tb_integrator_def *def, tb_method method)
{
    if (def == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    if ((int)method < 0 || method >= TB_METHOD_COUNT) {
        return TB_STATUS_INVALID_ARGUMENT;
    }
    const tb_integrator_def d = tb_integrator_def_default();
    const unsigned reads = tb__methods[method].reads;
    def->method = method;
    if (!(reads & TB__READS_DT)) {
        def->dt = d.dt;
        def->threads = d.threads;
    }
    if (!(reads & TB__READS_TOLERANCES)) {
        def->rtol = d.rtol;
        def->atol = d.atol;
        def->atol_vector = d.atol_vector;
        def->initial_step = d.initial_step;
        def->max_step = d.max_step;
        def->max_order = d.max_order;
    }
    if (!(reads & TB__READS_LINEAR_SOLVER)) {
        def->linear_solver = d.linear_solver;
    }
    return TB_STATUS_OK;
}

static tb_status validate_blocks(const tb_ode_system *system, tb_error *error)
{
    if (system->n % system->blocks.size != 0) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "system.blocks.size: %zu does not divide n = %zu", system->blocks.size,
                             system->n);
    }
    if (system->blocks.derivative == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER,
                             "system.blocks.derivative is NULL but blocks.size is %zu",
                             system->blocks.size);
    }
    if (system->post_step != NULL && system->blocks.post_step == NULL) {
        return tb__set_error(
            error, TB_STATUS_NULL_POINTER,
            "system.blocks.post_step is NULL but post_step and blocks.size are set");
    }
    if (system->blocks.lanes > 0 && system->blocks.lanes_derivative == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER,
                             "system.blocks.lanes_derivative is NULL but blocks.lanes is %zu",
                             system->blocks.lanes);
    }
    if (system->blocks.lanes > 0 && system->post_step != NULL &&
        system->blocks.lanes_post_step == NULL) {
        return tb__set_error(
            error, TB_STATUS_NULL_POINTER,
            "system.blocks.lanes_post_step is NULL but post_step and blocks.lanes are set");
    }
    if (system->blocks.lanes > TB__MAX_LANES) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "system.blocks.lanes: at most %d, got %zu", TB__MAX_LANES,
                             system->blocks.lanes);
    }
    return TB_STATUS_OK;
}

/* layout_generation, acquire and release come as a set: an integrator that could not release
 * what it acquired would leave the system busy for ever. */
static tb_status validate_lifetime_hooks(const tb_ode_system *system, tb_error *error)
{
    const int set = (system->lifetime.layout_generation != NULL) +
                    (system->lifetime.acquire != NULL) + (system->lifetime.release != NULL);
    if (set != 0 && set != 3) {
        return tb__set_error(
            error, TB_STATUS_NULL_POINTER,
            "system.lifetime.%s is NULL: layout_generation, acquire and release are set "
            "together or not at all",
            system->lifetime.layout_generation == NULL ? "layout_generation"
            : system->lifetime.acquire == NULL         ? "acquire"
                                                       : "release");
    }
    return TB_STATUS_OK;
}

static tb_status validate_system(const tb_ode_system *system, tb_error *error)
{
    if (system->n == 0 || system->n > SIZE_MAX / (4 * sizeof(double))) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "system.n: must be > 0 and fit in memory, got %zu", system->n);
    }
    if (system->derivative == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER, "system.derivative is NULL");
    }
    if (system->blocks.size > 0) {
        const tb_status status = validate_blocks(system, error);
        if (status != TB_STATUS_OK) {
            return status;
        }
    }
    if ((system->events.root_count > 0) != (system->events.roots != NULL) ||
        system->events.root_count > INT_MAX) {
        return tb__set_error(
            error,
            system->events.roots == NULL ? TB_STATUS_NULL_POINTER : TB_STATUS_INVALID_ARGUMENT,
            "system.events.roots and system.events.root_count (%zu) are set together (count "
            "at most %d) or not at all",
            system->events.root_count, INT_MAX);
    }
    if ((system->jacobian.capacity != NULL) != (system->jacobian.evaluate != NULL)) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER,
                             "system.jacobian.%s is NULL: capacity and evaluate are set together "
                             "or not at all",
                             system->jacobian.capacity == NULL ? "capacity" : "evaluate");
    }
    return validate_lifetime_hooks(system, error);
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
    const tb_status status = validate_system(system, error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if ((int)def->method < 0 || def->method >= TB_METHOD_COUNT) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT, "def.method: unknown method %d",
                             (int)def->method);
    }
    const tb_status unread = validate_unread_fields(def, error);
    if (unread != TB_STATUS_OK) {
        return unread;
    }
    if (def->threads < 0) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.threads: must be >= 1, or 0 for one per processor, got %d",
                             def->threads);
    }
    if (def->max_steps <= 0) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.max_steps: must be > 0, got %ld", def->max_steps);
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
    integrator->max_steps = def->max_steps;
    integrator->events = (tb_integrator_events){0, NAN, -1, 0};
    if (system->lifetime.layout_generation != NULL) {
        integrator->generation = system->lifetime.layout_generation(system->ctx);
    }
    status = integrator->entry->backend->create(integrator, def, out_error);
    if (status != TB_STATUS_OK) {
        free(integrator);
        return status;
    }
    *out_integrator = integrator;
    return TB_STATUS_OK;
}

static void free_integrator(tb_integrator *integrator)
{
    integrator->entry->backend->destroy(integrator);
    free(integrator);
}

void tb_integrator_destroy(tb_integrator *integrator)
{
    if (integrator != NULL && integrator->busy) {
        /* from a callback of its own advance, step or reset (a contact event, a frame): freed
         * now, the call in progress would read freed memory; it is freed as that call ends */
        integrator->destroy_pending = true;
    } else if (integrator != NULL) {
        free_integrator(integrator);
    }
}

/* Starts a call that steps or resets: refuses a re-entrant call (from the integrator's own
 * derivative, hook or acquire) and a system whose acquire refuses, changing nothing. The
 * detail of a re-entrant call is written for its caller; the call in progress clears it again
 * if it succeeds. */
static tb_status enter(tb_integrator *integrator, const char *call)
{
    if (integrator->busy) {
        return tb__set_detail(integrator->detail, TB_STATUS_BUSY,
                              "%s: the integrator is already in an advance, step or reset (called "
                              "from its own derivative, hook or acquire)",
                              call);
    }
    integrator->detail[0] = '\0';
    integrator->busy = true;
    const tb_ode_system *system = &integrator->system;
    if (system->lifetime.acquire != NULL) {
        const tb_status status =
            system->lifetime.acquire(system->ctx, integrator->generation, integrator->detail);
        if (status != TB_STATUS_OK) {
            integrator->busy = false;
            if (integrator->detail[0] == '\0') {
                tb__set_detail(integrator->detail, status, "%s: the system refused (acquire)",
                               call);
            }
            return status;
        }
    }
    return TB_STATUS_OK;
}

/* Ends a call that enter let through; passes its status on. */
static tb_status leave(tb_integrator *integrator, tb_status status)
{
    const tb_ode_system *system = &integrator->system;
    if (system->lifetime.release != NULL) {
        system->lifetime.release(system->ctx);
    }
    integrator->busy = false;
    if (status == TB_STATUS_OK) {
        integrator->detail[0] = '\0'; /* a refused re-entrant call's message is not ours */
    }
    if (integrator->destroy_pending) {
        free_integrator(integrator);
    }
    return status;
}

tb_status tb_integrator_advance(tb_integrator *integrator, double t_target)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb_status status = enter(integrator, "advance");
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (!isfinite(t_target)) {
        status = tb__set_detail(integrator->detail, TB_STATUS_NOT_FINITE,
                                "t_target: must be finite, got %g", t_target);
    } else if (t_target < integrator->t) {
        status = tb__set_detail(integrator->detail, TB_STATUS_INVALID_ARGUMENT,
                                "t_target: must be >= current time %.17g, got %.17g", integrator->t,
                                t_target);
    } else if (t_target > integrator->t) {
        status = tb__integrator_check_break(integrator); /* the last call may have ended on one */
        status = status != TB_STATUS_OK ? status
                                        : integrator->entry->backend->advance(integrator, t_target);
    }
    return leave(integrator, status);
}

tb_status tb_integrator_step(tb_integrator *integrator)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb_status status = enter(integrator, "step");
    if (status != TB_STATUS_OK) {
        return status;
    }
    status = tb__integrator_check_break(integrator); /* the last call may have ended on one */
    return leave(integrator,
                 status != TB_STATUS_OK ? status : integrator->entry->backend->step(integrator));
}

double tb_integrator_time(const tb_integrator *integrator)
{
    return integrator == NULL ? NAN : integrator->t;
}

/* A system's refusal (check_break, check_reset) that wrote no detail gets one naming it. */
static tb_status refused_by(tb_integrator *integrator, tb_status status, const char *check,
                            double t)
{
    if (status != TB_STATUS_OK && integrator->detail[0] == '\0') {
        tb__set_detail(integrator->detail, status,
                       "the system's %s refused t = %.17g (%s), writing no detail", check, t,
                       tb_status_string(status));
    }
    return status;
}

tb_status tb__integrator_check_break(tb_integrator *integrator)
{
    const tb_ode_system *system = &integrator->system;
    if (system->events.check_break == NULL) {
        return TB_STATUS_OK;
    }
    integrator->detail[0] = '\0';
    const tb_status status =
        system->events.check_break(integrator->t, integrator->y, system->ctx, integrator->detail);
    return refused_by(integrator, status, "events.check_break", integrator->t);
}

tb_status tb_integrator_reset(tb_integrator *integrator, double t)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb_status status = enter(integrator, "reset");
    if (status != TB_STATUS_OK) {
        return status;
    }
    const tb_ode_system *system = &integrator->system;
    if (!isfinite(t)) {
        status = tb__set_detail(integrator->detail, TB_STATUS_NOT_FINITE,
                                "t: must be finite, got %g", t);
    } else if (system->lifetime.check_reset != NULL) {
        status = system->lifetime.check_reset(t, integrator->y, system->ctx, integrator->detail);
        status = refused_by(integrator, status, "lifetime.check_reset", t);
    }
    if (status == TB_STATUS_OK) {
        status = integrator->entry->backend->reset(integrator, t);
    }
    return leave(integrator, status);
}

tb_status tb_integrator_get_stats(const tb_integrator *integrator, tb_integrator_stats *out_stats)
{
    if (integrator == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    /* The detail is the one thing a reading call writes: a message about the last call (the
     * integrator, made by calloc, is not const underneath). Inside a call in progress (from a
     * callback) the detail is that call's and stays. */
    char *detail = integrator->busy ? NULL : ((tb_integrator *)integrator)->detail;
    if (detail != NULL) {
        detail[0] = '\0';
    }
    if (out_stats == NULL) {
        return tb__set_detail(detail, TB_STATUS_NULL_POINTER, "out_stats is NULL");
    }
    integrator->entry->backend->get_stats(integrator, out_stats);
    return TB_STATUS_OK;
}

tb_status tb_integrator_get_events(const tb_integrator *integrator,
                                   tb_integrator_events *out_events)
{
    if (integrator == NULL || out_events == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    *out_events = integrator->events;
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

/* Fixed-step explicit Runge-Kutta methods: Euler, midpoint (RK2) and classical RK4 (their rows
 * are in methods.c), and the backend that advances with them and with the linearly implicit
 * Rosenbrock method (rosenbrock.c), which takes the same onsets, breaks, budget and hooks. Each
 * stepper writes the new state into y_new and never touches y, so a failed step loses nothing. */
#include "ode/integrator.h"
#include "ode/rosenbrock.h"

#include "core/detail.h"
#include "core/validate.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The last step of an advance may be stretched by this fraction of dt rather than leaving a
 * sliver step of round-off size. */
#define TB__LANDING_SLACK 1e-9

/* out = y + s k */
TB__CLONES static void add_scaled(double *out, const double *y, double s, const double *k, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        out[i] = y[i] + s * k[i];
    }
}

/* y_new = y + h f(t, y) */
int tb__euler_step(const tb_ode_system *system, double t, double h, double t_last, const double *y,
                   double *y_new, double *work, long *evals)
{
    (void)t_last; /* no stage at the end */
    double *k = work;
    ++*evals;
    int rc = system->derivative(t, y, k, system->ctx);
    if (rc != 0) {
        return rc;
    }
    add_scaled(y_new, y, h, k, system->n);
    return 0;
}

/* k1 = f(t, y); y_new = y + h f(t + h/2, y + h/2 k1) */
int tb__midpoint_step(const tb_ode_system *system, double t, double h, double t_last,
                      const double *y, double *y_new, double *work, long *evals)
{
    (void)t_last; /* no stage at the end */
    const size_t n = system->n;
    double *k = work, *y_mid = work + n;
    ++*evals;
    int rc = system->derivative(t, y, k, system->ctx);
    if (rc != 0) {
        return rc;
    }
    add_scaled(y_mid, y, 0.5 * h, k, n);
    ++*evals;
    rc = system->derivative(t + 0.5 * h, y_mid, k, system->ctx);
    if (rc != 0) {
        return rc;
    }
    add_scaled(y_new, y, h, k, n);
    return 0;
}

/* RK4's stage pass: y_new = sum + b k (the stage accumulated) and y_stage = y + a k (the next
 * stage's input; none after the last stage, y_stage NULL); sum is y or y_new. */
TB__CLONES static void rk4_stage(double *y_new, const double *sum, double *y_stage, const double *y,
                                 const double *k, double b, double a, size_t n)
{
    if (y_stage == NULL) {
        for (size_t i = 0; i < n; ++i) {
            y_new[i] = sum[i] + b * k[i];
        }
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        y_new[i] = sum[i] + b * k[i];
        y_stage[i] = y[i] + a * k[i];
    }
}

/* Classical RK4, y_new = y + h/6 (k1 + 2 k2 + 2 k3 + k4), accumulated stage by stage so the
 * workspace is one stage vector and one stage state (2n) instead of four stages. */
int tb__rk4_step(const tb_ode_system *system, double t, double h, double t_last, const double *y,
                 double *y_new, double *work, long *evals)
{
    static const double stage_time[4] = {0.0, 0.5, 0.5, 1.0};             /* c_i */
    static const double next_stage[4] = {0.5, 0.5, 1.0, 0.0};             /* a_{i+1,i} */
    static const double weight[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6}; /* b_i */
    const size_t n = system->n;
    double *k = work, *y_stage = work + n;
    const double *stage_input = y;
    for (int s = 0; s < 4; ++s) {
        ++*evals;
        const double t_stage = s == 3 ? t_last : t + stage_time[s] * h;
        int rc = system->derivative(t_stage, stage_input, k, system->ctx);
        if (rc != 0) {
            return rc;
        }
        const double b = weight[s] * h, a = next_stage[s] * h;
        /* one pass: accumulate the stage (the first one starts the sum from y) and form the
         * next stage's input */
        rk4_stage(y_new, s == 0 ? y : y_new, s < 3 ? y_stage : NULL, y, k, b, a, n);
        stage_input = y_stage;
    }
    return 0;
}

/* Times must resolve a step to this fraction of dt: near t = 1e15 doubles are 0.125 apart, and
 * t + dt would not move (or would move in steps of the spacing, not of dt). */
#define TB__TIME_RESOLUTION (1.0 / 1024.0)

/* Distance from |t| to the next larger double. */
static double time_spacing(double t)
{
    return nextafter(fabs(t), INFINITY) - fabs(t);
}

/* Refuses a dt that the times near t cannot resolve (see TB__TIME_RESOLUTION); what names t in
 * the message ("t0", "t_target", ...). */
static tb_status check_time_resolution(char *detail, double dt, double t, const char *what)
{
    const double spacing = time_spacing(t);
    if (spacing > TB__TIME_RESOLUTION * dt) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "dt: %g is too small for times near %s = %.17g, where doubles are "
                              "%g apart (a step must span at least %g of them); count time from "
                              "a nearer origin or use a larger dt",
                              dt, what, t, spacing, 1.0 / TB__TIME_RESOLUTION);
    }
    return TB_STATUS_OK;
}

/* The onset search's buffers and the Rosenbrock method's solver; on failure frees them and the
 * workspace. */
static tb_status create_onsets_and_solver(tb_integrator *integrator, tb_error *error)
{
    tb_status status = tb__onset_create(integrator, error);
    if (status == TB_STATUS_OK && integrator->entry->linearly_implicit) {
        status = tb__rosenbrock_create(integrator, error);
    }
    if (status != TB_STATUS_OK) {
        tb__onset_destroy(integrator);
        free(integrator->workspace);
    }
    return status;
}

static tb_status fixed_create(tb_integrator *integrator, const tb_integrator_def *def,
                              tb_error *error)
{
    if (!isfinite(def->dt)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE, "def.dt: must be finite, got %g",
                             def->dt);
    }
    if (!(def->dt > 0)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT, "def.dt: must be > 0, got %g",
                             def->dt);
    }
    char detail[TB_DETAIL_SIZE];
    if (check_time_resolution(detail, def->dt, integrator->t, "t0") != TB_STATUS_OK) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT, "def.%s", detail);
    }
    if (integrator->entry->linearly_implicit) {
        /* its solve couples the whole state: a separable system steps whole too */
        integrator->system.blocks = (tb_ode_blocks){0};
    }
    const size_t n = integrator->system.n;
    /* whole-array path: the new state (n) and the stepper's scratch (2n); chunked path: the
     * state before the step, to undo a failed one (n), and each thread's chunk buffers */
    size_t size = 3 * n, chunk_buffers = 0;
    if (integrator->system.blocks.size > 0) {
        tb__chunk_layout(integrator, def->threads);
        chunk_buffers = (size_t)integrator->threads * integrator->chunk_work;
        size = chunk_buffers + n;
    }
    /* from a cache line (chunk buffers first, each a whole number of lines), so that the vector
     * unit's loads do not straddle lines */
    size_t bytes = 0;
    integrator->workspace =
        tb__size_product(size, sizeof(double), &bytes) && bytes <= (size_t)-1 - TB__LINE
            ? malloc(bytes + TB__LINE)
            : NULL;
    if (integrator->workspace == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "integrator workspace of %zu doubles",
                             size);
    }
    const uintptr_t base = (uintptr_t)integrator->workspace;
    double *buffer = (double *)(base + (TB__LINE - base % TB__LINE) % TB__LINE);
    if (chunk_buffers > 0) {
        integrator->work = buffer;
        integrator->y_new = buffer + chunk_buffers;
    } else {
        integrator->y_new = buffer;
        integrator->work = buffer + n;
    }
    integrator->dt = def->dt;
    const tb_status status = create_onsets_and_solver(integrator, error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    integrator->stats.last_order = integrator->stats.current_order = integrator->entry->info.order;
    integrator->stats.current_step = def->dt;
    return TB_STATUS_OK;
}

static void fixed_destroy(tb_integrator *integrator)
{
    tb__rosenbrock_destroy(integrator);
    tb__onset_destroy(integrator);
    free(integrator->workspace);
}

/* Partial sums of the finiteness probe: independent chains, so the pass runs at the vector
 * unit's width rather than at one add's latency a component. */
#define TB__PROBES 16

/* The common case is one vectorisable pass: y * 0 is 0 for finite y and NaN for NaN or
 * infinity, so the sum is NaN exactly when some component is not finite; only then is it
 * located. */
TB__CLONES static size_t first_non_finite(const double *y, size_t n)
{
    double probes[TB__PROBES] = {0.0};
    size_t i = 0;
    for (; i + TB__PROBES <= n; i += TB__PROBES) {
        for (size_t k = 0; k < TB__PROBES; ++k) {
            probes[k] += y[i + k] * 0.0;
        }
    }
    for (; i < n; ++i) {
        probes[i % TB__PROBES] += y[i] * 0.0; /* independent chains here too */
    }
    double probe = 0.0;
    for (size_t k = 0; k < TB__PROBES; ++k) {
        probe += probes[k];
    }
    if (probe == 0.0) {
        return n;
    }
    for (i = 0; i < n; ++i) {
        if (!isfinite(y[i])) {
            return i;
        }
    }
    return n;
}

/* (clang 14 emits no symbol for a multi-versioned function of external linkage) */
size_t tb__first_non_finite(const double *y, size_t n)
{
    return first_non_finite(y, n);
}

static tb_status derivative_failed(tb_integrator *integrator, int rc, double h)
{
    ++integrator->stats.failed_steps;
    return tb__set_detail(integrator->detail, TB_STATUS_DERIVATIVE_FAILED,
                          "derivative returned %d in the %s step from t = %.17g (h = %g)", rc,
                          integrator->entry->info.name, integrator->t, h);
}

static tb_status hook_failed(tb_integrator *integrator, int rc, double t_end)
{
    ++integrator->stats.failed_steps;
    return tb__set_detail(integrator->detail, TB_STATUS_HOOK_FAILED,
                          "post-step hook returned %d at t = %.17g", rc, t_end);
}

/* hook_rc: what the post-step hook returned on the non-finite state (0 if it was not run). */
static tb_status not_finite(tb_integrator *integrator, size_t index, double value, double h,
                            int hook_rc)
{
    ++integrator->stats.failed_steps;
    char hook_note[64] = "";
    if (hook_rc != 0) {
        snprintf(hook_note, sizeof hook_note, " (the post-step hook returned %d on it)", hook_rc);
    }
    /* a NaN's sign differs between scalar and vector arithmetic and means nothing: printed
     * without it, the detail is the same on every vector path */
    return tb__set_detail(integrator->detail, TB_STATUS_STATE_NOT_FINITE,
                          "y[%zu] became %g in the %s step from t = %.17g (h = %g)%s; the step "
                          "size is beyond the method's stability limit or the system blew up",
                          index, isnan(value) ? fabs(value) : value, integrator->entry->info.name,
                          integrator->t, h, hook_note);
}

tb_status tb__fixed_report(tb_integrator *integrator, const tb__step_failure *failure, double h,
                           double t_end)
{
    switch (failure->status) {
    case TB_STATUS_DERIVATIVE_FAILED:
        return derivative_failed(integrator, failure->rc, h);
    case TB_STATUS_HOOK_FAILED:
        return hook_failed(integrator, failure->rc, t_end);
    case TB_STATUS_STATE_NOT_FINITE:
        return not_finite(integrator, failure->index, failure->value, h, failure->hook_rc);
    case TB_STATUS_SOLVER_FAILED:
        ++integrator->stats.failed_steps;
        if (failure->rc == TB__ROSENBROCK_LINEAR_FAILED &&
            tb__rosenbrock_message(integrator)[0] != '\0') {
            return tb__set_detail(integrator->detail, TB_STATUS_SOLVER_FAILED, "%s (h = %g)",
                                  tb__rosenbrock_message(integrator), h);
        }
        return tb__set_detail(integrator->detail, TB_STATUS_SOLVER_FAILED,
                              "a root function (tb_ode_system.events.roots) returned %d in the %s "
                              "step from t = %.17g (h = %g), looking for an onset",
                              failure->rc, integrator->entry->info.name, integrator->t, h);
    default:
        return failure->status;
    }
}

/* The method's step over the whole system: the row's explicit stepper, or the Rosenbrock one. */
static int step_method(tb_integrator *integrator, double h, double t_last, const double *y,
                       double *fresh, double *scratch, long *evals)
{
    if (integrator->entry->linearly_implicit) {
        return tb__rosenbrock_step(integrator, integrator->t, h, t_last, y, fresh, scratch, evals);
    }
    return integrator->entry->step(&integrator->system, integrator->t, h, t_last, y, fresh, scratch,
                                   evals);
}

/* A failed step_method: the derivative's return, or the Rosenbrock solve's. */
static tb__step_failure step_failed(int rc)
{
    if (rc == TB__ROSENBROCK_LINEAR_FAILED) {
        return (tb__step_failure){TB_STATUS_SOLVER_FAILED, rc, 0, 0, 0.0};
    }
    return (tb__step_failure){TB_STATUS_DERIVATIVE_FAILED, rc, 0, 0, 0.0};
}

static void commit(tb_integrator *integrator, double h, double t_end)
{
    integrator->t = t_end;
    integrator->stats.steps++;
    integrator->stats.last_step = h;
}

/* A system with roots: the trial step's end is checked for an onset inside it, and the step
 * taken again, to the onset, if there is one (fixed_onset.c); *h and *t_end say where it ends. */
static tb__step_failure end_at_onset(tb_integrator *integrator, const double *y, double *fresh,
                                     double *scratch, double *h, double *t_end, long *evals)
{
    double h_onset = *h;
    int rc = tb__onset_locate(integrator, y, fresh, *h, evals, &h_onset);
    if (rc != 0) {
        return (tb__step_failure){TB_STATUS_SOLVER_FAILED, rc, 0, 0, 0.0};
    }
    if (h_onset < *h) {
        *h = h_onset;
        *t_end = integrator->t + h_onset;
        /* an onset ends the step before any break: its last stage is at its end */
        rc = step_method(integrator, *h, *t_end, y, fresh, scratch, evals);
        if (rc != 0) {
            return step_failed(rc);
        }
    }
    return (tb__step_failure){TB_STATUS_OK, 0, 0, 0, 0.0};
}

/* Steps the whole system from y into fresh, with 2n doubles of scratch (to an onset inside the
 * step, if the system has roots: *h and *t_end shortened), applies its post-step hook and checks
 * that every component is finite. */
static tb__step_failure step_whole(tb_integrator *integrator, const double *y, double *fresh,
                                   double *scratch, double *h, double t_last, double *t_end,
                                   long *evals)
{
    const tb_ode_system *system = &integrator->system;
    tb__step_failure failure = {TB_STATUS_OK, 0, 0, 0, 0.0};
    int rc = step_method(integrator, *h, t_last, y, fresh, scratch, evals);
    if (rc != 0) {
        return step_failed(rc);
    }
    if (integrator->onset != NULL) {
        failure = end_at_onset(integrator, y, fresh, scratch, h, t_end, evals);
        if (failure.status != TB_STATUS_OK) {
            return failure;
        }
    }
    if (system->post_step != NULL) {
        rc = system->post_step(*t_end, fresh, system->ctx);
        if (rc != 0) {
            /* a hook that fails on a state that is no longer finite (a scene cannot
             * normalise a NaN quaternion) reports the real cause */
            failure = (tb__step_failure){TB_STATUS_HOOK_FAILED, rc, rc, 0, 0.0};
        }
    }
    const size_t bad = tb__first_non_finite(fresh, system->n);
    if (bad < system->n) {
        failure =
            (tb__step_failure){TB_STATUS_STATE_NOT_FINITE, 0, failure.hook_rc, bad, fresh[bad]};
    }
    return failure;
}

/* One step of size h over the whole array, or to an onset inside it; commits to y only if
 * everything succeeded. */
static tb_status take_whole_step(tb_integrator *integrator, double h, double t_last, double t_end)
{
    const double h_asked = h;
    const tb__step_failure failure =
        step_whole(integrator, integrator->y, integrator->y_new, integrator->work, &h, t_last,
                   &t_end, &integrator->stats.derivative_evals);
    if (failure.status != TB_STATUS_OK) {
        return tb__fixed_report(integrator, &failure, h, t_end);
    }
    memcpy(integrator->y, integrator->y_new, integrator->system.n * sizeof(double));
    commit(integrator, h, t_end);
    if (h < h_asked) {
        tb__onset_reached(integrator);
    }
    return TB_STATUS_OK;
}

/* The time of a step's stages at its end (c = 1, RK4's last): t + h, but the largest double
 * below t_end when the step ends on a break of the system (tb_ode_system.events.next_break), where
 * the right-hand side is only piecewise smooth in t (a linear key's velocity jumps): the step then
 * sees the piece it lies in, the left limit, and the step after starts on the next piece. */
static double last_stage_time(const tb_integrator *integrator, double h, double t_end)
{
    const tb_ode_system *system = &integrator->system;
    if (system->events.next_break != NULL &&
        system->events.next_break(integrator->t, system->ctx) == t_end) {
        return nextafter(t_end, integrator->t);
    }
    return integrator->t + h;
}

/* One step of size h from the integrator's time; commits to y only if everything succeeded. */
static tb_status take_step(tb_integrator *integrator, double h, double t_end)
{
    const double t_last = last_stage_time(integrator, h, t_end);
    if (integrator->system.blocks.size == 0) {
        return take_whole_step(integrator, h, t_last, t_end);
    }
    const tb_status status = tb__take_chunked_step(integrator, h, t_last, t_end);
    if (status == TB_STATUS_OK) {
        commit(integrator, h, t_end);
    }
    return status;
}

/* t_end, or the system's first break after t when it comes before
 * (tb_ode_system.events.next_break); *cut tells which. */
static double end_at_break(const tb_integrator *integrator, double t_end, bool *cut)
{
    const tb_ode_system *system = &integrator->system;
    const double next = system->events.next_break != NULL
                            ? system->events.next_break(integrator->t, system->ctx)
                            : INFINITY;
    *cut = next > integrator->t && next < t_end;
    return *cut ? next : t_end;
}

static tb_status fixed_step(tb_integrator *integrator)
{
    tb__onset_forget(integrator); /* y may have been changed since */
    bool cut;
    const double t_end = end_at_break(integrator, integrator->t + integrator->dt, &cut);
    tb_status status = check_time_resolution(integrator->detail, integrator->dt, t_end, "t + dt");
    status = status != TB_STATUS_OK ? status : take_step(integrator, t_end - integrator->t, t_end);
    return status == TB_STATUS_OK && cut ? tb__integrator_check_break(integrator) : status;
}

/* Steps to t_target are counted as advance lands them (see fixed_advance); more than
 * max_steps is refused before the first step, so nothing changes. */
static tb_status check_budget(tb_integrator *integrator, double t_target)
{
    const double steps = (t_target - integrator->t) / integrator->dt - TB__LANDING_SLACK;
    if (steps > (double)integrator->max_steps) {
        return tb__set_detail(integrator->detail, TB_STATUS_TOO_MANY_STEPS,
                              "t_target: %.17g is %.3g steps of dt = %g from t = %.17g, more "
                              "than max_steps = %ld (raise it to allow that); nothing was stepped",
                              t_target, ceil(steps), integrator->dt, integrator->t,
                              integrator->max_steps);
    }
    return check_time_resolution(integrator->detail, integrator->dt, t_target, "t_target");
}

/* The budget ran out (or a step stopped moving time) before t_target: y is the last good
 * step's state. steps on the grid and cuts, the steps cut short at a break or an onset, each
 * have a budget of max_steps (breaks one ulp apart would cut steps for ever). */
static tb_status budget_used(tb_integrator *integrator, double t_target, long steps, long cuts)
{
    return tb__set_detail(integrator->detail, TB_STATUS_TOO_MANY_STEPS,
                          "max_steps = %ld used up (%ld steps, and %ld cut short at breaks or "
                          "onsets) on the way to t = %.17g: stopped at t = %.17g",
                          integrator->max_steps, steps, cuts, t_target, integrator->t);
}

/* Where the system's rest from the integrator's state ends (tb_ode_events.rest_until): its
 * time when it does not rest, or has no rest_until (the chunked path reads none). */
static double rest_end(const tb_integrator *integrator)
{
    const tb_ode_system *system = &integrator->system;
    if (system->events.rest_until == NULL || system->blocks.size != 0) {
        return integrator->t;
    }
    return system->events.rest_until(integrator->t, integrator->y, system->ctx);
}

/* Where the system rests from the integrator's state, its time moves on to where the rest ends
 * or t_target without steps, and the post-step hook runs once there; true when the time moved.
 * *status is the hook's failure, if any (y then as it was). */
static bool jump_at_rest(tb_integrator *integrator, double t_target, tb_status *status)
{
    const tb_ode_system *system = &integrator->system;
    *status = TB_STATUS_OK;
    const double t = integrator->t, until = fmin(rest_end(integrator), t_target);
    if (!(until > t)) {
        return false;
    }
    memcpy(integrator->y_new, integrator->y, system->n * sizeof(double));
    if (system->post_step != NULL) {
        const int rc = system->post_step(until, integrator->y_new, system->ctx);
        if (rc != 0) {
            const tb__step_failure failure = {TB_STATUS_HOOK_FAILED, rc, rc, 0, 0.0};
            *status = tb__fixed_report(integrator, &failure, until - t, until);
            return false;
        }
    }
    memcpy(integrator->y, integrator->y_new, system->n * sizeof(double));
    integrator->t = until;
    integrator->stats.rest_time += until - t;
    tb__onset_forget(integrator); /* the roots kept from the last step's end were at its time */
    return true;
}

static tb_status fixed_advance(tb_integrator *integrator, double t_target)
{
    /* at rest all the way, the call takes no step: max_steps does not bound it */
    tb_status status =
        rest_end(integrator) >= t_target
            ? check_time_resolution(integrator->detail, integrator->dt, t_target, "t_target")
            : check_budget(integrator, t_target);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__onset_forget(integrator); /* y may have been changed since */
    const double dt = integrator->dt;
    double t_start = integrator->t;
    /* Step times are t_start + i dt rather than a running sum, so round-off does not
     * accumulate over long runs; a step cut at a break or an onset leaves i for the rest of the
     * way. */
    long cuts = 0; /* steps cut short at a break or an onset: a budget of max_steps too */
    for (long i = 1; integrator->t < t_target;) {
        if (jump_at_rest(integrator, t_target, &status)) {
            t_start = integrator->t; /* the steps after a rest keep a grid from its end */
            i = 1;
            continue;
        }
        if (status != TB_STATUS_OK) {
            return status;
        }
        double t_end = t_start + (double)i * dt;
        if (t_end >= t_target - TB__LANDING_SLACK * dt) {
            t_end = t_target;
        }
        bool cut;
        t_end = end_at_break(integrator, t_end, &cut);
        if (i > integrator->max_steps || cuts >= integrator->max_steps ||
            !(t_end > integrator->t)) {
            return budget_used(integrator, t_target, i - 1, cuts);
        }
        status = take_step(integrator, t_end - integrator->t, t_end);
        if (status == TB_STATUS_OK && cut && integrator->t == t_end) { /* on a break */
            status = tb__integrator_check_break(integrator);
        }
        if (status != TB_STATUS_OK || integrator->destroy_pending) {
            return status; /* destroyed from a callback at this step: it stops here */
        }
        const bool short_step = cut || integrator->t < t_end;
        i += short_step ? 0 : 1;
        cuts += short_step ? 1 : 0;
    }
    return TB_STATUS_OK;
}

static tb_status fixed_reset(tb_integrator *integrator, double t)
{
    const tb_status status = check_time_resolution(integrator->detail, integrator->dt, t, "t");
    if (status == TB_STATUS_OK) {
        tb__onset_forget(integrator);
        integrator->t = t;
    }
    return status;
}

static void fixed_get_stats(const tb_integrator *integrator, tb_integrator_stats *stats)
{
    *stats = integrator->stats;
}

const tb__backend tb__fixed_step_backend = {
    fixed_create, fixed_advance, fixed_step, fixed_reset, fixed_get_stats, fixed_destroy,
};

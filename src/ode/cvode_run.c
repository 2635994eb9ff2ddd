/* Stepping both SUNDIALS backends share (CVODE, ARKStep, through tb__sundials_ops): advancing
 * to an output time or by one step, outputs from the interpolant handed out through the
 * post-step hook, restarts when the caller changed y or the right-hand side changed, failures
 * named, and the statistics with the counts from before restarts. */
#include "ode/cvode_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <nvector/nvector_serial.h>

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The flags both share (sundials_internal.h's table): CVODE's names for ARKStep's equal values. */
#include <cvode/cvode.h>

void tb__sundials_get_stats(const tb_integrator *integrator, tb_integrator_stats *stats)
{
    const tb__cvode *cvode = integrator->cvode;
    tb_integrator_stats own = {0};
    cvode->ops->read_counters(integrator, &own);
    const tb_integrator_stats *base = &cvode->base;
    stats->steps = base->steps + own.steps;
    stats->derivative_evals = base->derivative_evals + own.derivative_evals + cvode->jacobian_evals;
    stats->jacobian_derivative_evals =
        base->jacobian_derivative_evals + own.jacobian_derivative_evals + cvode->jacobian_evals;
    stats->error_test_failures = base->error_test_failures + own.error_test_failures;
    stats->nonlinear_failures = base->nonlinear_failures + own.nonlinear_failures;
    stats->failed_steps = stats->error_test_failures + stats->nonlinear_failures;
    stats->linear_iterations = base->linear_iterations + own.linear_iterations;
    stats->last_step = own.last_step;
    stats->current_step = own.current_step;
    stats->last_order = own.last_order;
    stats->current_order = own.current_order;
    stats->reinitializations = base->reinitializations;
    stats->nonlinear_iterations = base->nonlinear_iterations + own.nonlinear_iterations;
    stats->jacobian_evals = base->jacobian_evals + own.jacobian_evals;
}

/* --- stepping ----------------------------------------------------------------------------- */

static tb_status restart(tb_integrator *integrator, double t)
{
    tb__cvode *cvode = integrator->cvode;
    tb__sundials_get_stats(integrator, &cvode->base); /* the restart zeroes the counters */
    cvode->jacobian_evals = 0;                        /* now part of base */
    cvode->base.reinitializations++;
    const int flag = cvode->ops->reinit(integrator);
    if (flag != CV_SUCCESS) {
        char name[64];
        tb__sundials_flag_name(cvode, flag, name, sizeof name);
        return tb__set_detail(integrator->detail, TB_STATUS_SOLVER_FAILED,
                              "%s restart at t = %.17g: ReInit returned %s: %s", cvode->ops->name,
                              t, name, cvode->message);
    }
    integrator->t = t;
    cvode->t_origin = t;
    cvode->break_at = INFINITY; /* the march sets the next before its first step */
    cvode->rhs_generation = tb__sundials_rhs_generation(&integrator->system);
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
    if (cvode->stale || tb__sundials_rhs_generation(&integrator->system) != cvode->rhs_generation ||
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
    default:
        return flag == cvode->ops->hook_flags[0] || flag == cvode->ops->hook_flags[1]
                   ? TB_STATUS_HOOK_FAILED
                   : TB_STATUS_SOLVER_FAILED;
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
    tb__sundials_flag_name(cvode, flag, name, sizeof name);
    if (cvode->derivative_status != 0) {
        snprintf(derivative_note, sizeof derivative_note, "; derivative returned %d at t = %.17g",
                 cvode->derivative_status, cvode->derivative_time);
    } else if (cvode->non_finite_index < n) {
        snprintf(derivative_note, sizeof derivative_note,
                 "; derivative gave dydt[%zu] = %g at t = %.17g", cvode->non_finite_index,
                 cvode->non_finite_value, cvode->non_finite_time);
    }
    return tb__set_detail(integrator->detail, failure_status(flag, cvode, n),
                          "%s %s on the way to t = %.17g, stopped at t = %.17g%s: %s",
                          cvode->ops->name, name, t_target, integrator->t, derivative_note,
                          cvode->message);
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
        flag = cvode->ops->evolve(cvode->mem, horizon, cvode->y, tau_reached, CV_ONE_STEP);
    }
    if (flag >= 0 && mode == CV_NORMAL) {
        flag = *tau_reached >= tau_out
                   ? cvode->ops->get_dky(cvode->mem, tau_out, 0, cvode->y)
                   : cvode->ops->evolve(cvode->mem, tau_out, cvode->y, tau_reached, CV_NORMAL);
    } else if (flag >= 0 && !stepped) {
        flag = cvode->ops->evolve(cvode->mem, horizon, cvode->y, tau_reached, CV_ONE_STEP);
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
        if (flag == TB__CV_STOPPED) {
            return TB_STATUS_OK; /* destroyed from a callback: freed as the call returns */
        }
        /* the rhs changed at an event: restart there, go on (one step: the next call does) */
        const bool go_on = flag == TB__CV_EVENT_RESTART && mode == CV_NORMAL;
        status = flag < 0 ? fail(integrator, flag, tau_reached, t_out)
                 : go_on  ? restart(integrator, cvode->t_origin + tau_reached)
                          : hand_out(integrator,
                                    mode == CV_NORMAL ? t_out : cvode->t_origin + tau_reached);
        if (go_on && status == TB_STATUS_OK) { /* at an event or a break: may it go on? */
            status = tb__integrator_check_break(integrator);
        }
        cvode->stale = cvode->stale || (flag == TB__CV_EVENT_RESTART && !go_on);
        if (!go_on || status != TB_STATUS_OK || integrator->destroy_pending) {
            return status;
        }
    }
}

tb_status tb__sundials_advance(tb_integrator *integrator, double t_target)
{
    return run(integrator, t_target, CV_NORMAL);
}

tb_status tb__sundials_step(tb_integrator *integrator)
{
    return run(integrator, INFINITY, CV_ONE_STEP);
}

tb_status tb__sundials_reset(tb_integrator *integrator, double t)
{
    return restart(integrator, t);
}

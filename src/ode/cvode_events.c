/* Events and step limits for the SUNDIALS backends (CVODE and ARKStep alike, through
 * tb__sundials_ops; CVODE's names below): the system's root functions registered with
 * CVodeRootInit, so that a step ends on each sign change, and a step limit asked of the system
 * after every step (tb_ode_system.events.step_limit), applied as CVODE's stop time: CVodeSetMaxStep
 * would act only from the step after next, since CVODE picks each step's size at the end of the
 * one before, while a stop time cuts the very next step. With either, an advance steps one CVODE
 * step at a time (CV_ONE_STEP) and interpolates the output, as the plain path does. */
#include "ode/cvode_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>

#include <math.h>
#include <stdlib.h>

/* CVODE's root function: the system's at t = t_origin + tau. */
static int roots(sunrealtype tau, N_Vector y, sunrealtype *g, void *user_data)
{
    tb_integrator *integrator = user_data;
    const tb_ode_system *system = &integrator->system;
    return system->events.roots(integrator->cvode->t_origin + tau, N_VGetArrayPointer(y), g,
                                system->ctx);
}

tb_status tb__cvode_events_init(tb_integrator *integrator, tb_error *error)
{
    tb__cvode *cvode = integrator->cvode;
    const tb_ode_system *system = &integrator->system;
    if (system->events.root_count > 0) {
        cvode->roots_found = tb__malloc_array(system->events.root_count, sizeof(int));
        if (cvode->roots_found == NULL) {
            return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "%zu root flags",
                                 system->events.root_count);
        }
        int flag = cvode->ops->root_init(cvode->mem, (int)system->events.root_count, roots);
        if (flag == CV_SUCCESS) {
            /* a function that starts at zero (a body set down touching) is not an error */
            flag = cvode->ops->no_inactive_root_warn(cvode->mem);
        }
        if (flag != CV_SUCCESS) {
            return tb__set_error(error, TB_STATUS_SOLVER_FAILED,
                                 "%s set-up: RootInit for %zu functions returned %d: %s",
                                 cvode->ops->name, system->events.root_count, flag, cvode->message);
        }
    }
    if (system->events.step_limit != NULL) {
        cvode->y_step = N_VClone(cvode->y);
        cvode->dydt_step = N_VClone(cvode->y);
        if (cvode->y_step == NULL || cvode->dydt_step == NULL) {
            return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "step-limit state");
        }
    }
    return TB_STATUS_OK;
}

void tb__cvode_events_free(tb__cvode *cvode)
{
    free(cvode->roots_found);
    cvode->roots_found = NULL;
    N_Vector *vectors[2] = {&cvode->y_step, &cvode->dydt_step};
    for (int k = 0; k < 2; ++k) {
        if (*vectors[k] != NULL) {
            N_VDestroy(*vectors[k]);
            *vectors[k] = NULL;
        }
    }
}

bool tb__cvode_marches(const tb_integrator *integrator)
{
    return integrator->system.events.root_count > 0 ||
           integrator->system.events.step_limit != NULL ||
           integrator->system.events.next_break != NULL || integrator->cvode->sparse != NULL;
}

/* CVODE stopped at an event at tau: counts it and names the lowest function that fired. */
static void note_event(tb_integrator *integrator, double tau)
{
    tb__cvode *cvode = integrator->cvode;
    tb_integrator_events *events = &integrator->events;
    cvode->ops->root_info(cvode->mem, cvode->roots_found);
    events->count++;
    events->last_time = cvode->t_origin + tau;
    for (size_t i = 0; i < integrator->system.events.root_count; ++i) {
        if (cvode->roots_found[i] != 0) {
            events->last_root = (long)i;
            events->last_direction = cvode->roots_found[i] > 0 ? 1 : -1;
            return;
        }
    }
}

/* The next step from CVODE's internal time tn is cut to the system's limit at (tn, y_n). */
static int limit_next_step(tb_integrator *integrator, sunrealtype tn)
{
    tb__cvode *cvode = integrator->cvode;
    const tb_ode_system *system = &integrator->system;
    /* a break ahead: CVODE stops on it (and the march restarts there) */
    const double next_t = system->events.next_break != NULL
                              ? system->events.next_break(cvode->t_origin + tn, system->ctx)
                              : INFINITY;
    const double next = next_t - cvode->t_origin;
    cvode->break_stop = isfinite(next) && next > tn ? next : INFINITY;
    cvode->break_at = isfinite(cvode->break_stop) ? next_t : INFINITY;
    if (system->events.step_limit == NULL) {
        return cvode->ops->set_stop_time(cvode->mem, isfinite(cvode->break_stop) ? cvode->break_stop
                                                                                 : tn + 1e300);
    }
    const double *state = N_VGetArrayPointer(cvode->y), *rate = NULL;
    if (cvode->started) { /* y may hold an interpolated output: take CVODE's own y_n, y'_n */
        int flag = cvode->ops->get_dky(cvode->mem, tn, 0, cvode->y_step);
        if (flag == CV_SUCCESS) {
            flag = cvode->ops->get_dky(cvode->mem, tn, 1, cvode->dydt_step);
        }
        if (flag != CV_SUCCESS) {
            return flag;
        }
        state = N_VGetArrayPointer(cvode->y_step);
        rate = N_VGetArrayPointer(cvode->dydt_step);
    }
    const double limit = system->events.step_limit(cvode->t_origin + tn, state, rate, system->ctx);
    /* no limit, or one below the time's resolution: a stop time far ahead (6.x cannot clear
     * one) */
    const double stop = limit > 0.0 && isfinite(limit) && tn + limit > tn ? tn + limit : tn + 1e300;
    return cvode->ops->set_stop_time(cvode->mem, fmin(stop, cvode->break_stop));
}

/* The system's at_event at the event CVODE stopped at (y there): whether it changed the
 * right-hand side. */
static bool changed_at_event(tb_integrator *integrator, double tau)
{
    const tb_ode_system *system = &integrator->system;
    if (system->events.at_event == NULL) {
        return false;
    }
    const unsigned long long before =
        system->lifetime.rhs_generation != NULL ? system->lifetime.rhs_generation(system->ctx) : 0;
    system->events.at_event(integrator->cvode->t_origin + tau,
                            N_VGetArrayPointer(integrator->cvode->y), system->ctx);
    return system->lifetime.rhs_generation != NULL &&
           system->lifetime.rhs_generation(system->ctx) != before;
}

/* The last step ended on the break at tn, past the last call's output (interpolated before it):
 * the curve after it is another, so the march restarts there, with the solver's y on it, as where
 * a step stops on one inside a call (tb__cvode_march). Without it the next call went on from tn
 * with the history of the piece before and no check of the break. */
static int restart_on_break_reached(tb_integrator *integrator, sunrealtype tn,
                                    sunrealtype *tau_reached)
{
    *tau_reached = tn;
    const int flag =
        integrator->cvode->ops->get_dky(integrator->cvode->mem, tn, 0, integrator->cvode->y);
    if (flag == CV_SUCCESS) {
        changed_at_event(integrator, tn); /* as at a stop on a break in tb__cvode_march */
    }
    return flag == CV_SUCCESS ? TB__CV_EVENT_RESTART : flag;
}

/* max_steps used up before tau_out. */
static int too_much_work(tb_integrator *integrator, double tau_out)
{
    snprintf(integrator->cvode->message, sizeof integrator->cvode->message,
             "max_steps = %ld steps taken (one at a time, for the events and the step limit) "
             "before reaching t = %.17g",
             integrator->max_steps, tau_out);
    return CV_TOO_MUCH_WORK;
}

int tb__cvode_march(tb_integrator *integrator, double tau_out, int mode, double horizon,
                    sunrealtype *tau_reached)
{
    tb__cvode *cvode = integrator->cvode;
    for (long calls = 0;; ++calls) {
        if (integrator->destroy_pending) {
            return TB__CV_STOPPED; /* destroyed by a callback at the last step: stop there */
        }
        sunrealtype tn = *tau_reached;
        if (cvode->started) {
            cvode->ops->current_time(cvode->mem, &tn);
        }
        if (mode == CV_NORMAL && cvode->started && tn >= tau_out) {
            return cvode->ops->get_dky(cvode->mem, tau_out, 0, cvode->y);
        }
        if (cvode->started && tn == cvode->break_stop && *tau_reached < tn) {
            return restart_on_break_reached(integrator, tn, tau_reached);
        }
        if (calls == integrator->max_steps) {
            return too_much_work(integrator, tau_out);
        }
        int flag = limit_next_step(integrator, tn);
        flag = flag == CV_SUCCESS ? tb__cvode_sparse_refresh(integrator, tn) : flag;
        if (flag != CV_SUCCESS) {
            return flag;
        }
        cvode->started = true;
        /* in one-step mode tout only sets the first step's estimate and the direction */
        flag = cvode->ops->evolve(cvode->mem, horizon, cvode->y, tau_reached, CV_ONE_STEP);
        if (flag == CV_ROOT_RETURN) {
            note_event(integrator, *tau_reached);
            /* an event past tau_out: the output is interpolated before it, and the changed
             * right-hand side restarts the next call from there */
            if (changed_at_event(integrator, *tau_reached) &&
                (mode == CV_ONE_STEP || *tau_reached < tau_out)) {
                return TB__CV_EVENT_RESTART;
            }
        }
        /* on a break: the curve after it is another; restart there (on the output: at the
         * next call; a break past tau_out is beyond this call). A root found on the break (a gap
         * a jumping key closed) is on it too: CVODE must not go on with the history before. */
        const bool on_break = (flag == CV_TSTOP_RETURN || flag == CV_ROOT_RETURN) &&
                              *tau_reached == cvode->break_stop;
        if (on_break && (mode == CV_ONE_STEP || *tau_reached < tau_out)) {
            if (flag == CV_TSTOP_RETURN) {                  /* a root's at_event ran above */
                changed_at_event(integrator, *tau_reached); /* e.g. what a moving body wakes */
            }
            return TB__CV_EVENT_RESTART;
        }
        cvode->stale = cvode->stale || (on_break && *tau_reached == tau_out);
        if (flag < 0 || mode == CV_ONE_STEP) {
            return flag;
        }
        if (*tau_reached >= tau_out && flag == CV_ROOT_RETURN) {
            return *tau_reached == tau_out ? CV_SUCCESS
                                           : cvode->ops->get_dky(cvode->mem, tau_out, 0, cvode->y);
        }
    }
}

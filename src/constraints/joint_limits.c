/* Joint limits and motors: the axial row (a hinge's angle about its axis, a slider's travel
 * along it, joint_rows.c) enters the solve while a stop holds the joint or a motor drives it.
 *
 * A stop is a unilateral row switched at events. Free, a joint engages a stop where its
 * coordinate reaches the bound moving into it: an impact, the axial rate reversed times the
 * restitution e by the momenta projection (the impulse J^T mu through every joint's rows with
 * the axial row's rate set to -e times its rate before, exact), after the position projection
 * has put the coordinate on the bound (or where it would be after the bounce, below). If the joint
 * then separates faster than TB__STOP_REST_RATE it is free again (a bounce); else the stop holds it
 * (the row in the solve, its position and rate projected to the bound and 0) while its lambda
 * pushes, and releases it where lambda would pull. Fixed-step methods take these decisions at every
 * step's end (a crossing is found to a step; its overshoot d is projected back to e d short of the
 * bound, where the joint would be at its speed); adaptive ones at the roots of one function per
 * limited joint: the gap to the nearer stop while free, the stop's push while held (CVODE
 * locates both).
 *
 * A motor's row asks the axial acceleration TB__JOINT_MOTOR_RATE (speed - rate) (velocity) or
 * K^2 (target - coordinate) - 2 K rate with K = TB__JOINT_MOTOR_RATE (position, critically
 * damped) of the solve; where its |lambda| would pass motor_max_force it is fixed at the cap
 * (applied as a load) and the rest solved without it: a box-constrained solve, exact for one
 * motor, one pass per capped motor for several. */
#include "constraints/joints_internal.h"

#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <string.h>

/* rad/s or m/s: a stop whose impact leaves the joint separating slower than this holds it
 * (resting contact), rather than letting it make ever smaller bounces. */
#define TB__STOP_REST_RATE 1e-6
/* rad or m: under adaptive methods a free joint this close to a stop at an event (CVODE's
 * root, located to about 100 roundings) is on it. */
#define TB__STOP_ENGAGE_GAP 1e-7
/* rad or m: where an event's impact leaves a joint, inside its bound (engage); far below what
 * a frame shows (the tests ask 1e-12 past a stop at most) and far above the projection's 1e-13
 * tolerance, so that the gap's sign after the event is certain. */
#define TB__STOP_EVENT_INSIDE 1e-12
/* what an exactly zero root becomes (scene_events.c's TB__GAP_FOR_ZERO, same reason) */
#define TB__ROOT_FOR_ZERO 1e-150

static bool has_axial_row(const tb__joint *joint, bool with_motors)
{
    return joint->stop != TB__STOP_NONE || (with_motors && joint->def.motor != TB_MOTOR_OFF);
}

void tb__joints_configure_rows(tb__joints *js, bool with_motors)
{
    for (size_t j = 0; j < js->count; ++j) {
        tb__joint *joint = &js->joints[j];
        const bool plain = !joint->def.has_limits && joint->def.motor == TB_MOTOR_OFF &&
                           joint->motor_state == TB__MOTOR_NONE && !joint->axial_first;
        if (joint->broken || (joint->def.soft_frequency > 0.0 && !joint->axial_first) ||
            (plain && joint->rows == joint->base_rows)) { /* nothing to change */
            continue;
        }
        const bool extra = has_axial_row(joint, with_motors);
        if (joint->axial_first) { /* its rows stay laid out; the axial row alone is solved */
            joint->solved_rows = extra ? 1 : 0;
        } else {
            joint->rows = joint->base_rows + (extra ? 1 : 0);
            joint->solved_rows = joint->rows;
        }
        joint->motor_state = !with_motors || joint->def.motor == TB_MOTOR_OFF ? TB__MOTOR_NONE
                             : joint->stop != TB__STOP_NONE                   ? TB__MOTOR_AT_STOP
                                                                              : TB__MOTOR_ROW;
        joint->motor_load = 0.0;
        joint->axial_zero = joint->stop == TB__STOP_LOWER           ? joint->def.limits[0]
                            : joint->stop == TB__STOP_UPPER         ? joint->def.limits[1]
                            : joint->def.motor == TB_MOTOR_POSITION ? joint->def.motor_target
                                                                    : 0.0;
        joint->axial_zero += joint->impact ? joint->impact_back : 0.0;
    }
}

double tb__joint_motor_acceleration(const tb__joint *joint, const tb__joint_eval *eval, double rate)
{
    const double k = TB__JOINT_MOTOR_RATE;
    return joint->def.motor == TB_MOTOR_VELOCITY
               ? k * (joint->def.motor_speed - rate)
               : -k * k * eval->C[joint->axial_row] - 2.0 * k * rate;
}

bool tb__joints_cap_motors(tb__joints *js, const tb_scene *scene, double *dydt)
{
    bool capped = false;
    for (size_t j = 0; j < js->count; ++j) {
        tb__joint *joint = &js->joints[j];
        tb__joint_eval *eval = &js->evals[j];
        const int r = joint->axial_row;
        if (joint->motor_state != TB__MOTOR_ROW || joint->broken ||
            !(fabs(eval->lambda[r]) > joint->def.motor_max_force)) {
            continue;
        }
        const double cap = copysign(joint->def.motor_max_force, eval->lambda[r]);
        joint->motor_state = TB__MOTOR_CAPPED;
        tb__joint_drop_axial_row(joint);
        eval->lambda[r] = eval->rhs[r] = cap; /* the solve copies rhs into lambda: keep it */
        tb__joint_add_row_load(js, scene, j, r, cap, dydt);
        capped = true;
    }
    return capped;
}

/* Joint j's axial rate at (t, y), its axial row in the evals (the stop already set). */
static double axial_rate(tb__joints *js, const tb_scene *scene, double t, const double *y, size_t j)
{
    tb__joint *joint = &js->joints[j];
    tb__motion m[2];
    const tb__body *constants[2];
    for (int s = 0; s < 2; ++s) {
        tb__joint_motion(scene, t, y, joint->body[s], false, &m[s]);
        constants[s] = tb__joint_body_constants(scene, joint->body[s]);
    }
    tb__joints_configure_rows(js, false);
    tb__joint_rows(joint, &m[0], &m[1], constants, &js->evals[j]);
    double rate[TB__JOINT_ROWS];
    tb__joint_row_velocities(joint, &js->evals[j], &m[0], &m[1], rate);
    return rate[joint->axial_row];
}

/* Joint j, at coordinate c, engages stop: an impact when it moves into it. A fixed step finds
 * it past the stop by c - bound; at its speed, it would have come back e (c - bound) by the
 * step's end, which is where the position projection puts it (exact for a constant speed). At an
 * event (CVODE's root or a fixed step's located onset, within roundings of the bound) it goes at
 * least TB__STOP_EVENT_INSIDE inside the bound: a joint that bounces off a stop while a load pushes
 * it back (a motor's door) leaves it by ever smaller bounces, and one left on the bound to the
 * rounding, its root function of either sign, could cross no root on its way back and go through
 * the stop. */
static void engage(tb__joints *js, const tb_scene *scene, double t, const double *y, size_t j,
                   int stop, double c, bool event)
{
    tb__joint *joint = &js->joints[j];
    joint->stop = stop;
    joint->impact = false;
    const double rate = axial_rate(js, scene, t, y, j);
    joint->impact = tb__stop_sign(stop) * rate < 0.0;
    joint->impact_rate = joint->impact ? -joint->def.restitution * rate : 0.0;
    const double back = -joint->def.restitution * (c - joint->def.limits[stop - 1]);
    const double s = tb__stop_sign(stop); /* an event's: at least TB__STOP_EVENT_INSIDE inside */
    joint->impact_back =
        event && !(s * back > TB__STOP_EVENT_INSIDE) ? s * TB__STOP_EVENT_INSIDE : back;
    if (event && !joint->impact) { /* leaving the stop: it stays free, its rate as it is, put */
        joint->impact = joint->leaving = true; /* inside the bound all the same */
        joint->impact_rate = rate;
    }
}

void tb__joints_after_impacts(tb__joints *js)
{
    for (size_t j = 0; j < js->count; ++j) {
        tb__joint *joint = &js->joints[j];
        if (joint->impact && (joint->leaving || tb__stop_sign(joint->stop) * joint->impact_rate >
                                                    TB__STOP_REST_RATE)) {
            joint->stop = TB__STOP_NONE; /* a bounce, or leaving it */
        }
        joint->impact = joint->leaving = false;
        joint->impact_back = 0.0;
    }
}

static double coordinate_at(const tb__joints *js, const tb_scene *scene, double t, const double *y,
                            size_t j)
{
    const tb__joint *joint = &js->joints[j];
    tb__motion m[2];
    for (int s = 0; s < 2; ++s) {
        tb__joint_motion(scene, t, y, joint->body[s], false, &m[s]);
    }
    return tb__joint_axial_coordinate(joint, &m[0], &m[1]);
}

/* The derivative at (t, y) into the joints' scratch, for the held stops' lambdas; 0 or its
 * failure. */
int tb__joints_held_lambdas(tb__joints *js, const tb_scene *scene, double t, const double *y)
{
    const size_t n = tb_scene_state_size(scene);
    if (n > js->scratch_size) {
        double *grown = tb__realloc_array(js->scratch, n, sizeof(double));
        if (grown == NULL) {
            return -1;
        }
        js->scratch = grown;
        js->scratch_size = n;
    }
    return tb_scene_derivative(t, y, js->scratch, (void *)scene);
}

static bool any_held(const tb__joints *js)
{
    for (size_t j = 0; j < js->count; ++j) {
        if (js->joints[j].stop != TB__STOP_NONE && !js->joints[j].broken) {
            return true;
        }
    }
    return false;
}

/* The stop's push (N or N m, positive while it pushes) from the last derivative. */
static double push(const tb__joints *js, size_t j)
{
    return js->joints[j].stop_push;
}

/* A stop switched at t (an event when gap > 0). */
static void note_switch(tb__joint *joint, int before, double t, double gap, bool *changed)
{
    *changed = true;
    if (gap > 0.0) {
        joint->switched = true;
        joint->stop_before = before;
        joint->switched_at = t;
    }
}

void tb__joints_undo_later_switches(tb__joints *js, double t)
{
    for (size_t j = 0; j < js->count; ++j) {
        tb__joint *joint = &js->joints[j];
        if (joint->switched && t < joint->switched_at) {
            joint->stop = joint->stop_before;
        }
        joint->switched = joint->switched && t <= joint->switched_at;
    }
}

/* Engages or releases the stops at (t, y); gap: how close a free joint must be to a stop
 * (negative: past it) to engage it, whatever its direction (fixed steps) or only moving into
 * it (events). *changed: whether one did. */
static int switch_stops(tb__joints *js, const tb_scene *scene, double t, const double *y,
                        double gap, bool *changed)
{
    const int rc = any_held(js) ? tb__joints_held_lambdas(js, scene, t, y) : 0;
    for (size_t j = 0; j < js->count && rc == 0; ++j) {
        tb__joint *joint = &js->joints[j];
        if (!joint->def.has_limits || joint->broken) {
            continue;
        }
        const int before = joint->stop;
        if (joint->stop != TB__STOP_NONE) {
            if (push(js, j) <= 0.0) {
                joint->stop = TB__STOP_NONE;
                note_switch(joint, before, t, gap, changed);
            }
            continue;
        }
        const double c = coordinate_at(js, scene, t, y, j);
        const int stop = c - joint->def.limits[0] < gap   ? TB__STOP_LOWER
                         : joint->def.limits[1] - c < gap ? TB__STOP_UPPER
                                                          : TB__STOP_NONE;
        if (stop != TB__STOP_NONE) {
            const bool inside =
                tb__stop_sign(stop) * (c - joint->def.limits[stop - 1]) >= TB__STOP_EVENT_INSIDE;
            engage(js, scene, t, y, j, stop, c, gap > 0.0);
            if (joint->leaving && inside) { /* leaving, its gap's sign certain: as it is */
                joint->stop = TB__STOP_NONE;
                joint->impact = joint->leaving = false;
                continue;
            }
            note_switch(joint, before, t, gap, changed);
        }
    }
    return rc;
}

int tb__joints_step_limits(tb__joints *js, const tb_scene *scene, double t, double *y)
{
    bool changed = false;
    return switch_stops(js, scene, t, y, 0.0, &changed);
}

size_t tb__joints_root_count(const void *constraints)
{
    const tb__joints *js = constraints;
    size_t count = 0;
    for (size_t j = 0; js != NULL && j < js->count; ++j) {
        count += js->joints[j].def.has_limits ? 1 : 0;
    }
    return count;
}

int tb__joints_roots(void *constraints, const tb_scene *scene, double t, const double *y, double *g)
{
    tb__joints *js = constraints;
    const int rc = any_held(js) ? tb__joints_held_lambdas(js, scene, t, y) : 0;
    size_t k = 0;
    for (size_t j = 0; j < js->count && rc == 0; ++j) {
        const tb__joint *joint = &js->joints[j];
        if (!joint->def.has_limits) {
            continue;
        }
        double value = 1.0; /* broken: never again */
        if (!joint->broken && joint->stop != TB__STOP_NONE) {
            value = push(js, j);
        } else if (!joint->broken) {
            const double c = coordinate_at(js, scene, t, y, j);
            value = fmin(c - joint->def.limits[0], joint->def.limits[1] - c);
        }
        g[k++] = value == 0.0 ? TB__ROOT_FOR_ZERO : value;
    }
    return rc;
}

int tb__joints_at_event(void *constraints, const tb_scene *scene, double t, double *y)
{
    tb__joints *js = constraints;
    bool changed = false;
    int rc = switch_stops(js, scene, t, y, TB__STOP_ENGAGE_GAP, &changed);
    if (rc == 0 && changed) {
        rc = tb__joints_project(constraints, scene, t, y);
        ((tb_scene *)scene)->effects_generation++; /* the rows changed: CVODE restarts */
    }
    return rc;
}

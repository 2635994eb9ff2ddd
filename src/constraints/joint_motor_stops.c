/* A motor on a joint with limits, while a stop holds the joint (a hinge's motor driving a door
 * into its stop, a slider's motor pushing a carriage against its end of travel).
 *
 * The motor and the stop act on the same axial row, one DOF: its acceleration a (sign s: +1 at
 * a lower stop, -1 at an upper one, so that s a > 0 leaves the stop) responds to the row's total
 * lambda as s a = g (s lambda - P0), g > 0, where P0 is the push the stop needs to hold the joint
 * with no motor. The stop asks s a >= 0 with its push >= 0, one of them 0; the motor asks its
 * acceleration a_m under |lambda_m| <= max. So:
 *
 *   - s a_m < 0 (the motor drives into the stop): the stop wins, a = 0, and the motor can never
 *     reach a_m: it pushes at its cap, lambda_m = -s max, and the stop pushes P0 + max (a door
 *     with no other load: the stop takes exactly the motor's max torque);
 *   - s a_m >= 0 (away): the motor's row alone, capped as a free motor's; if the capped motor
 *     cannot lift the joint off (s cap < P0), the stop holds with the motor at its cap beside it.
 *
 * Each case is one or two more solves of the derivative, for these joints only while their stops
 * hold them. The stop's push the release reads (joint.stop_push, the root function under CVODE)
 * is the stop's lambda where its row is solved and P0 - s lambda_m where the motor's row replaced
 * it: negative while the motor pulls the joint off, continuous through the release. */
#include "constraints/joints_internal.h"

#include <math.h>

/* The motor's asked axial acceleration at a stop (the row's C is measured from the bound). */
static double asked_at_stop(const tb__joint *joint, const tb__joint_eval *eval)
{
    const int r = joint->axial_row;
    const double k = TB__JOINT_MOTOR_RATE, rate = eval->rate[r];
    if (joint->def.motor == TB_MOTOR_VELOCITY) {
        return k * (joint->def.motor_speed - rate);
    }
    const double coordinate = eval->C[r] + joint->axial_zero;
    return -k * k * (coordinate - joint->def.motor_target) - 2.0 * k * rate;
}

/* The first solve had the stop's row alone: into the stop, the motor at its cap as a load;
 * away, the motor's row instead of the stop's. */
static void decide(tb__joints *js, const tb_scene *scene, size_t j, double *dydt)
{
    tb__joint *joint = &js->joints[j];
    tb__joint_eval *eval = &js->evals[j];
    const int r = joint->axial_row;
    const double s = tb__stop_sign(joint->stop);
    joint->held_push = s * eval->lambda[r];
    if (s * asked_at_stop(joint, eval) < 0.0) {
        joint->motor_state = TB__MOTOR_LOAD;
        joint->motor_load = -s * joint->def.motor_max_force;
        tb__joint_add_row_load(js, scene, j, r, joint->motor_load, dydt);
    } else {
        joint->motor_state = TB__MOTOR_AWAY;
        joint->axial_zero = joint->def.motor == TB_MOTOR_POSITION ? joint->def.motor_target : 0.0;
    }
}

/* The motor's row pulling the joint off passed its cap: fixed there as a load; the stop's row
 * back where the capped motor cannot lift the joint off. */
static void cap_away(tb__joints *js, const tb_scene *scene, size_t j, double *dydt)
{
    tb__joint *joint = &js->joints[j];
    tb__joint_eval *eval = &js->evals[j];
    const int r = joint->axial_row;
    const double cap = copysign(joint->def.motor_max_force, eval->lambda[r]);
    tb__joint_add_row_load(js, scene, j, r, cap, dydt);
    if (tb__stop_sign(joint->stop) * cap < joint->held_push) {
        joint->motor_state = TB__MOTOR_LOAD;
        joint->motor_load = cap;
        joint->axial_zero = joint->def.limits[joint->stop - 1];
    } else {
        joint->motor_state = TB__MOTOR_CAPPED;
        tb__joint_drop_axial_row(joint);
        eval->lambda[r] = eval->rhs[r] = cap; /* the solve copies rhs into lambda: keep it */
    }
}

bool tb__joints_motors_at_stops(tb__joints *js, const tb_scene *scene, double *dydt)
{
    bool changed = false;
    for (size_t j = 0; j < js->count; ++j) {
        const tb__joint *joint = &js->joints[j];
        if (joint->broken) {
            continue;
        }
        if (joint->motor_state == TB__MOTOR_AT_STOP) {
            decide(js, scene, j, dydt);
            changed = true;
        } else if (joint->motor_state == TB__MOTOR_AWAY &&
                   fabs(js->evals[j].lambda[joint->axial_row]) > joint->def.motor_max_force) {
            cap_away(js, scene, j, dydt);
            changed = true;
        }
    }
    return changed;
}

void tb__joints_note_pushes(tb__joints *js)
{
    for (size_t j = 0; j < js->count; ++j) {
        tb__joint *joint = &js->joints[j];
        if (joint->stop == TB__STOP_NONE || joint->broken) {
            joint->stop_push = 0.0;
            continue;
        }
        const double axial = tb__stop_sign(joint->stop) * js->evals[j].lambda[joint->axial_row];
        const bool motor_row =
            joint->motor_state == TB__MOTOR_AWAY || joint->motor_state == TB__MOTOR_CAPPED;
        joint->stop_push = motor_row ? joint->held_push - axial : axial;
    }
}

int tb__joints_release_at_output(tb__joints *js, const tb_scene *scene, double t, double *y)
{
    bool any = false;
    for (size_t j = 0; j < js->count; ++j) {
        const tb__joint *joint = &js->joints[j];
        any = any ||
              (joint->stop != TB__STOP_NONE && !joint->broken && joint->def.motor != TB_MOTOR_OFF);
    }
    const int rc = any ? tb__joints_held_lambdas(js, scene, t, y) : 0;
    bool released = false;
    for (size_t j = 0; any && rc == 0 && j < js->count; ++j) {
        tb__joint *joint = &js->joints[j];
        if (joint->stop != TB__STOP_NONE && !joint->broken && joint->def.motor != TB_MOTOR_OFF &&
            joint->stop_push <= 0.0) {
            joint->stop = TB__STOP_NONE;
            released = true;
        }
    }
    if (released) { /* the rows changed: CVODE restarts */
        ((tb_scene *)scene)->effects_generation++;
    }
    return rc;
}

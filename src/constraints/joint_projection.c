/* tb_scene_project_joints: the post-step projection (joint_stage.c) as a call, for a start off
 * the joints. It works on a copy of the states, so a refusal changes nothing. */
#include "constraints/joints_internal.h"

#include "core/validate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rounds of the projection (each a few Newton iterations, stopping at round-off): from a start
 * 1 mm off, Newton's quadratic convergence reaches round-off within the first. */
#define TB__PROJECTION_ROUNDS 4

/* The largest position and velocity error of the projected joints at y; *worst_joint the
 * joint of the larger. */
static void largest_error(const tb_scene *scene, const tb__joints *js, const double *y,
                          double *worst, size_t *worst_joint)
{
    *worst = 0.0;
    *worst_joint = 0;
    for (size_t j = 0; j < js->count; ++j) {
        double position = 0.0, velocity = 0.0;
        if (js->joints[j].solved_rows == 0 || js->joints[j].def.soft_frequency > 0.0) {
            /* broken, or soft (a spring: not projected, but for its stop's axial row) */
            continue;
        }
        (void)tb_scene_joint_error(scene, y, j, &position, &velocity);
        const double error =
            isnan(position) || isnan(velocity) ? INFINITY : fmax(position, velocity);
        if (error > *worst) {
            *worst = error;
            *worst_joint = j;
        }
    }
}

static tb_status check_call(tb_scene *scene, double tolerance)
{
    tb_status status = tb__validate_nonnegative(scene->detail, tolerance, "tolerance");
    return status != TB_STATUS_OK ? status : tb__scene_check_idle(scene, "projecting the joints");
}

tb_status tb_scene_project_joints(tb_scene *scene, double tolerance, double *out_error)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = check_call(scene, tolerance);
    tb__joints *js = scene->constraints;
    if (status != TB_STATUS_OK || js == NULL) {
        if (status == TB_STATUS_OK && out_error != NULL) {
            *out_error = 0.0;
        }
        return status;
    }
    const double accept = tolerance > 0.0 ? tolerance : TB_JOINT_PROJECTION_TOLERANCE;
    const size_t n = tb_scene_state_size(scene);
    double *y = tb__malloc_array(n > 0 ? n : 1, sizeof(double)), worst = INFINITY;
    size_t joint = 0;
    if (y == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "a copy of the states");
    }
    memcpy(y, tb_scene_states_const(scene), n * sizeof(double));
    for (int round = 0; round < TB__PROJECTION_ROUNDS && !(worst <= accept); ++round) {
        if (tb__joints_project(js, scene, scene->time, y) != 0) {
            break;
        }
        largest_error(scene, js, y, &worst, &joint);
    }
    if (worst <= accept) {
        memcpy(tb_scene_states(scene), y, n * sizeof(double));
        if (out_error != NULL) {
            *out_error = worst;
        }
    } else {
        status = tb__scene_fail(scene, TB_STATUS_SOLVER_FAILED,
                                "joints[%zu]: the projection left an error of %.3g, more than the "
                                "tolerance %.3g (m or rad, m/s or rad/s)",
                                joint, worst, accept);
    }
    free(y);
    return status;
}

static bool keyframed(const tb_scene *scene, size_t body)
{
    return body != TB_WORLD && tb__body_fixed(scene, body) && !tb__body_static(scene, body);
}

void tb__joints_conserved(const void *constraints, const tb_scene *scene, tb_conserved *c)
{
    const tb__joints *js = constraints;
    for (size_t j = 0; j < js->count; ++j) {
        const tb__joint *joint = &js->joints[j];
        const tb_joint_def *def = &joint->def;
        /* An ideal joint between two dynamic bodies puts equal and opposite loads on them about
         * one point (its rows' torques are couples): it keeps momentum and does no work. */
        if (!tb__joint_side_moves(scene, joint->body[0]) ||
            !tb__joint_side_moves(scene, joint->body[1])) {
            c->linear_momentum = c->angular_momentum = 0;
            c->angular_momentum_about_center_of_mass = 0;
        }
        /* work: a moving support, a motor, a soft joint's damper (its spring's energy is in
         * tb_scene_potential_energy), a stop that is not perfectly elastic */
        if (keyframed(scene, joint->body[0]) || keyframed(scene, joint->body[1]) ||
            def->motor != TB_MOTOR_OFF || def->soft_damping_ratio > 0.0 ||
            (def->has_limits && def->restitution < 1.0)) {
            c->energy = 0;
        }
    }
}

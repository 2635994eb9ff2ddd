/* Breaking joints and the joints' reactions. A joint with a finite break_force or break_torque
 * breaks at the first step boundary (the post-step hook: every fixed step; CVODE's projection
 * and outputs) where the magnitude of its reaction on body_a passes a limit: the force, or the
 * torque about its anchor. Its rows then leave the solve for the rest of the run (their block of
 * the factor keeps its place, with no rows; a run again from before the break has them back,
 * tb__joints_restart), tb_scene_joint_broken reports it, and the scene's right-hand side
 * generation moves on so that CVODE restarts. The break is found to a step: the reaction is read
 * at step boundaries, not located by a root function. Under CVODE, whose projections run on
 * trial steps too, the boundaries are its outputs (the start of each advance). */
#include "constraints/joints_internal.h"

#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void tb__joint_reaction(const tb_scene *scene, const tb__joints *js, size_t j, double force[3],
                        double torque[3])
{
    const tb__joint *joint = &js->joints[j];
    const tb__joint_eval *eval = &js->evals[j];
    tb__v3_set(force, 0.0, 0.0, 0.0);
    tb__v3_set(torque, 0.0, 0.0, 0.0);
    /* a capped motor's lambda stays on its row, past rows unless the layout keeps it */
    const int rows = joint->rows + (joint->motor_state == TB__MOTOR_CAPPED && !joint->axial_first);
    for (int r = 0; r < rows && !joint->broken; ++r) {
        tb__v3_axpy(force, eval->lambda[r], eval->J[r].v[0]);
        tb__v3_axpy(torque, eval->lambda[r], eval->J[r].w[0]);
    }
    if (joint->motor_state == TB__MOTOR_LOAD && !joint->broken) { /* a motor into its stop */
        tb__v3_axpy(force, joint->motor_load, eval->J[joint->axial_row].v[0]);
        tb__v3_axpy(torque, joint->motor_load, eval->J[joint->axial_row].w[0]);
    }
    double arm[3], moment[3];
    tb__point_arm(tb__derivative_motion(scene, joint->body[0]), joint->anchor[0], arm);
    tb__v3_cross(moment, arm, force); /* about the centre of mass -> about the anchor */
    tb__v3_axpy(torque, -1.0, moment);
}

bool tb__joints_reserve_scratch(tb__joints *js, size_t n)
{
    if (n <= js->scratch_size) {
        return true;
    }
    double *grown = tb__realloc_array(js->scratch, n, sizeof(double));
    if (grown == NULL) {
        return false;
    }
    js->scratch = grown;
    js->scratch_size = n;
    return true;
}

int tb__joints_check_breaking(tb__joints *js, const tb_scene *scene, double t, double *y)
{
    if (js->breakable == 0) {
        return 0;
    }
    if (!tb__joints_reserve_scratch(js, tb_scene_state_size(scene))) {
        return -1;
    }
    const int rc = tb_scene_derivative(t, y, js->scratch, (void *)scene);
    bool broke = false;
    for (size_t j = 0; j < js->count && rc == 0; ++j) {
        tb__joint *joint = &js->joints[j];
        if (joint->broken) {
            continue;
        }
        double force[3], torque[3];
        tb__joint_reaction(scene, js, j, force, torque);
        if (tb__v3_norm(force) > joint->def.break_force ||
            tb__v3_norm(torque) > joint->def.break_torque) {
            joint->broken = true;
            joint->broken_time = t;
            joint->solved_rows = 0;
            memset(js->evals[j].lambda, 0, sizeof js->evals[j].lambda);
            broke = true;
        }
    }
    if (broke) { /* the right-hand side changed: CVODE restarts (rhs_generation) */
        ((tb_scene *)scene)->effects_generation++;
    }
    return rc;
}

void tb__joints_restart(void *constraints, const tb_scene *scene, double t)
{
    (void)scene;
    tb__joints *js = constraints;
    for (size_t j = 0; j < js->count; ++j) {
        tb__joint *joint = &js->joints[j];
        if (joint->broken && t < joint->broken_time) {
            joint->broken = false;
            /* the stops and motors lay their rows out again at the next derivative
             * (tb__joints_configure_rows) */
            tb__joint_solve_rows_as_made(joint);
        }
    }
}

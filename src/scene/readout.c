/* Read-outs: quantities derived from a state array (rotation, velocities, energy, momenta). */
#include "scene/scene_internal.h"

#include "math/tb_math.h"

/* The prologue of every read-out: clears the detail, then names a NULL state or output. */
static tb_status check(const tb_scene *scene, const double *y, const void *out)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (y == NULL || out == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "%s is NULL",
                              y == NULL ? "y" : "output");
    }
    return TB_STATUS_OK;
}

static tb_status check_body(const tb_scene *scene, const double *y, size_t id, const void *out)
{
    tb_status status = check(scene, y, out);
    return status == TB_STATUS_OK ? tb__scene_check_id(scene, id, "id") : status;
}

tb_status tb_scene_body_rotation(const tb_scene *scene, const double *y, size_t id, double out_R[9])
{
    tb_status status = check_body(scene, y, id, out_R);
    if (status == TB_STATUS_OK) {
        double x[3], q[4];
        tb__body_pose_at(scene, scene->time, y, id, x, q);
        tb__q_to_matrix(out_R, q);
    }
    return status;
}

tb_status tb_scene_body_velocity(const tb_scene *scene, const double *y, size_t id, double out_v[3])
{
    tb_status status = check_body(scene, y, id, out_v);
    if (status == TB_STATUS_OK) {
        tb__motion motion;
        tb__body_motion_at(scene, scene->time, y, id, &motion);
        tb__v3_copy(out_v, motion.v);
    }
    return status;
}

tb_status tb_scene_body_angular_velocity(const tb_scene *scene, const double *y, size_t id,
                                         double out_omega[3])
{
    tb_status status = check_body(scene, y, id, out_omega);
    if (status == TB_STATUS_OK) {
        tb__motion motion;
        tb__body_motion_at(scene, scene->time, y, id, &motion);
        tb__v3_copy(out_omega, motion.omega);
    }
    return status;
}

tb_status tb_scene_body_shape_pose(const tb_scene *scene, const double *y, size_t id,
                                   double out_position[3], double out_orientation[4])
{
    tb_status status = check_body(scene, y, id, out_position);
    if (status == TB_STATUS_OK && out_orientation == NULL) {
        status =
            tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_orientation is NULL");
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const tb_mass_properties *props = &scene->mass_props[id];
    const double *r = props->rotation;
    const double principal_from_shape[4] = {r[0], -r[1], -r[2], -r[3]};
    double x[3], q[4], offset[3];
    tb__body_pose_at(scene, scene->time, y, id, x, q);
    tb__q_mul(out_orientation, q, principal_from_shape); /* shape -> principal -> world */
    tb__q_rotate(offset, out_orientation, props->center);
    tb__v3_set(out_position, x[0] - offset[0], x[1] - offset[1], x[2] - offset[2]);
    return TB_STATUS_OK;
}

tb_status tb_scene_body_point(const tb_scene *scene, const double *y, size_t id,
                              const double point[3], double out_position[3], double out_velocity[3])
{
    tb_status status = check_body(scene, y, id, out_position);
    if (status == TB_STATUS_OK && point == NULL) {
        status = tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "point is NULL");
    }
    if (status == TB_STATUS_OK && !tb__all_finite(point, 3)) {
        status = tb__scene_fail((tb_scene *)scene, TB_STATUS_NOT_FINITE,
                                "point: contains NaN or infinity (%g, %g, %g)", point[0], point[1],
                                point[2]);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    double r[3], arm[3];
    tb__shape_point_to_principal(&scene->mass_props[id], point, r);
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, id, &motion);
    tb__point_arm(&motion, r, arm);
    tb__v3_set(out_position, motion.x[0] + arm[0], motion.x[1] + arm[1], motion.x[2] + arm[2]);
    if (out_velocity != NULL) {
        tb__point_velocity(&motion, arm, out_velocity);
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_body_shape_velocity(const tb_scene *scene, const double *y, size_t id,
                                       double out_velocity[3])
{
    tb_status status = check_body(scene, y, id, out_velocity);
    if (status == TB_STATUS_OK) {
        double position[3];
        status =
            tb_scene_body_point(scene, y, id, (const double[3]){0, 0, 0}, position, out_velocity);
    }
    return status;
}

tb_status tb_scene_body_frame_angular_velocity(const tb_scene *scene, const double *y, size_t id,
                                               double out_omega[3])
{
    double pose[3], orientation[4];
    tb_status status = tb_scene_body_shape_pose(scene, y, id, pose, orientation);
    if (status == TB_STATUS_OK && out_omega == NULL) {
        status = tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_omega is NULL");
    }
    if (status == TB_STATUS_OK) {
        tb__motion motion;
        tb__body_motion_at(scene, scene->time, y, id, &motion);
        tb__q_rotate_inverse(out_omega, orientation, motion.omega); /* world -> shape frame */
    }
    return status;
}

/* One body's frame values (tb_scene_frame_values), its id checked by the caller. */
static void frame_values_of(const tb_scene *scene, const double *y, size_t id, double out[13])
{
    double *origin = out, *q = out + 3, *v = out + 7, *omega = out + 10, arm[3], spin[3];
    tb_scene_body_shape_pose(scene, y, id, origin, q);
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, id, &motion);
    tb__v3_copy(v, motion.v);
    tb__v3_copy(omega, motion.omega);
    /* the shape origin moves with v + omega x (origin - centre of mass) */
    const double *x = motion.x;
    tb__v3_set(arm, origin[0] - x[0], origin[1] - x[1], origin[2] - x[2]);
    tb__v3_cross(spin, omega, arm);
    tb__v3_axpy(v, 1.0, spin);
}

tb_status tb_scene_frame_values(const tb_scene *scene, const double *y, double *out_values)
{
    tb_status status = check(scene, y, out_values);
    for (size_t id = 0; status == TB_STATUS_OK && id < scene->body_count; ++id) {
        frame_values_of(scene, y, id, out_values + TB_FRAME_VALUES * id);
    }
    return status;
}

tb_status tb_scene_kinetic_energy(const tb_scene *scene, const double *y, double *out_energy)
{
    tb_status status = check(scene, y, out_energy);
    if (status != TB_STATUS_OK) {
        return status;
    }
    double energy = 0.0; /* of the bodies that have a state (slots) */
    for (size_t i = 0; i < scene->slot_count; ++i) {
        const double *s = y + TB_STATE_SIZE * i;
        double omega[3];
        tb__angular_velocity(&scene->bodies[i], s, omega);
        energy += 0.5 * tb__v3_dot(s + TB_STATE_P, s + TB_STATE_P) * scene->bodies[i].inv_mass +
                  0.5 * tb__v3_dot(omega, s + TB_STATE_L);
    }
    *out_energy = energy;
    return TB_STATUS_OK;
}

tb_status tb_scene_linear_momentum(const tb_scene *scene, const double *y, double out_P[3])
{
    tb_status status = check(scene, y, out_P);
    if (status != TB_STATUS_OK) {
        return status;
    }
    double P[3] = {0, 0, 0};
    for (size_t i = 0; i < scene->slot_count; ++i) {
        tb__v3_axpy(P, 1.0, y + TB_STATE_SIZE * i + TB_STATE_P);
    }
    tb__v3_copy(out_P, P);
    return TB_STATUS_OK;
}

tb_status tb_scene_angular_momentum(const tb_scene *scene, const double *y, const double point[3],
                                    double out_L[3])
{
    tb_status status = check(scene, y, out_L);
    if (status == TB_STATUS_OK && point == NULL) {
        status = tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "point is NULL");
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    double L[3] = {0, 0, 0};
    for (size_t i = 0; i < scene->slot_count; ++i) {
        const double *s = y + TB_STATE_SIZE * i;
        const double arm[3] = {s[0] - point[0], s[1] - point[1], s[2] - point[2]};
        double orbital[3];
        tb__v3_cross(orbital, arm, s + TB_STATE_P);
        tb__v3_axpy(L, 1.0, orbital);
        tb__v3_axpy(L, 1.0, s + TB_STATE_L);
    }
    tb__v3_copy(out_L, L);
    return TB_STATUS_OK;
}

tb_status tb_scene_potential_energy(const tb_scene *scene, const double *y, double *out_energy)
{
    tb_status status = check(scene, y, out_energy);
    if (status != TB_STATUS_OK) {
        return status;
    }
    double energy = 0.0;
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        if (effect->ops->potential_energy != NULL) {
            energy += effect->ops->potential_energy(effect, scene, y);
        }
    }
    const tb__constraint_ops *constraints = scene->constraint_ops;
    if (constraints != NULL && constraints->potential_energy != NULL) {
        energy += constraints->potential_energy(scene->constraints, scene, y);
    }
    *out_energy = energy;
    return TB_STATUS_OK;
}

tb_status tb_scene_conserved(const tb_scene *scene, tb_conserved *out_conserved)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_conserved == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_conserved is NULL");
    }
    tb_conserved c = {1, 1, 1, 1};
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        const tb__effect_ops *ops = effect->ops;
        c.energy &= ops->conserves_energy != NULL && ops->conserves_energy(effect);
        c.linear_momentum &= ops->conserves_momentum;
        c.angular_momentum &= ops->conserves_momentum;
        c.angular_momentum_about_center_of_mass &=
            ops->conserves_momentum || ops->no_torque_about_center_of_mass;
    }
    const tb__constraint_ops *constraints = scene->constraint_ops;
    if (constraints != NULL && constraints->conserved != NULL) {
        constraints->conserved(scene->constraints, scene, &c);
    }
    *out_conserved = c;
    return TB_STATUS_OK;
}

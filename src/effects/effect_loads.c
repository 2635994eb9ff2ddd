/* Loads that do not depend on the motion: gravity on every body, a constant force at a body
 * point, a constant torque (each fixed in the world or turning with the body). */
#include "effects/effect_loads.h"

#include "core/detail.h"
#include "effects/effect_lanes.h"
#include "math/tb_math.h"

/* --- gravity: F_i += M_i g for every body ------------------------------------------------ */

static int apply_gravity(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                         double *dydt, size_t first, size_t count)
{
    (void)t;
    (void)y;
    const tb__body *bodies = scene->bodies + first;
    const double *g = tb__gravity_of(effect)->g;
    for (size_t i = 0; i < count; ++i) {
        tb__v3_axpy(dydt + TB_STATE_SIZE * i + TB_STATE_P, bodies[i].mass, g);
    }
    return 0;
}

/* -sum M_i g . x_i (J), zero at the world origin. */
static double gravity_potential_energy(const tb__effect *effect, const tb_scene *scene,
                                       const double *y)
{
    double energy = 0.0;
    for (size_t i = 0; i < scene->slot_count; ++i) {
        const double *x = y + TB_STATE_SIZE * i + TB_STATE_X;
        energy -= scene->bodies[i].mass * tb__v3_dot(tb__gravity_of(effect)->g, x);
    }
    return energy;
}

static bool always(const tb__effect *effect)
{
    (void)effect;
    return true;
}

static const tb__effect_lanes gravity_lanes = {TB__EFFECT_LANES(tb__gravity_lanes)};

static const tb__effect_ops gravity_ops = {
    .name = "gravity",
    .lanes = &gravity_lanes, /* effect_lanes.c */
    .apply_bodies = apply_gravity,
    .potential_energy = gravity_potential_energy,
    .conserves_energy = always,
    .no_torque_about_center_of_mass = true,
    .constant_loads = true,
};

tb_status tb_scene_add_gravity(tb_scene *scene, const double g[3])
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = tb__check_vector(scene, g, "g");
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__gravity_params gravity;
    tb__v3_copy(gravity.g, g);
    const tb__effect effect = {.ops = &gravity_ops, .body = TB_ALL_BODIES, .params = &gravity};
    return tb__scene_push_effect(scene, &effect, sizeof gravity);
}

/* --- constant force at a body point, constant torque ------------------------------------ */

/* Points fixed in a body are offsets from its centre of mass in its principal frame (m). */
typedef struct tb__load_params {
    double
        vector[3];   /* force (N) or torque (N m): world, or principal frame for body-frame loads */
    double point[3]; /* where a force acts, principal frame */
} tb__load_params;

static const tb__load_params *load_of(const tb__effect *effect)
{
    return effect->params;
}

/* F += f, tau += (p - x) x f with the lever arm p - x = R r (r in the principal frame). */
static int apply_world_force(const tb__effect *effect, const tb_scene *scene, double t,
                             const double *y, double *dydt, size_t first, size_t count)
{
    (void)scene;
    (void)t;
    size_t i;
    if (tb__local_body(effect->slot, first, count, &i)) {
        double q[4], arm[3];
        tb__unit_quaternion(y, i, q);
        tb__q_rotate(arm, q, load_of(effect)->point);
        tb__add_load(dydt, i, arm, load_of(effect)->vector);
    }
    return 0;
}

static int apply_body_force(const tb__effect *effect, const tb_scene *scene, double t,
                            const double *y, double *dydt, size_t first, size_t count)
{
    (void)scene;
    (void)t;
    size_t i;
    if (tb__local_body(effect->slot, first, count, &i)) {
        double q[4], arm[3], force[3];
        tb__unit_quaternion(y, i, q);
        tb__q_rotate(arm, q, load_of(effect)->point);
        tb__q_rotate(force, q, load_of(effect)->vector);
        tb__add_load(dydt, i, arm, force);
    }
    return 0;
}

static int apply_world_torque(const tb__effect *effect, const tb_scene *scene, double t,
                              const double *y, double *dydt, size_t first, size_t count)
{
    (void)scene;
    (void)t;
    (void)y;
    size_t i;
    if (tb__local_body(effect->slot, first, count, &i)) {
        tb__v3_axpy(dydt + TB_STATE_SIZE * i + TB_STATE_L, 1.0, load_of(effect)->vector);
    }
    return 0;
}

static int apply_body_torque(const tb__effect *effect, const tb_scene *scene, double t,
                             const double *y, double *dydt, size_t first, size_t count)
{
    (void)scene;
    (void)t;
    size_t i;
    if (tb__local_body(effect->slot, first, count, &i)) {
        double q[4], torque[3];
        tb__unit_quaternion(y, i, q);
        tb__q_rotate(torque, q, load_of(effect)->vector);
        tb__v3_axpy(dydt + TB_STATE_SIZE * i + TB_STATE_L, 1.0, torque);
    }
    return 0;
}

/* Constant loads add no mode of their own and have no potential the read-outs count. */
/* A world force's torque turns with the body (its point is the body's): not constant. */
static const tb__effect_ops world_force_ops = {.name = "force", .apply_bodies = apply_world_force};
static const tb__effect_ops body_force_ops = {.name = "force", .apply_bodies = apply_body_force};
static const tb__effect_ops world_torque_ops = {
    .name = "torque", .apply_bodies = apply_world_torque, .constant_loads = true};
static const tb__effect_ops body_torque_ops = {.name = "torque", .apply_bodies = apply_body_torque};

static tb_status check_frame(tb_scene *scene, tb_frame frame)
{
    if (frame != TB_FRAME_WORLD && frame != TB_FRAME_BODY) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT, "frame: unknown frame %d",
                              (int)frame);
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_add_force(tb_scene *scene, size_t id, const double force[3],
                             const double point[3], tb_frame frame)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, force, "force");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, point, "point");
    }
    if (status == TB_STATUS_OK) {
        status = check_frame(scene, frame);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const tb_mass_properties *props = &scene->mass_props[id];
    tb__load_params load;
    const tb__effect effect = {.ops = frame == TB_FRAME_WORLD ? &world_force_ops : &body_force_ops,
                               .body = id,
                               .params = &load};
    tb__shape_point_to_principal(props, point, load.point);
    if (frame == TB_FRAME_WORLD) {
        tb__v3_copy(load.vector, force);
    } else {
        tb__shape_vector_to_principal(props, force, load.vector);
    }
    return tb__scene_push_effect(scene, &effect, sizeof load);
}

tb_status tb_scene_add_torque(tb_scene *scene, size_t id, const double torque[3], tb_frame frame)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, torque, "torque");
    }
    if (status == TB_STATUS_OK) {
        status = check_frame(scene, frame);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__load_params load = {.point = {0.0, 0.0, 0.0}};
    const tb__effect effect = {.ops =
                                   frame == TB_FRAME_WORLD ? &world_torque_ops : &body_torque_ops,
                               .body = id,
                               .params = &load};
    if (frame == TB_FRAME_WORLD) {
        tb__v3_copy(load.vector, torque);
    } else {
        tb__shape_vector_to_principal(&scene->mass_props[id], torque, load.vector);
    }
    return tb__scene_push_effect(scene, &effect, sizeof load);
}

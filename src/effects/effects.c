/* Effects: each compiles to one entry of the scene's effect list, whose apply function adds
 * forces into dP/dt and torques into dL/dt. The derivative visits only the entries the scene
 * holds. This file: the list itself, gravity, constant forces and torques, user effects. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

tb_status tb__scene_reserve_effects(tb_scene *scene, size_t capacity)
{
    tb__effect *effects = realloc(scene->effects, capacity * sizeof *effects);
    if (effects == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "room for %zu effects", capacity);
    }
    scene->effects = effects;
    size_t *order = realloc(scene->effect_order, capacity * sizeof *order);
    if (order == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "room for %zu effects", capacity);
    }
    scene->effect_order = order;
    scene->effect_capacity = capacity;
    return TB_STATUS_OK;
}

/* Where in effect_order the new last effect goes (see tb_scene). */
static size_t order_position(const tb_scene *scene, const tb__effect *effect)
{
    const size_t all = scene->all_body_effect_count, single = scene->single_body_effect_count;
    if (effect->apply != NULL) {
        return all + single + scene->coupled_effect_count;
    }
    if (effect->body == TB_ALL_BODIES) {
        return all;
    }
    size_t k = all;
    while (k < all + single && scene->effects[scene->effect_order[k]].body <= effect->body) {
        ++k;
    }
    return k;
}

tb_status tb__scene_push_effect(tb_scene *scene, const tb__effect *effect)
{
    if (scene->effect_count == scene->effect_capacity) {
        const size_t capacity = scene->effect_capacity > 0 ? 2 * scene->effect_capacity : 8;
        const tb_status status = tb__scene_reserve_effects(scene, capacity);
        if (status != TB_STATUS_OK) {
            return status;
        }
    }
    const size_t index = scene->effect_count;
    scene->effects[scene->effect_count++] = *effect;
    if (effect->states_per_contact > 0) {
        const tb_status status = tb__scene_layout_states(scene, scene->body_count);
        if (status != TB_STATUS_OK) {
            scene->effect_count--;
            return status;
        }
    }
    const size_t position = order_position(scene, effect);
    size_t *order = scene->effect_order;
    memmove(order + position + 1, order + position, (index - position) * sizeof *order);
    order[position] = index;
    if (effect->apply != NULL) {
        scene->coupled_effect_count++;
    } else if (effect->body == TB_ALL_BODIES) {
        scene->all_body_effect_count++;
    } else {
        scene->single_body_effect_count++;
    }
    return TB_STATUS_OK;
}

size_t tb_scene_effect_count(const tb_scene *scene)
{
    return scene == NULL ? 0 : scene->effect_count;
}

void tb__shape_point_to_principal(const tb_mass_properties *props, const double point[3],
                                  double out[3])
{
    const double from_center[3] = {point[0] - props->center[0], point[1] - props->center[1],
                                   point[2] - props->center[2]};
    tb__q_rotate_inverse(out, props->rotation, from_center);
}

void tb__shape_vector_to_principal(const tb_mass_properties *props, const double v[3],
                                   double out[3])
{
    tb__q_rotate_inverse(out, props->rotation, v);
}

/* --- gravity: F_i += M_i g for every body ------------------------------------------------ */

static int apply_gravity(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                         double *dydt, size_t first, size_t count)
{
    (void)t;
    (void)y;
    const tb__body *bodies = scene->bodies + first;
    for (size_t i = 0; i < count; ++i) {
        tb__v3_axpy(dydt + TB_STATE_SIZE * i + 7, bodies[i].mass, effect->vector);
    }
    return 0;
}

tb_status tb_scene_add_gravity(tb_scene *scene, const double g[3])
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    tb_status status = tb__check_vector(scene, g, "g");
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__effect effect = {.apply_bodies = apply_gravity, .kind = TB__GRAVITY, .body = TB_ALL_BODIES};
    tb__v3_copy(effect.vector, g);
    return tb__scene_push_effect(scene, &effect);
}

/* --- constant force at a body point, constant torque ------------------------------------ */

/* F += f, tau += (p - x) x f with the lever arm p - x = R r (r in the principal frame). */
static int apply_world_force(const tb__effect *effect, const tb_scene *scene, double t,
                             const double *y, double *dydt, size_t first, size_t count)
{
    (void)scene;
    (void)t;
    size_t i;
    if (tb__local_body(effect->body, first, count, &i)) {
        double q[4], arm[3];
        tb__unit_quaternion(y, i, q);
        tb__q_rotate(arm, q, effect->point);
        tb__add_load(dydt, i, arm, effect->vector);
    }
    return 0;
}

static int apply_body_force(const tb__effect *effect, const tb_scene *scene, double t,
                            const double *y, double *dydt, size_t first, size_t count)
{
    (void)scene;
    (void)t;
    size_t i;
    if (tb__local_body(effect->body, first, count, &i)) {
        double q[4], arm[3], force[3];
        tb__unit_quaternion(y, i, q);
        tb__q_rotate(arm, q, effect->point);
        tb__q_rotate(force, q, effect->vector);
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
    if (tb__local_body(effect->body, first, count, &i)) {
        tb__v3_axpy(dydt + TB_STATE_SIZE * i + 10, 1.0, effect->vector);
    }
    return 0;
}

static int apply_body_torque(const tb__effect *effect, const tb_scene *scene, double t,
                             const double *y, double *dydt, size_t first, size_t count)
{
    (void)scene;
    (void)t;
    size_t i;
    if (tb__local_body(effect->body, first, count, &i)) {
        double q[4], torque[3];
        tb__unit_quaternion(y, i, q);
        tb__q_rotate(torque, q, effect->vector);
        tb__v3_axpy(dydt + TB_STATE_SIZE * i + 10, 1.0, torque);
    }
    return 0;
}

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
    scene->detail[0] = '\0';
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
    tb__effect effect = {.apply_bodies =
                             frame == TB_FRAME_WORLD ? apply_world_force : apply_body_force,
                         .kind = TB__FORCE,
                         .body = id};
    tb__shape_point_to_principal(props, point, effect.point);
    if (frame == TB_FRAME_WORLD) {
        tb__v3_copy(effect.vector, force);
    } else {
        tb__shape_vector_to_principal(props, force, effect.vector);
    }
    return tb__scene_push_effect(scene, &effect);
}

tb_status tb_scene_add_torque(tb_scene *scene, size_t id, const double torque[3], tb_frame frame)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
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
    tb__effect effect = {.apply_bodies =
                             frame == TB_FRAME_WORLD ? apply_world_torque : apply_body_torque,
                         .kind = TB__TORQUE,
                         .body = id};
    if (frame == TB_FRAME_WORLD) {
        tb__v3_copy(effect.vector, torque);
    } else {
        tb__shape_vector_to_principal(&scene->mass_props[id], torque, effect.vector);
    }
    return tb__scene_push_effect(scene, &effect);
}

/* --- user effects ------------------------------------------------------------------------ */

static int apply_user(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                      double *dydt)
{
    return effect->user(t, scene, y, dydt, effect->user_ctx);
}

tb_status tb_scene_add_user_effect(tb_scene *scene, tb_user_effect_fn fn, void *ctx)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    if (fn == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "fn is NULL");
    }
    tb__effect effect = {
        .apply = apply_user, .kind = TB__USER, .body = TB_ALL_BODIES, .user = fn, .user_ctx = ctx};
    return tb__scene_push_effect(scene, &effect);
}

void tb_effect_add_force(const tb_scene *scene, const double *y, double *dydt, size_t id,
                         const double force[3], const double point[3])
{
    (void)scene;
    const double *x = y + TB_STATE_SIZE * id;
    const double arm[3] = {point[0] - x[0], point[1] - x[1], point[2] - x[2]};
    tb__add_load(dydt, id, arm, force);
}

void tb_effect_add_torque(const tb_scene *scene, double *dydt, size_t id, const double torque[3])
{
    (void)scene;
    tb__v3_axpy(dydt + TB_STATE_SIZE * id + 10, 1.0, torque);
}

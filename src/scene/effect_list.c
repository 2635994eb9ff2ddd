/* The scene's effect list: each effect added compiles to one entry (its rows of operations and
 * its parameters, which only the effect's own files in src/effects/ read), kept in the order the
 * derivative applies them. Also the conversions every effect uses to store a body point or
 * direction in the body's principal frame. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

tb_status tb__scene_reserve_effects(tb_scene *scene, size_t capacity)
{
    size_t effect_bytes, order_bytes;
    tb_status status = tb__validate_size_product(scene->detail, capacity, sizeof(tb__effect),
                                                 "effect_capacity", &effect_bytes);
    if (status == TB_STATUS_OK) {
        status = tb__validate_size_product(scene->detail, capacity, sizeof(size_t),
                                           "effect_capacity", &order_bytes);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__effect *effects = realloc(scene->effects, effect_bytes);
    if (effects == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "room for %zu effects", capacity);
    }
    scene->effects = effects;
    size_t *order = realloc(scene->effect_order, order_bytes);
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
    if (effect->ops->apply != NULL) {
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

/* Room for one more effect: doubles the list, refusing a size that would overflow. */
static tb_status grow(tb_scene *scene)
{
    if (scene->effect_count < scene->effect_capacity) {
        return TB_STATUS_OK;
    }
    size_t capacity = 8;
    if (scene->effect_capacity > 0 &&
        tb__validate_size_product(scene->detail, scene->effect_capacity, 2, "effect list",
                                  &capacity) != TB_STATUS_OK) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    return tb__scene_reserve_effects(scene, capacity);
}

tb_status tb__scene_push_effect(tb_scene *scene, const tb__effect *effect, size_t params_size)
{
    /* a per-body row applies to ranges of bodies; every other row to the whole state */
    assert((effect->ops->apply == NULL) ==
           !(effect->ops->couples_bodies || effect->ops->owns_states));
    assert((effect->ops->apply == NULL) != (effect->ops->apply_bodies == NULL));
    tb_status status = tb__scene_check_idle(scene, "adding an effect");
    if (status == TB_STATUS_OK && effect->ops->apply_bodies != NULL &&
        effect->body < scene->body_count) { /* a load on one body needs its state */
        status = tb__scene_check_dynamic(scene, effect->body, "id");
    }
    if (status == TB_STATUS_OK) {
        status = grow(scene);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    void *params = malloc(params_size > 0 ? params_size : 1);
    if (params == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "an effect's parameters");
    }
    memcpy(params, effect->params, params_size);
    const size_t index = scene->effect_count;
    scene->effects[scene->effect_count++] = *effect;
    scene->effects[index].params = params;
    scene->effects[index].slot =
        effect->body < scene->body_count ? tb__body_slot(scene, effect->body) : TB_NO_SLOT;
    if (effect->states_per_contact > 0 || effect->fixed_states > 0) {
        status = tb__scene_layout_states(scene, scene->slot_count);
        if (status != TB_STATUS_OK) {
            scene->effect_count--;
            free(params);
            return status;
        }
    }
    const size_t position = order_position(scene, effect);
    size_t *order = scene->effect_order;
    memmove(order + position + 1, order + position, (index - position) * sizeof *order);
    order[position] = index;
    if (effect->ops->apply != NULL) {
        scene->coupled_effect_count++;
    } else if (effect->body == TB_ALL_BODIES) {
        scene->all_body_effect_count++;
    } else {
        scene->single_body_effect_count++;
    }
    scene->effects_generation++;
    tb__scene_wake_all(scene); /* a load added: the bodies at rest may move */
    return TB_STATUS_OK;
}

tb_status tb__scene_check_effects_start(tb_scene *scene, const double *y)
{
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        if (effect->ops->check_start != NULL) {
            const tb_status status = effect->ops->check_start(effect, scene, y, scene->detail);
            if (status != TB_STATUS_OK) {
                return status;
            }
        }
    }
    return TB_STATUS_OK;
}

tb_status tb__scene_check_points(tb_scene *scene, const double *y, size_t id, size_t first)
{
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        const tb__effect_stepping *stepping = tb__stepping_of(effect);
        if (stepping->check_points != NULL) {
            const tb_status status =
                stepping->check_points(effect, scene, y, id, first, scene->detail);
            for (size_t k = 0; k < e && status != TB_STATUS_OK; ++k) { /* those that took them */
                const tb__effect_stepping *taken = tb__stepping_of(&scene->effects[k]);
                if (taken->check_points != NULL && taken->uncheck_points != NULL) {
                    taken->uncheck_points(&scene->effects[k]);
                }
            }
            if (status != TB_STATUS_OK) {
                return status;
            }
        }
    }
    return TB_STATUS_OK;
}

const tb__effect_stepping tb__effect_no_stepping = {.post_step = NULL};

/* Every check_shape op before any change. */
static tb_status check_shapes(tb_scene *scene, size_t id)
{
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        if (tb__stepping_of(effect)->check_shape != NULL) {
            const tb_status status = tb__stepping_of(effect)->check_shape(effect, scene, id);
            if (status != TB_STATUS_OK) {
                return status;
            }
        }
    }
    return TB_STATUS_OK;
}

tb_status tb__scene_shapes_changed(tb_scene *scene, size_t id)
{
    tb_status status = check_shapes(scene, id);
    bool layout = false; /* an effect's state count changed: lay the states out once, at the end */
    size_t changed = 0;  /* effects [0, changed) were asked (the one that failed too) */
    for (; changed < scene->effect_count && status == TB_STATUS_OK; ++changed) {
        tb__effect *effect = &scene->effects[changed];
        if (tb__stepping_of(effect)->shapes_changed != NULL) {
            const size_t states = tb__effect_state_count(effect, scene);
            status = tb__stepping_of(effect)->shapes_changed(effect, scene, id);
            layout = layout || tb__effect_state_count(effect, scene) != states;
        }
    }
    if (status == TB_STATUS_OK && layout) { /* fails before it changes anything */
        status = tb__scene_layout_states(scene, scene->slot_count);
    }
    for (size_t e = 0; e < changed; ++e) {
        tb__effect *effect = &scene->effects[e];
        if (tb__stepping_of(effect)->shapes_settled != NULL) {
            tb__stepping_of(effect)->shapes_settled(effect, status != TB_STATUS_OK);
        }
    }
    return status;
}

void tb__effect_rate_add_decay(tb__effect_rate *out, double rate, size_t body)
{
    if (rate > out->decay) {
        out->decay = rate;
        out->decay_body = body;
    }
}

void tb__effect_rate_add_damped_mode(tb__effect_rate *out, double omega, double zeta, size_t body)
{
    out->ringing = fmax(out->ringing, omega);
    if (zeta > 1.0) { /* the faster root, omega (zeta + sqrt(zeta^2 - 1)); past 1e150 zeta^2
                         overflows and sqrt(zeta^2 - 1) is zeta in doubles */
        const double root = zeta < 1e150 ? sqrt(zeta * zeta - 1.0) : zeta;
        tb__effect_rate_add_decay(out, omega * (zeta + root), body);
    } else if (omega > out->oscillation) {
        out->oscillation = omega;
        out->oscillation_body = body;
    }
}

bool tb__scene_has_post_step_effects(const tb_scene *scene)
{
    for (size_t e = 0; e < scene->effect_count; ++e) {
        if (tb__stepping_of(&scene->effects[e])->post_step != NULL) {
            return true;
        }
    }
    return false;
}

int tb__scene_post_step(double t, double *y, void *ctx)
{
    tb_scene *scene = ctx;
    if (scene == NULL || y == NULL) {
        return -1;
    }
    scene->time = t; /* the states' time, which bodies without a state are read at */
    int rc = scene->renormalize ? tb_scene_normalize_quaternions(t, y, ctx) : 0;
    if (rc == 0 && scene->constraint_ops != NULL) { /* back onto the joints */
        rc = scene->constraint_ops->project(scene->constraints, scene, t, y);
    }
    tb__scene_sleep_begin(scene);
    for (size_t e = 0; e < scene->effect_count && rc == 0; ++e) {
        const tb__effect *effect = &scene->effects[e];
        if (tb__stepping_of(effect)->post_step != NULL) {
            tb__stepping_of(effect)->post_step(effect, scene, y); /* links the pairs it finds */
        }
    }
    if (rc == 0) {
        tb__scene_sleep_end(scene, t, y);
        tb__scene_events_observe(scene, t, y, true); /* a fixed step's end (if watched) */
    }
    return rc;
}

void tb__scene_restart(tb_scene *scene, double t, const double *y)
{
    tb__scene_sleep_restart(scene, t);
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        if (tb__stepping_of(effect)->restart != NULL) {
            tb__stepping_of(effect)->restart(effect, scene, t, y);
        }
    }
    if (scene->constraint_ops != NULL && scene->constraint_ops->restart != NULL) {
        scene->constraint_ops->restart(scene->constraints, scene, t);
    }
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

/* A ground plane's bookkeeping of the bodies it meets through their shapes (ground_shapes.h):
 * which bodies have contact points (they keep the points' law), upper bounds of how many it
 * meets, and the friction pool sized for them, grown when a shape is set and put back when the
 * change is refused (tb__ground_shapes_settled). */
#include "effects/ground_shapes.h"

#include "core/detail.h"
#include "core/validate.h"
#include "effects/ground_shapes_internal.h"

#include <stdlib.h>
#include <string.h>

tb_status tb__ground_shapes_note_points(const tb__effect *effect, const tb_scene *scene, size_t id,
                                        bool has_points, char *detail)
{
    tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    if (id >= shapes->capacity) { /* doubling: bodies given points one by one, O(n) in all */
        const size_t n =
            scene->body_count > 2 * shapes->capacity ? scene->body_count : 2 * shapes->capacity;
        unsigned char *flags = realloc(shapes->has_points, n);
        if (flags == NULL) {
            return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY,
                                  "the ground's flags of bodies with points: %zu bodies", n);
        }
        memset(flags + shapes->capacity, 0, n - shapes->capacity); /* added since: no points */
        shapes->has_points = flags;
        shapes->capacity = n;
    }
    shapes->undo = (tb__ground_note){id, shapes->slots_wanted, shapes->ids_wanted,
                                     shapes->met_bound, shapes->has_points[id] != 0};
    const bool was = tb__ground_shapes_meet(shapes, scene, id);
    shapes->has_points[id] = has_points;
    const bool now = tb__ground_shapes_meet(shapes, scene, id);
    if (now && !was) {
        shapes->met_bound += 1;
        shapes->slots_wanted += TB__GROUND_SLOTS_PER_SHAPE;
        shapes->ids_wanted = id + 1 > shapes->ids_wanted ? id + 1 : shapes->ids_wanted;
    } else if (was && !now && shapes->slots_wanted >= TB__GROUND_SLOTS_PER_SHAPE) {
        /* ids_wanted stays an upper bound until the next refresh; slots_wanted may be behind
         * the shapes set since it (tb__ground_shapes_changed leaves it when the pool has room),
         * so it is not taken below 0 */
        shapes->slots_wanted -= TB__GROUND_SLOTS_PER_SHAPE;
    }
    return TB_STATUS_OK;
}

void tb__ground_shapes_unnote(const tb__effect *effect)
{
    tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    const tb__ground_note *before = &shapes->undo;
    shapes->has_points[before->id] = before->had;
    shapes->slots_wanted = before->slots_wanted;
    shapes->ids_wanted = before->ids_wanted;
    shapes->met_bound = before->met_bound;
}

tb_status tb__ground_shapes_refresh(const tb__effect *effect, const tb_scene *scene, char *detail)
{
    tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    const size_t n = scene->body_count;
    if (n > shapes->capacity) {
        unsigned char *flags = realloc(shapes->has_points, n);
        if (flags == NULL) {
            return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY,
                                  "the ground's flags of bodies with points: %zu bodies", n);
        }
        shapes->has_points = flags;
        shapes->capacity = n;
    }
    if (shapes->capacity > 0) { /* a scene without bodies has no flags yet (NULL) */
        memset(shapes->has_points, 0, shapes->capacity);
    }
    for (size_t j = 0; j < scene->contact_count; ++j) {
        shapes->has_points[scene->contacts[j].body] = 1;
    }
    size_t met = 0;
    shapes->ids_wanted = 0;
    for (size_t id = 0; id < n; ++id) {
        if (tb__ground_shapes_meet(shapes, scene, id)) {
            met += 1;
            shapes->ids_wanted = id + 1;
        }
    }
    shapes->slots_wanted = TB__GROUND_SLOTS_PER_SHAPE * met; /* met <= n, allocated above */
    shapes->met_bound = met;
    return TB_STATUS_OK;
}

/* A new, empty pool of `slots` slots for ids below `bodies` in place of the ground's; the old one
 * (NULL for none) is the caller's to keep or free. Nothing changes on failure. */
static tb_status swap_pool(tb_scene *scene, tb__effect *effect, size_t slots, size_t bodies)
{
    tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    size_t bytes;
    tb_status status = tb__validate_size_product(
        scene->detail, slots, TB__FRICTION_SLOT_STATES * sizeof(double), "bodies", &bytes);
    tb__friction_pool *pool =
        status == TB_STATUS_OK ? tb__friction_pool_create(slots, bodies, shapes->presliding) : NULL;
    if (pool == NULL) {
        return status != TB_STATUS_OK
                   ? status
                   : tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY,
                                    "the ground's friction pool: %zu slots", slots);
    }
    shapes->law.friction = pool;
    shapes->pool_bodies = bodies;
    effect->fixed_states = TB__FRICTION_SLOT_STATES * slots;
    return TB_STATUS_OK;
}

tb_status tb__ground_shapes_changed(tb__effect *effect, tb_scene *scene, size_t id)
{
    tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    shapes->change =
        (tb__ground_pool_change){shapes->law.friction, shapes->pool_bodies, effect->fixed_states,
                                 shapes->slots_wanted, shapes->ids_wanted,  shapes->met_bound};
    const size_t have = effect->fixed_states / TB__FRICTION_SLOT_STATES;
    if (!tb__ground_shapes_meet(shapes, scene, id)) { /* points, or no shape: nothing to hold */
        return TB_STATUS_OK;
    }
    shapes->met_bound += 1;
    if (TB__GROUND_SLOTS_PER_SHAPE * shapes->met_bound <= have && id < shapes->pool_bodies) {
        return TB_STATUS_OK;
    }
    tb_status status = tb__ground_shapes_refresh(effect, scene, scene->detail);
    if (status != TB_STATUS_OK ||
        (shapes->slots_wanted <= have && shapes->ids_wanted <= shapes->pool_bodies)) {
        return status;
    }
    /* doubling: n bodies given shapes one by one grow it log n times, not n; the scene lays the
     * states out again once every effect took the shape (tb__scene_shapes_changed) */
    const size_t slots = shapes->slots_wanted > 2 * have ? shapes->slots_wanted : 2 * have;
    const size_t bodies =
        scene->body_count > 2 * shapes->pool_bodies ? scene->body_count : 2 * shapes->pool_bodies;
    return swap_pool(scene, effect, slots, bodies);
}

void tb__ground_shapes_settled(tb__effect *effect, bool undo)
{
    tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    const tb__ground_pool_change *before = &shapes->change;
    if (undo) {
        if (shapes->law.friction != before->pool) {
            tb__friction_pool_destroy(shapes->law.friction);
            shapes->law.friction = before->pool;
        }
        shapes->pool_bodies = before->pool_bodies;
        effect->fixed_states = before->fixed_states;
        shapes->slots_wanted = before->slots_wanted;
        shapes->ids_wanted = before->ids_wanted;
        shapes->met_bound = before->met_bound;
    } else if (shapes->law.friction != before->pool) {
        tb__friction_pool_destroy(before->pool);
    }
    shapes->change.pool = shapes->law.friction; /* settled: nothing left to free or put back */
}

tb_status tb__ground_shapes_create(tb_scene *scene, const tb_ground_def *def, tb__effect *effect)
{
    tb__ground_params *ground = tb__ground_of(effect);
    ground->shapes = calloc(1, sizeof *ground->shapes);
    if (ground->shapes == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "the ground's shaped bodies");
    }
    tb__contact_params *law = &ground->shapes->law;
    law->omega = ground->omega;
    law->damping_ratio = ground->damping_ratio;
    law->static_friction = ground->static_friction;
    law->kinetic_friction = ground->kinetic_friction;
    law->stribeck_velocity = ground->stribeck_velocity;
    law->gravity = ground->gravity;
    law->bristle_stiffness = ground->bristle_stiffness;
    law->slip_velocity =
        tb__contact_slip_velocity(def->static_friction, def->gravity, def->presliding);
    ground->shapes->presliding = def->presliding;
    ground->shapes->pool_bodies = scene->body_count;
    tb_status status = tb__ground_shapes_refresh(effect, scene, scene->detail);
    if (status == TB_STATUS_OK && ground->shapes->slots_wanted > 0) { /* none for none */
        status = swap_pool(scene, effect, ground->shapes->slots_wanted, scene->body_count);
    }
    return status;
}

void tb__ground_shapes_release(tb__effect *effect)
{
    tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    if (shapes != NULL) {
        tb__friction_pool_destroy(shapes->law.friction);
        free(shapes->has_points);
        free(shapes);
        tb__ground_of(effect)->shapes = NULL;
    }
}

/* Read-outs of the contact effects and ground planes (include/tumble/contact_info.h): what
 * `tumble check` reports. Part of the contact effects' own code: it reads their parameters
 * (tb__contact_params, tb__ground_params), which nothing outside them does. */
#include "tumble/contact_info.h"

#include "contact/contact_law.h"
#include "contact/contact_pairs.h"
#include "effects/effect_contact.h"
#include "effects/effect_ground.h"
#include "effects/ground_shapes.h"

#include <math.h>
#include <string.h>

/* The scene's k-th effect named kind ("contact", "ground"), or NULL. */
static const tb__effect *kth_effect(const tb_scene *scene, const char *kind, size_t k,
                                    size_t *out_index)
{
    for (size_t i = 0; i < scene->effect_count; ++i) {
        if (strcmp(scene->effects[i].ops->name, kind) == 0 && k-- == 0) {
            *out_index = i;
            return &scene->effects[i];
        }
    }
    return NULL;
}

static size_t count_effects(const tb_scene *scene, const char *kind)
{
    size_t count = 0;
    for (size_t i = 0; scene != NULL && i < scene->effect_count; ++i) {
        count += strcmp(scene->effects[i].ops->name, kind) == 0;
    }
    return count;
}

size_t tb_scene_contact_count(const tb_scene *scene)
{
    return count_effects(scene, "contact");
}

size_t tb_scene_ground_count(const tb_scene *scene)
{
    return count_effects(scene, "ground");
}

static tb_status find(const tb_scene *scene, const char *kind, size_t k, const void *out,
                      const tb__effect **effect, size_t *index)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out is NULL");
    }
    *effect = kth_effect(scene, kind, k, index);
    if (*effect == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_OUT_OF_RANGE,
                              "k: the scene has %zu %s effects, got %zu",
                              count_effects(scene, kind), kind, k);
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_get_contact(const tb_scene *scene, size_t k, tb_contact_info *out)
{
    const tb__effect *effect;
    size_t index;
    const tb_status status = find(scene, "contact", k, out, &effect, &index);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const tb__contact_params *c = tb__contact_of(effect);
    *out = (tb_contact_info){
        .effect = index,
        .every_body = c->every_body,
        .body_count = c->body_count,
        .bodies = c->bodies,
        .restitution = tb__contact_restitution(c->damping_ratio),
        .static_friction = c->static_friction,
        .kinetic_friction = c->kinetic_friction,
        .penetration = c->gravity / (c->omega * c->omega),
        .gravity = c->gravity,
        .stribeck_velocity = c->stribeck_velocity,
    };
    return TB_STATUS_OK;
}

tb_status tb_scene_get_ground(const tb_scene *scene, size_t k, tb_ground_info *out)
{
    const tb__effect *effect;
    size_t index;
    const tb_status status = find(scene, "ground", k, out, &effect, &index);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const tb__ground_params *g = tb__ground_of(effect);
    *out = (tb_ground_info){
        .effect = index,
        .normal = {g->normal[0], g->normal[1], g->normal[2]},
        .offset = g->offset,
        .restitution = tb__contact_restitution(g->damping_ratio),
        .static_friction = g->static_friction,
        .kinetic_friction = g->kinetic_friction,
        .penetration = g->penetration,
        .gravity = g->gravity,
    };
    return TB_STATUS_OK;
}

tb_status tb_scene_body_contact_point_count(const tb_scene *scene, size_t id, size_t *out_count)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_count == NULL) { /* named, not the previous failure's detail kept */
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_count is NULL");
    }
    const tb_status status = tb__scene_check_id(scene, id, "id");
    if (status != TB_STATUS_OK) {
        return status;
    }
    size_t count = 0;
    for (size_t k = 0; k < scene->contact_count; ++k) {
        count += scene->contacts[k].body == id;
    }
    *out_count = count;
    return TB_STATUS_OK;
}

/* Appends touch to out while there is room; counts it either way. */
static void note(const tb_contact_touch *touch, tb_contact_touch *out, size_t capacity,
                 size_t *count)
{
    if (*count < capacity) {
        out[*count] = *touch;
    }
    *count += 1;
}

static void pairs_touching(const tb_scene *scene, size_t index, const double *y,
                           tb_contact_touch *out, size_t capacity, size_t *count)
{
    tb__contact_pairs *pairs = tb__contact_of(&scene->effects[index])->pairs;
    tb__pair_contact batch[16];
    size_t found;
    /* a body pair's touching piece pairs come one after another: one touch for all of them */
    tb_contact_touch last = {index, TB_ALL_BODIES, TB_ALL_BODIES, -INFINITY, 0};
    tb__contact_pairs_skip_asleep(pairs, false); /* an asleep pair at rest touches too */
    tb__contact_pairs_begin(pairs, scene, scene->time, y);
    while ((found = tb__contact_pairs_next(pairs, scene, y, batch, 16)) > 0) {
        for (size_t k = 0; k < found; ++k) {
            const tb__contact_manifold *m = &batch[k].manifold;
            if (batch[k].body_a != last.body_a || batch[k].body_b != last.body_b) {
                if (last.points > 0) {
                    note(&last, out, capacity, count);
                }
                last = (tb_contact_touch){index, batch[k].body_a, batch[k].body_b, -INFINITY, 0};
            }
            last.points += m->count;
            for (int j = 0; j < m->count; ++j) {
                last.depth = fmax(last.depth, m->points[j].depth);
            }
        }
    }
    if (last.points > 0) {
        note(&last, out, capacity, count);
    }
    tb__contact_pairs_skip_asleep(pairs, true);
}

/* Each body whose contact points dip into ground plane index, with its deepest point. */
static void ground_touching(const tb_scene *scene, size_t index, const double *y,
                            tb_contact_touch *out, size_t capacity, size_t *count)
{
    const tb__ground_params *g = tb__ground_of(&scene->effects[index]);
    tb_contact_touch touch = {index, TB_ALL_BODIES, TB_WORLD, -INFINITY, 0};
    for (size_t k = 0; k <= scene->contact_count; ++k) {
        const tb__contact *c = k < scene->contact_count ? &scene->contacts[k] : NULL;
        if (touch.points > 0 && (c == NULL || c->body != touch.body_a)) {
            note(&touch, out, capacity, count);
        }
        if (c == NULL) {
            break;
        }
        if (c->body != touch.body_a) {
            touch = (tb_contact_touch){index, c->body, TB_WORLD, -INFINITY, 0};
        }
        tb__motion motion;
        tb__body_motion_at(scene, scene->time, y, c->body, &motion);
        double arm[3];
        tb__point_arm(&motion, c->r, arm);
        double height = -g->offset;
        for (int j = 0; j < 3; ++j) {
            height += g->normal[j] * (motion.x[j] + arm[j]);
        }
        const double depth = c->radius - height;
        if (depth > 0.0) {
            touch.depth = fmax(touch.depth, depth);
            touch.points += 1;
        }
    }
}

/* Each body that ground plane index meets through its shape and whose shape dips into it. */
static void ground_shapes_touching(const tb_scene *scene, size_t index, const double *y,
                                   tb_contact_touch *out, size_t capacity, size_t *count)
{
    for (size_t id = 0; id < scene->body_count; ++id) {
        tb_contact_touch touch = {index, id, TB_WORLD, -INFINITY, 0};
        if (tb__ground_shape_touch(&scene->effects[index], scene, y, id, &touch.depth,
                                   &touch.points) &&
            touch.points > 0) {
            note(&touch, out, capacity, count);
        }
    }
}

tb_status tb_scene_contact_touching(const tb_scene *scene, const double *y, tb_contact_touch *out,
                                    size_t capacity, size_t *out_count)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (y == NULL || out_count == NULL || (out == NULL && capacity > 0)) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "%s is NULL%s",
                              y == NULL           ? "y"
                              : out_count == NULL ? "out_count"
                                                  : "out",
                              y != NULL && out_count != NULL ? " (capacity > 0)" : "");
    }
    if (scene->busy) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_BUSY,
                              "tb_scene_contact_touching: an integrator is stepping the scene");
    }
    size_t count = 0;
    for (size_t i = 0; i < scene->effect_count; ++i) {
        if (strcmp(scene->effects[i].ops->name, "contact") == 0) {
            pairs_touching(scene, i, y, out, capacity, &count);
        }
    }
    for (size_t i = 0; i < scene->effect_count; ++i) {
        if (strcmp(scene->effects[i].ops->name, "ground") == 0) {
            ground_touching(scene, i, y, out, capacity, &count);
            ground_shapes_touching(scene, i, y, out, capacity, &count);
        }
    }
    *out_count = count;
    return TB_STATUS_OK;
}

/* Contact points: where bodies touch ground planes. A body's points are stored contiguously
 * (the ground law reads each body's motion once), in the principal frame, with the share of the
 * body's weight each carries at rest. Also generators of points for common shapes. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Finite positions and radii >= 0, and no point so far out (1e200 m) that the contact's rate,
 * which grows with the inverse mass M |r|^2 / I at the point's reach, overflows. */
static tb_status check_points(tb_scene *scene, size_t id, const tb_contact_point *points,
                              size_t count)
{
    for (size_t k = 0; k < count; ++k) {
        char what[48];
        snprintf(what, sizeof what, "points[%zu].position", k);
        tb_status status = tb__validate_vector(scene->detail, points[k].position, what);
        if (status == TB_STATUS_OK) {
            snprintf(what, sizeof what, "points[%zu].radius", k);
            status = tb__validate_nonnegative(scene->detail, points[k].radius, what);
        }
        if (status != TB_STATUS_OK) {
            return status;
        }
        double r[3];
        tb__shape_point_to_principal(&scene->mass_props[id], points[k].position, r);
        const double reach = tb__v3_hypot(r) + points[k].radius; /* 1e300 m, not inf */
        const double arm[3] = {reach, 0.0, 0.0};
        const tb__body *body = tb__body_constants(scene, id);
        if (!isfinite(body->mass * tb__inverse_mass_at(body, arm))) {
            return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                  "points[%zu]: %g m from the body's centre of mass is so far "
                                  "that the contact's rate overflows",
                                  k, reach);
        }
    }
    return TB_STATUS_OK;
}

static tb_status validate(tb_scene *scene, size_t id, const tb_contact_point *points, size_t count,
                          size_t support)
{
    if (points == NULL && count > 0) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "points is NULL (count %zu)", count);
    }
    /* before the ground planes' start checks, which read the state under the step */
    tb_status status = tb__scene_check_idle(scene, "setting contact points");
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_id(scene, id, "id");
    }
    if (status == TB_STATUS_OK) { /* a ground plane pushes bodies that can move */
        status = tb__scene_check_dynamic(scene, id, "id");
    }
    if (status == TB_STATUS_OK) {
        status = check_points(scene, id, points, count);
    }
    if (status == TB_STATUS_OK && count > 0 && (support == 0 || support > count)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "support: must be in [1, %zu] (the points that carry the body at "
                                "rest), got %zu",
                                count, support);
    }
    return status;
}

/* Body id's points, in the principal frame, into out[0..count). */
static void fill_points(const tb_scene *scene, size_t id, const tb_contact_point *points,
                        size_t count, size_t support, tb__contact *out)
{
    for (size_t k = 0; k < count; ++k) {
        out[k].body = id;
        tb__shape_point_to_principal(&scene->mass_props[id], points[k].position, out[k].r);
        out[k].radius = points[k].radius;
        out[k].share = 1.0 / (double)support;
    }
}

/* 1 + the largest body id among the points held (0 for none). */
static size_t contact_bodies_end(const tb_scene *scene)
{
    size_t end = 0;
    for (size_t j = 0; j < scene->contact_count; ++j) {
        end = scene->contacts[j].body + 1 > end ? scene->contacts[j].body + 1 : end;
    }
    return end;
}

/* The effects' checks of body id's points, now contacts[first ..] (tb__scene_check_points: those
 * alone, so that n bodies given points one by one cost O(n), not the O(n^2) of every point's
 * depth at every body), and the states' layout for the points now held (their bodies below
 * end); on failure the points before (old, old_count, old_capacity) are put back, and where the
 * layout failed, the notes the effects' checks took (uncheck_points). */
static tb_status commit_points(tb_scene *scene, size_t id, size_t first, size_t end,
                               tb__contact *old, size_t old_count, size_t old_capacity)
{
    const size_t old_end = scene->contact_bodies_end;
    scene->contact_bodies_end = end;
    tb_status status = tb__scene_check_points(scene, scene->states, id, first);
    if (status == TB_STATUS_OK) {
        status = tb__scene_layout_states(scene, scene->slot_count);
        for (size_t e = 0; e < scene->effect_count && status != TB_STATUS_OK; ++e) {
            const tb__effect_stepping *stepping = tb__stepping_of(&scene->effects[e]);
            if (stepping->check_points != NULL && stepping->uncheck_points != NULL) {
                stepping->uncheck_points(&scene->effects[e]); /* F118: every plane's note */
            }
        }
    }
    if (status != TB_STATUS_OK && old != scene->contacts) {
        free(scene->contacts);
        scene->contacts = old;
    } else if (status == TB_STATUS_OK && old != scene->contacts) {
        free(old);
    }
    if (status != TB_STATUS_OK) {
        scene->contact_count = old_count;
        scene->contact_capacity = old_capacity;
        scene->contact_bodies_end = old_end;
    } else { /* F99: asleep, a box whose points were removed hung in the air */
        tb__scene_wake_body(scene, id);
    }
    return status;
}

/* A body without points yet, past every body that has some (a scene being built, body after body):
 * its points go after the others in place, the array growing by doubling, so building n bodies
 * costs O(n), not the O(n^2) of copying every point at every body (100000 bodies took minutes to
 * load). */
static tb_status append_points(tb_scene *scene, size_t id, const tb_contact_point *points,
                               size_t count, size_t support)
{
    const size_t old_count = scene->contact_count, total = old_count + count;
    if (total > scene->contact_capacity) {
        const size_t capacity =
            total > 2 * scene->contact_capacity ? total : 2 * scene->contact_capacity;
        size_t bytes;
        tb_status status = tb__validate_size_product(scene->detail, capacity, sizeof(tb__contact),
                                                     "count", &bytes);
        if (status != TB_STATUS_OK) {
            return status;
        }
        tb__contact *grown = realloc(scene->contacts, bytes);
        if (grown == NULL) {
            return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "%zu contact points", total);
        }
        scene->contacts = grown; /* the points held so far are unchanged */
        scene->contact_capacity = capacity;
    }
    if (count > 0) { /* with no points, contacts may still be NULL */
        fill_points(scene, id, points, count, support, scene->contacts + old_count);
    }
    scene->contact_count = total;
    const size_t end =
        count > 0 && id >= scene->contact_bodies_end ? id + 1 : scene->contact_bodies_end;
    return commit_points(scene, id, old_count, end, scene->contacts, old_count,
                         scene->contact_capacity);
}

/* Removes body id's points and appends the new ones at the end (keeps each body's points
 * contiguous). Works on a copy so that a failure changes nothing. */
tb_status tb_scene_set_contact_points(tb_scene *scene, size_t id, const tb_contact_point *points,
                                      size_t count, size_t support)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = validate(scene, id, points, count, support);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (id >= scene->contact_bodies_end) {
        return append_points(scene, id, points, count, support); /* id has no points yet */
    }
    size_t kept = 0;
    for (size_t j = 0; j < scene->contact_count; ++j) {
        kept += scene->contacts[j].body != id;
    }
    const size_t total = kept + count;
    size_t bytes;
    status = tb__validate_size_product(scene->detail, total > 0 ? total : 1, sizeof(tb__contact),
                                       "count", &bytes);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__contact *contacts = malloc(bytes);
    if (contacts == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "%zu contact points", total);
    }
    size_t w = 0;
    for (size_t j = 0; j < scene->contact_count; ++j) {
        if (scene->contacts[j].body != id) {
            contacts[w++] = scene->contacts[j];
        }
    }
    fill_points(scene, id, points, count, support, contacts + w);
    tb__contact *old = scene->contacts;
    const size_t old_count = scene->contact_count, old_capacity = scene->contact_capacity;
    scene->contacts = contacts;
    scene->contact_count = total;
    scene->contact_capacity = total;
    return commit_points(scene, id, w, contact_bodies_end(scene), old, old_count, old_capacity);
}

/* The generators' checks: room for `needed` points, and each dimension finite and >= 0 (they
 * have no detail: the status says which kind of input was bad). */
static tb_status room(size_t needed, size_t capacity, tb_contact_point *out, size_t *out_count)
{
    if (out == NULL || out_count == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    return needed <= capacity ? TB_STATUS_OK : TB_STATUS_OUT_OF_RANGE;
}

static tb_status check_dimensions(const double *values, int count)
{
    tb_status status = TB_STATUS_OK;
    for (int k = 0; k < count && status == TB_STATUS_OK; ++k) {
        status = tb__validate_nonnegative(NULL, values[k], "dimension");
    }
    return status;
}

tb_status tb_contact_points_box(const double size[3], tb_contact_point *out, size_t capacity,
                                size_t *out_count)
{
    tb_status status = size == NULL ? TB_STATUS_NULL_POINTER : room(8, capacity, out, out_count);
    if (status == TB_STATUS_OK) {
        status = check_dimensions(size, 3);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    for (unsigned c = 0; c < 8; ++c) {
        for (int i = 0; i < 3; ++i) {
            out[c].position[i] = ((c >> i) & 1 ? 0.5 : -0.5) * size[i];
        }
        out[c].radius = 0.0;
    }
    *out_count = 8;
    return TB_STATUS_OK;
}

tb_status tb_contact_points_sphere(double radius, tb_contact_point *out, size_t capacity,
                                   size_t *out_count)
{
    tb_status status = room(1, capacity, out, out_count);
    if (status == TB_STATUS_OK) {
        status = check_dimensions(&radius, 1);
    }
    if (status == TB_STATUS_OK) {
        memset(out, 0, sizeof *out);
        out[0].radius = radius;
        *out_count = 1;
    }
    return status;
}

tb_status tb_contact_points_capsule(double radius, double length, tb_contact_point *out,
                                    size_t capacity, size_t *out_count)
{
    tb_status status = room(2, capacity, out, out_count);
    if (status == TB_STATUS_OK) {
        status = check_dimensions((const double[]){radius, length}, 2);
    }
    if (status == TB_STATUS_OK) {
        memset(out, 0, 2 * sizeof *out);
        out[0].position[2] = -0.5 * length;
        out[1].position[2] = 0.5 * length;
        out[0].radius = out[1].radius = radius;
        *out_count = 2;
    }
    return status;
}

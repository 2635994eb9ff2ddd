/* Scene files: the "bodies" section. Each body has a name, mass properties from a shape
 * (scene_file_shapes.c) or given directly (mass and inertia), a pose, velocities, and contact
 * points for ground planes (a shape's natural ones unless told otherwise). */
#include "io/scene_file_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* "mass" with "inertia": three principal moments or a full 3 x 3 tensor (kg m^2, shape frame,
 * about the centre of mass), and an optional "center" (shape frame). */
static tb_status load_inertia(tb__loader *ld, const json_t *body, const char *path,
                              tb__body_build *b)
{
    double mass, center[3] = {0, 0, 0}, I[9] = {0};
    tb_status status = tb__json_number(ld, body, path, "mass", true, &mass);
    if (status == TB_STATUS_OK) {
        status = tb__check_positive_at(ld, path, "mass", mass);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, body, path, "center", 3, false, center);
    }
    const json_t *inertia = json_object_get(body, "inertia");
    if (status == TB_STATUS_OK && inertia == NULL) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "needs a shape, or mass with inertia (3 principal moments or a 3x3 "
                             "tensor)");
    }
    char where[160];
    snprintf(where, sizeof where, "%s.inertia", path);
    const bool moments =
        json_array_size(inertia) == 3 && json_is_number(json_array_get(inertia, 0));
    if (status == TB_STATUS_OK && moments) {
        double m[3];
        status = tb__json_numbers(ld, inertia, where, 3, m);
        I[0] = m[0], I[4] = m[1], I[8] = m[2];
    } else if (status == TB_STATUS_OK &&
               (!json_is_array(inertia) || json_array_size(inertia) != 3)) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                               "must be 3 principal moments or 3 rows of 3 numbers");
    }
    for (size_t row = 0; row < 3 && status == TB_STATUS_OK && !moments; ++row) {
        char row_path[176];
        snprintf(row_path, sizeof row_path, "%s[%zu]", where, row);
        status = tb__json_numbers(ld, json_array_get(inertia, row), row_path, 3, I + 3 * row);
    }
    tb_error error;
    if (status == TB_STATUS_OK) {
        status = tb__mass_result(ld, tb_mass_from_tensor(mass, center, I, &b->def.mass, &error),
                                 path, &error);
    }
    return status;
}

/* Entry k of a contact's "points": {"position", "radius" (default 0)}. */
static tb_status load_contact_point(tb__loader *ld, const json_t *entry, const char *where,
                                    size_t k, tb_contact_point *p)
{
    static const char *const point_keys[] = {"position", "radius", NULL};
    char item[176];
    tb__path_index(item, sizeof item, where, "points", k);
    p->radius = 0.0;
    tb_status status = tb__json_object(ld, entry, item, point_keys);
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, entry, item, "position", 3, true, p->position);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, entry, item, "radius", false, &p->radius);
    }
    return status == TB_STATUS_OK ? tb__check_non_negative_at(ld, item, "radius", p->radius)
                                  : status;
}

/* "contact": false, or {"points": [{"position", "radius"}], "support": n}. */
static tb_status load_contact(tb__loader *ld, const json_t *body, const char *path,
                              tb__body_build *b)
{
    const json_t *contact = json_object_get(body, "contact");
    b->has_contacts = b->contacts.count > 0;
    if (contact == NULL) {
        return TB_STATUS_OK;
    }
    char where[160];
    snprintf(where, sizeof where, "%s.contact", path);
    if (json_is_false(contact)) {
        b->has_contacts = false;
        return TB_STATUS_OK;
    }
    if (b->def.motion != TB_MOTION_DYNAMIC) { /* not dropped without a word */
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                             "a %s body has no contact points: ground planes push only dynamic "
                             "bodies (contact between bodies uses its shape); remove it",
                             b->def.motion == TB_MOTION_STATIC ? "static" : "keyframed");
    }
    static const char *const keys[] = {"points", "support", NULL};
    tb_status status = tb__json_object(ld, contact, where, keys);
    const json_t *list = json_object_get(contact, "points");
    if (status == TB_STATUS_OK && (!json_is_array(list) || json_array_size(list) == 0)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                             "points: must be a non-empty array of {position, radius}");
    }
    const size_t n = status == TB_STATUS_OK ? json_array_size(list) : 0;
    free(b->contacts.many);
    b->contacts.many = tb__malloc_array(n > 0 ? n : 1, sizeof *b->contacts.many);
    if (b->contacts.many == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, where, "%zu contact points", n);
    }
    for (size_t k = 0; k < n && status == TB_STATUS_OK; ++k) {
        status = load_contact_point(ld, json_array_get(list, k), where, k, &b->contacts.many[k]);
    }
    long support = (long)n;
    if (status == TB_STATUS_OK) {
        status = tb__json_count(ld, contact, where, "support", false, &support);
    }
    if (status == TB_STATUS_OK && (support < 1 || (size_t)support > n)) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                               "support: must be from 1 to the number of points (%zu), got %ld", n,
                               support);
    }
    b->contacts.count = n;
    b->contacts.support = (size_t)support;
    b->has_contacts = true;
    return status;
}

/* "position", "orientation" (w, x, y, z: the shape frame's), and "velocity" with
 * "angular_velocity" (world) or "angular_velocity_body" (shape frame). */
static tb_status load_motion(tb__loader *ld, const json_t *body, const char *path, tb_body_def *def)
{
    tb_status status = tb__json_vector(ld, body, path, "position", 3, false, def->position);
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, body, path, "orientation", 4, false, def->orientation);
    }
    const double norm = tb__q_norm(def->orientation);
    if (status == TB_STATUS_OK && fabs(norm - 1.0) > 1e-4) {
        char where[160];
        snprintf(where, sizeof where, "%s.orientation", path);
        status =
            tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                          "must be a unit quaternion (w, x, y, z) to 1e-4, got |q| = %g", norm);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, body, path, "velocity", 3, false, def->velocity);
    }
    const bool world = json_object_get(body, "angular_velocity") != NULL;
    const bool own = json_object_get(body, "angular_velocity_body") != NULL;
    if (status == TB_STATUS_OK && world && own) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "give angular_velocity or angular_velocity_body, not both");
    }
    if (status == TB_STATUS_OK && world) {
        status =
            tb__json_vector(ld, body, path, "angular_velocity", 3, true, def->angular_velocity);
    }
    if (status == TB_STATUS_OK && own) {
        double omega[3], q[4];
        status = tb__json_vector(ld, body, path, "angular_velocity_body", 3, true, omega);
        for (int k = 0; k < 4; ++k) {
            q[k] = def->orientation[k] / norm;
        }
        tb__q_rotate(def->angular_velocity, q, omega);
    }
    return status;
}

/* "motion": "dynamic" (the default), "static" or "keyframed". */
static tb_status load_motion_kind(tb__loader *ld, const json_t *body, const char *path,
                                  tb_body_motion *out)
{
    const char *motion = NULL;
    tb_status status = tb__json_string(ld, body, path, "motion", false, &motion);
    if (status != TB_STATUS_OK || motion == NULL || strcmp(motion, "dynamic") == 0) {
        return status;
    }
    if (strcmp(motion, "static") == 0 || strcmp(motion, "keyframed") == 0) {
        *out = motion[0] == 's' ? TB_MOTION_STATIC : TB_MOTION_KEYFRAMED;
        return TB_STATUS_OK;
    }
    char where[160];
    snprintf(where, sizeof where, "%s.motion", path);
    return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                         "\"%s\" is not a motion: \"dynamic\", \"static\" or \"keyframed\"",
                         motion);
}

/* A keyframed body's "keys" and "interpolation" (scene_file_keys.c; required for it, refused for
 * the others), its added pose the first key's; k->keys NULL for a body of another kind. */
typedef struct keys_build {
    tb_body_key *keys;
    size_t count;
    tb_interpolation interpolation;
} keys_build;

static tb_status load_body_keys(tb__loader *ld, const json_t *body, const char *path,
                                tb__body_build *b, keys_build *k)
{
    if (b->def.motion != TB_MOTION_KEYFRAMED) {
        const bool keyed = json_object_get(body, "keys") || json_object_get(body, "interpolation");
        return keyed ? tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                                     "keys and interpolation are for \"motion\": \"keyframed\"")
                     : TB_STATUS_OK;
    }
    if (json_object_get(body, "position") || json_object_get(body, "orientation")) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "a keyframed body's pose comes from its keys: no position or "
                             "orientation");
    }
    if (json_object_get(body, "velocity") || json_object_get(body, "angular_velocity") ||
        json_object_get(body, "angular_velocity_body")) { /* else read and silently unused */
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "a keyframed body's velocities come from its keys: give them "
                             "as a key's velocity or angular_velocity");
    }
    tb_status status = tb__load_keys(ld, body, path, &k->keys, &k->count, &k->interpolation);
    if (status == TB_STATUS_OK) {
        const tb_body_key *first = &k->keys[0];
        const double norm = tb__q_norm(first->orientation);
        for (int i = 0; i < 3; ++i) {
            b->def.position[i] = first->position[i];
        }
        for (int i = 0; i < 4; ++i) {
            b->def.orientation[i] = first->orientation[i] / norm;
        }
    }
    return status;
}

static tb_status add_body(tb__loader *ld, const char *path, tb__body_build *b, const keys_build *k)
{
    size_t id;
    tb_status status = tb_scene_add_body(ld->scene, &b->def, &id);
    if (status == TB_STATUS_OK && k->keys != NULL) {
        status = tb_scene_set_body_keys(ld->scene, id, k->keys, k->count, k->interpolation);
    }
    if (status != TB_STATUS_OK) { /* the file's key, not the C field ("def.name") it went to */
        const char *detail = tb_scene_detail(ld->scene);
        return tb__load_fail(ld, status == TB_STATUS_OUT_OF_MEMORY ? status : TB_STATUS_BAD_SCENE,
                             path, "%s", detail + (strncmp(detail, "def.", 4) == 0 ? 4 : 0));
    }
    if (b->has_contacts && b->def.motion == TB_MOTION_DYNAMIC) { /* the ground's, for bodies
                                                                     that can move */
        const tb_contact_point *points = b->contacts.many ? b->contacts.many : b->contacts.points;
        status = tb_scene_set_contact_points(ld->scene, id, points, b->contacts.count,
                                             b->contacts.support);
    }
    if (status != TB_STATUS_OK) {
        return tb__load_fail(ld, status, path, "contact: %s", tb_scene_detail(ld->scene));
    }
    if (b->pieces != NULL) {
        status = tb_scene_set_body_pieces(ld->scene, id, b->pieces, b->piece_count);
    } else if (b->shape.type != TB_SHAPE_NONE) {
        status = tb_scene_set_body_shape(ld->scene, id, &b->shape);
    }
    return status == TB_STATUS_OK
               ? status
               : tb__load_fail(ld, status == TB_STATUS_OUT_OF_MEMORY ? status : TB_STATUS_BAD_SCENE,
                               path, "shape: %s", tb_scene_detail(ld->scene));
}

/* The body's shape (and mass properties from it) or its mass and inertia; a body with no
 * state needs neither. */
static tb_status load_shape_or_inertia(tb__loader *ld, const json_t *body, const char *path,
                                       tb__body_build *b)
{
    const bool shaped = json_object_get(body, "shape") != NULL;
    if (shaped && (json_object_get(body, "inertia") || json_object_get(body, "center"))) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "inertia and center come from the shape: give one or the other");
    }
    if (!shaped && json_object_get(body, "density")) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "density: applies to a shape; with inertia give mass");
    }
    const bool needs_mass = b->def.motion == TB_MOTION_DYNAMIC || json_object_get(body, "mass");
    if (!shaped && !needs_mass) {
        return TB_STATUS_OK;
    }
    return shaped ? tb__load_shape(ld, body, path, b) : load_inertia(ld, body, path, b);
}

static tb_status load_body(tb__loader *ld, const json_t *body, const char *path)
{
    static const char *const keys[] = {"name",
                                       "shape",
                                       "mass",
                                       "density",
                                       "inertia",
                                       "center",
                                       "position",
                                       "orientation",
                                       "velocity",
                                       "angular_velocity",
                                       "angular_velocity_body",
                                       "contact",
                                       "motion",
                                       "keys",
                                       "interpolation",
                                       NULL};
    tb__body_build b;
    memset(&b, 0, sizeof b);
    keys_build k = {NULL, 0, TB_INTERPOLATION_CUBIC};
    b.def = tb_body_def_default();
    b.shape = tb_shape_default();
    tb_status status = tb__json_object(ld, body, path, keys);
    if (status == TB_STATUS_OK) {
        status = tb__json_string(ld, body, path, "name", true, &b.def.name);
    }
    size_t existing;
    if (status == TB_STATUS_OK && tb_scene_find_body(ld->scene, b.def.name, &existing) == 0) {
        status =
            tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                          "name: \"%s\" is already the name of bodies[%zu]", b.def.name, existing);
    }
    if (status == TB_STATUS_OK) {
        status = load_motion_kind(ld, body, path, &b.def.motion);
    }
    if (status == TB_STATUS_OK) {
        status = load_shape_or_inertia(ld, body, path, &b);
    }
    if (status == TB_STATUS_OK) {
        status = load_contact(ld, body, path, &b);
    }
    if (status == TB_STATUS_OK) {
        status = load_motion(ld, body, path, &b.def);
    }
    if (status == TB_STATUS_OK) {
        status = load_body_keys(ld, body, path, &b, &k);
    }
    if (status == TB_STATUS_OK) {
        status = add_body(ld, path, &b, &k);
    }
    free(k.keys);
    free(b.contacts.many);
    free(b.shape_vertices);
    free(b.shape_triangles);
    tb__free_pieces(&b);
    return status;
}

tb_status tb__load_bodies(tb__loader *ld, const json_t *bodies)
{
    if (!json_is_array(bodies) || json_array_size(bodies) == 0) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, "bodies",
                             "must be a non-empty array of bodies");
    }
    tb_status status = TB_STATUS_OK;
    for (size_t i = 0; i < json_array_size(bodies) && status == TB_STATUS_OK; ++i) {
        char path[32];
        tb__path_index(path, sizeof path, "", "bodies", i);
        status = load_body(ld, json_array_get(bodies, i), path);
    }
    return status;
}

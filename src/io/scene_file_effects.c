/* Scene files: the "effects" section, a list of {"type": ..., parameters} objects that name
 * bodies by their "name". */
#include "io/scene_file_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The body called by the string at object.key, or (allow_world) TB_WORLD if it is missing. */
static tb_status body_named(tb__loader *ld, const json_t *object, const char *path, const char *key,
                            bool allow_missing, size_t *out)
{
    const char *name = NULL;
    tb_status status = tb__json_string(ld, object, path, key, !allow_missing, &name);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (name == NULL) {
        *out = TB_WORLD; /* TB_WORLD and TB_ALL_BODIES are the same "none given" value */
        return TB_STATUS_OK;
    }
    if (tb_scene_find_body(ld->scene, name, out) != TB_STATUS_OK) {
        char where[160];
        snprintf(where, sizeof where, "%s.%s", path, key);
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "no body is named \"%s\"", name);
    }
    return TB_STATUS_OK;
}

/* Reads the listed optional numbers, each >= 0 (or > 0 if its name is in positive). */
typedef struct number_field {
    const char *key;
    double *value;
    bool positive;
} number_field;

static tb_status numbers(tb__loader *ld, const json_t *object, const char *path,
                         const number_field *fields)
{
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; fields[k].key != NULL && status == TB_STATUS_OK; ++k) {
        status = tb__json_number(ld, object, path, fields[k].key, false, fields[k].value);
        if (status == TB_STATUS_OK) {
            status = fields[k].positive
                         ? tb__check_positive_at(ld, path, fields[k].key, *fields[k].value)
                         : tb__check_non_negative_at(ld, path, fields[k].key, *fields[k].value);
        }
    }
    return status;
}

/* A library refusal, prefixed with the effect's path. */
static tb_status added(tb__loader *ld, tb_status status, const char *path)
{
    return status == TB_STATUS_OK
               ? status
               : tb__load_fail(ld, TB_STATUS_BAD_SCENE, path, "%s", tb_scene_detail(ld->scene));
}

static tb_status load_gravity(tb__loader *ld, const json_t *e, const char *path)
{
    static const char *const keys[] = {"type", "g", NULL};
    double g[3] = {0.0, 0.0, -9.81};
    tb_status status = tb__json_object(ld, e, path, keys);
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, e, path, "g", 3, false, g);
    }
    return status == TB_STATUS_OK ? added(ld, tb_scene_add_gravity(ld->scene, g), path) : status;
}

static tb_status load_drag(tb__loader *ld, const json_t *e, const char *path)
{
    static const char *const keys[] = {
        "type", "body", "linear", "quadratic", "angular", "angular_quadratic", NULL};
    tb_drag_def def = tb_drag_def_default();
    const number_field fields[] = {{"linear", &def.linear, false},
                                   {"quadratic", &def.quadratic, false},
                                   {"angular", &def.angular, false},
                                   {"angular_quadratic", &def.angular_quadratic, false},
                                   {NULL, NULL, false}};
    tb_status status = tb__json_object(ld, e, path, keys);
    if (status == TB_STATUS_OK) {
        status = body_named(ld, e, path, "body", true, &def.body);
    }
    if (status == TB_STATUS_OK) {
        status = numbers(ld, e, path, fields);
    }
    return status == TB_STATUS_OK ? added(ld, tb_scene_add_drag(ld->scene, &def), path) : status;
}

/* World position of a point given in a body's shape frame (or a world point). */
static void world_point(const tb_scene *scene, size_t body, const double point[3], double out[3])
{
    if (body == TB_WORLD) {
        tb__v3_copy(out, point);
        return;
    }
    double origin[3], q[4];
    tb_scene_body_shape_pose(scene, tb_scene_states_const(scene), body, origin, q);
    tb__q_rotate(out, q, point);
    tb__v3_axpy(out, 1.0, origin);
}

static tb_status load_spring(tb__loader *ld, const json_t *e, const char *path)
{
    static const char *const keys[] = {"type",      "body_a",  "point_a",     "body_b", "point_b",
                                       "stiffness", "damping", "rest_length", NULL};
    tb_spring_def def = tb_spring_def_default();
    const number_field fields[] = {{"stiffness", &def.stiffness, false},
                                   {"damping", &def.damping, false},
                                   {"rest_length", &def.rest_length, false},
                                   {NULL, NULL, false}};
    tb_status status = tb__json_object(ld, e, path, keys);
    if (status == TB_STATUS_OK) {
        status = body_named(ld, e, path, "body_a", false, &def.body_a);
    }
    if (status == TB_STATUS_OK) {
        status = body_named(ld, e, path, "body_b", true, &def.body_b);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, e, path, "point_a", 3, false, def.point_a);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, e, path, "point_b", 3, def.body_b == TB_WORLD, def.point_b);
    }
    if (status == TB_STATUS_OK && json_object_get(e, "stiffness") == NULL) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, path, "stiffness: missing (N/m)");
    }
    if (status == TB_STATUS_OK && json_object_get(e, "rest_length") == NULL) {
        double a[3], b[3]; /* default: the spring starts at rest */
        world_point(ld->scene, def.body_a, def.point_a, a);
        world_point(ld->scene, def.body_b, def.point_b, b);
        const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
        def.rest_length = tb__v3_norm(d);
    }
    if (status == TB_STATUS_OK) {
        status = numbers(ld, e, path, fields);
    }
    return status == TB_STATUS_OK ? added(ld, tb_scene_add_spring(ld->scene, &def), path) : status;
}

static tb_status frame_named(tb__loader *ld, const json_t *e, const char *path, tb_frame *out)
{
    const char *frame = NULL;
    tb_status status = tb__json_string(ld, e, path, "frame", false, &frame);
    *out = TB_FRAME_WORLD;
    if (status == TB_STATUS_OK && frame != NULL) {
        if (strcmp(frame, "body") == 0) {
            *out = TB_FRAME_BODY;
        } else if (strcmp(frame, "world") != 0) {
            char where[160];
            snprintf(where, sizeof where, "%s.frame", path);
            status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                                   "must be \"world\" or \"body\", got \"%s\"", frame);
        }
    }
    return status;
}

static tb_status load_force_or_torque(tb__loader *ld, const json_t *e, const char *path, bool force)
{
    static const char *const force_keys[] = {"type", "body", "force", "point", "frame", NULL};
    static const char *const torque_keys[] = {"type", "body", "torque", "frame", NULL};
    double vector[3], point[3] = {0, 0, 0};
    size_t body;
    tb_frame frame;
    tb_status status = tb__json_object(ld, e, path, force ? force_keys : torque_keys);
    if (status == TB_STATUS_OK) {
        status = body_named(ld, e, path, "body", false, &body);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, e, path, force ? "force" : "torque", 3, true, vector);
    }
    if (status == TB_STATUS_OK && force) {
        status = tb__json_vector(ld, e, path, "point", 3, false, point);
    }
    if (status == TB_STATUS_OK) {
        status = frame_named(ld, e, path, &frame);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    return added(ld,
                 force ? tb_scene_add_force(ld->scene, body, vector, point, frame)
                       : tb_scene_add_torque(ld->scene, body, vector, frame),
                 path);
}

static tb_status load_ground(tb__loader *ld, const json_t *e, const char *path)
{
    static const char *const keys[] = {
        "type",        "normal",          "offset",           "gravity",           "penetration",
        "restitution", "static_friction", "kinetic_friction", "stribeck_velocity", "presliding",
        NULL};
    tb_ground_def def = tb_ground_def_default();
    const number_field fields[] = {{"gravity", &def.gravity, true},
                                   {"penetration", &def.penetration, true},
                                   {"restitution", &def.restitution, false},
                                   {"static_friction", &def.static_friction, false},
                                   {"kinetic_friction", &def.kinetic_friction, false},
                                   {"stribeck_velocity", &def.stribeck_velocity, true},
                                   {"presliding", &def.presliding, true},
                                   {NULL, NULL, false}};
    tb_status status = tb__json_object(ld, e, path, keys);
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, e, path, "normal", 3, false, def.normal);
    }
    /* a direction: any length will do (tb_scene_add_ground normalises it) */
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, e, path, "offset", false, &def.offset);
    }
    if (status == TB_STATUS_OK) {
        status = numbers(ld, e, path, fields);
    }
    return status == TB_STATUS_OK ? added(ld, tb_scene_add_ground(ld->scene, &def), path) : status;
}

/* Entry k of a contact effect's "bodies": the id of a body with a shape, named once. */
static tb_status contact_body(tb__loader *ld, const json_t *names, const char *where, size_t k,
                              size_t *ids)
{
    const json_t *entry = json_array_get(names, k);
    if (!json_is_string(entry)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "entry %zu: must be a body's name", k);
    }
    const char *name = json_string_value(entry);
    if (tb_scene_find_body(ld->scene, name, &ids[k]) != TB_STATUS_OK) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "entry %zu: no body is named \"%s\"",
                             k, name);
    }
    for (size_t j = 0; j < k; ++j) {
        if (ids[j] == ids[k]) {
            return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                                 "entry %zu: \"%s\" is listed twice (also entry %zu)", k, name, j);
        }
    }
    tb_shape_type type = TB_SHAPE_NONE;
    tb_scene_body_shape_type(ld->scene, ids[k], &type);
    if (type == TB_SHAPE_NONE) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                             "entry %zu: \"%s\" has no shape, so it cannot touch anything", k,
                             name);
    }
    return TB_STATUS_OK;
}

/* "bodies": an array of body names, into ids[] (room for the array's entries). */
static tb_status contact_bodies(tb__loader *ld, const json_t *names, const char *path, size_t *ids,
                                size_t *count)
{
    char where[160];
    snprintf(where, sizeof where, "%s.bodies", path);
    *count = json_array_size(names);
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < *count && status == TB_STATUS_OK; ++k) {
        status = contact_body(ld, names, where, k, ids);
    }
    return status;
}

static tb_status load_contact(tb__loader *ld, const json_t *e, const char *path)
{
    static const char *const keys[] = {
        "type",        "bodies",  "restitution",       "static_friction", "kinetic_friction",
        "penetration", "gravity", "stribeck_velocity", "presliding",      NULL};
    tb_contact_def def = tb_contact_def_default();
    const number_field fields[] = {{"restitution", &def.restitution, false},
                                   {"static_friction", &def.static_friction, false},
                                   {"kinetic_friction", &def.kinetic_friction, false},
                                   {"penetration", &def.penetration, true},
                                   {"gravity", &def.gravity, true},
                                   {"stribeck_velocity", &def.stribeck_velocity, true},
                                   {"presliding", &def.presliding, true},
                                   {NULL, NULL, false}};
    tb_status status = tb__json_object(ld, e, path, keys);
    if (status == TB_STATUS_OK) {
        status = numbers(ld, e, path, fields);
    }
    const json_t *names = json_object_get(e, "bodies");
    size_t *ids = NULL;
    if (status == TB_STATUS_OK && names != NULL &&
        (!json_is_array(names) || json_array_size(names) == 0)) {
        char where[160];
        snprintf(where, sizeof where, "%s.bodies", path);
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "must be an array of body names");
    }
    if (status == TB_STATUS_OK && names != NULL) {
        ids = tb__malloc_array(json_array_size(names) + 1, sizeof *ids);
        status = ids == NULL ? tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "body list")
                             : contact_bodies(ld, names, path, ids, &def.body_count);
        def.bodies = ids;
    }
    if (status == TB_STATUS_OK) {
        status = added(ld, tb_scene_add_contact(ld->scene, &def), path);
    }
    free(ids);
    return status;
}

static tb_status load_effect(tb__loader *ld, const json_t *e, const char *path)
{
    const char *type = NULL;
    tb_status status = json_is_object(e) ? tb__json_string(ld, e, path, "type", true, &type)
                                         : tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                                                         "must be an object with a \"type\"");
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (strcmp(type, "gravity") == 0) {
        return load_gravity(ld, e, path);
    }
    if (strcmp(type, "drag") == 0) {
        return load_drag(ld, e, path);
    }
    if (strcmp(type, "spring") == 0) {
        return load_spring(ld, e, path);
    }
    if (strcmp(type, "force") == 0 || strcmp(type, "torque") == 0) {
        return load_force_or_torque(ld, e, path, strcmp(type, "force") == 0);
    }
    if (strcmp(type, "ground") == 0) {
        return load_ground(ld, e, path);
    }
    if (strcmp(type, "contact") == 0) {
        return load_contact(ld, e, path);
    }
    char where[160];
    snprintf(where, sizeof where, "%s.type", path);
    return tb__load_fail(
        ld, TB_STATUS_BAD_SCENE, where,
        "must be one of gravity, drag, spring, force, torque, ground, contact, got "
        "\"%s\"",
        type);
}

tb_status tb__load_effects(tb__loader *ld, const json_t *effects)
{
    if (!json_is_array(effects)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, "effects", "must be an array of effects");
    }
    tb_status status = TB_STATUS_OK;
    for (size_t i = 0; i < json_array_size(effects) && status == TB_STATUS_OK; ++i) {
        char path[32];
        tb__path_index(path, sizeof path, "", "effects", i);
        status = load_effect(ld, json_array_get(effects, i), path);
    }
    return status;
}

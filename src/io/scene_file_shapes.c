/* Scene files: a body's "shape" (box, sphere, cylinder, capsule, ellipsoid, mesh, points):
 * its mass properties with the body's mass or density, and the contact points it brings. Each
 * type takes its own keys; one that belongs to another type is refused, not ignored. */
#include "io/scene_file_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* mass from "mass" or "density" (exactly one) */
tb_status tb__load_mass_mode(tb__loader *ld, const json_t *body, const char *path,
                             tb_mass_mode *mode, double *value)
{
    const bool has_mass = json_object_get(body, "mass") != NULL;
    const bool has_density = json_object_get(body, "density") != NULL;
    if (has_mass == has_density) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             has_mass ? "give mass or density, not both"
                                      : "missing mass or density (the shape needs one)");
    }
    *mode = has_mass ? TB_MASS_GIVEN : TB_MASS_DENSITY;
    const char *key = has_mass ? "mass" : "density";
    tb_status status = tb__json_number(ld, body, path, key, true, value);
    return status == TB_STATUS_OK ? tb__check_positive_at(ld, path, key, *value) : status;
}

/* The library's message names the mass or density: prefix the body's path. */
tb_status tb__mass_result(tb__loader *ld, tb_status status, const char *path, const tb_error *error)
{
    return status == TB_STATUS_OK
               ? status
               : tb__load_fail(ld, TB_STATUS_BAD_SCENE, path, "%s", error->message);
}

static tb_status positive_vector(tb__loader *ld, const json_t *shape, const char *path,
                                 const char *key, double out[3])
{
    tb_status status = tb__json_vector(ld, shape, path, key, 3, true, out);
    for (int i = 0; i < 3 && status == TB_STATUS_OK; ++i) {
        char item[32];
        snprintf(item, sizeof item, "%s[%d]", key, i);
        status = tb__check_positive_at(ld, path, item, out[i]);
    }
    return status;
}

static tb_status positive_number(tb__loader *ld, const json_t *shape, const char *path,
                                 const char *key, double *out)
{
    tb_status status = tb__json_number(ld, shape, path, key, true, out);
    return status == TB_STATUS_OK ? tb__check_positive_at(ld, path, key, *out) : status;
}

/* Cylinder rims: 12 points around each end face; resting on a face, 12 carry it. */
static void cylinder_contacts(double radius, double length, tb__shape_contacts *c)
{
    for (int k = 0; k < 24; ++k) {
        const double angle = 2.0 * 3.14159265358979323846 * (k % 12) / 12.0;
        tb_contact_point *p = &c->points[k];
        tb__v3_set(p->position, radius * cos(angle), radius * sin(angle),
                   k < 12 ? -0.5 * length : 0.5 * length);
        p->radius = 0.0;
    }
    c->count = 24;
    c->support = 12;
}

/* Ellipsoid: the 6 ends of its axes and 8 points on the diagonals, on the surface. */
static void ellipsoid_contacts(const double a[3], tb__shape_contacts *c)
{
    size_t n = 0;
    for (int axis = 0; axis < 3; ++axis) {
        for (int sign = -1; sign <= 1; sign += 2) {
            memset(&c->points[n], 0, sizeof c->points[n]);
            c->points[n++].position[axis] = sign * a[axis];
        }
    }
    const double s = 1.0 / sqrt(3.0);
    for (unsigned corner = 0; corner < 8; ++corner, ++n) {
        for (int i = 0; i < 3; ++i) {
            c->points[n].position[i] = ((corner >> i) & 1 ? s : -s) * a[i];
        }
        c->points[n].radius = 0.0;
    }
    c->count = n;
    c->support = 1;
}

static tb_status load_box_sphere(tb__loader *ld, const json_t *shape, const char *path,
                                 const char *type, tb_mass_mode mode, double value,
                                 tb__body_build *b, tb_error *error)
{
    tb_status status;
    if (strcmp(type, "box") == 0) {
        double size[3];
        status = positive_vector(ld, shape, path, "size", size);
        if (status == TB_STATUS_OK) {
            status = tb_mass_from_box(mode, value, size, &b->def.mass, error);
            b->shape.type = TB_SHAPE_BOX;
            memcpy(b->shape.size, size, sizeof size);
            tb_contact_points_box(size, b->contacts.points, TB__SHAPE_POINTS_MAX,
                                  &b->contacts.count);
            b->contacts.support = 4;
        }
        return status;
    }
    double radius;
    status = positive_number(ld, shape, path, "radius", &radius);
    if (status == TB_STATUS_OK) {
        status = tb_mass_from_sphere(mode, value, radius, &b->def.mass, error);
        b->shape.type = TB_SHAPE_SPHERE;
        b->shape.radius = radius;
        tb_contact_points_sphere(radius, b->contacts.points, TB__SHAPE_POINTS_MAX,
                                 &b->contacts.count);
        b->contacts.support = 1;
    }
    return status;
}

static tb_status load_round(tb__loader *ld, const json_t *shape, const char *path, const char *type,
                            tb_mass_mode mode, double value, tb__body_build *b, tb_error *error)
{
    if (strcmp(type, "ellipsoid") == 0) {
        double semi_axes[3];
        tb_status status = positive_vector(ld, shape, path, "semi_axes", semi_axes);
        if (status == TB_STATUS_OK) {
            status = tb_mass_from_ellipsoid(mode, value, semi_axes, &b->def.mass, error);
            b->shape.type = TB_SHAPE_ELLIPSOID;
            memcpy(b->shape.semi_axes, semi_axes, sizeof semi_axes);
            ellipsoid_contacts(semi_axes, &b->contacts);
        }
        return status;
    }
    double radius, length;
    tb_status status = positive_number(ld, shape, path, "radius", &radius);
    if (status == TB_STATUS_OK) {
        status = positive_number(ld, shape, path, "length", &length);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    b->shape.radius = radius;
    b->shape.length = length;
    b->shape.type = strcmp(type, "cylinder") == 0 ? TB_SHAPE_CYLINDER : TB_SHAPE_CAPSULE;
    if (strcmp(type, "cylinder") == 0) {
        cylinder_contacts(radius, length, &b->contacts);
        return tb_mass_from_cylinder(mode, value, radius, length, &b->def.mass, error);
    }
    tb_contact_points_capsule(radius, length, b->contacts.points, TB__SHAPE_POINTS_MAX,
                              &b->contacts.count);
    b->contacts.support = 2;
    return tb_mass_from_capsule(mode, value, radius, length, &b->def.mass, error);
}

/* Vertices as contact points (radius 0); a mesh rests on at least 3 of them. */
static tb_status vertex_contacts(tb__loader *ld, const double *vertices, size_t count,
                                 const char *path, tb__shape_contacts *c)
{
    c->many = tb__malloc_array(count > 0 ? count : 1, sizeof *c->many);
    if (c->many == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "%zu contact points", count);
    }
    for (size_t v = 0; v < count; ++v) {
        memcpy(c->many[v].position, vertices + 3 * v, 3 * sizeof(double));
        c->many[v].radius = 0.0;
    }
    c->count = count;
    c->support = count < 3 ? count : 3;
    return TB_STATUS_OK;
}

static tb_status load_mesh(tb__loader *ld, const json_t *shape, const char *path, tb_mass_mode mode,
                           double value, tb__body_build *b, tb_error *error)
{
    tb_status status = tb__load_mesh_shape(ld, shape, path, mode, value, b, error);
    if (status == TB_STATUS_OK) {
        status = vertex_contacts(ld, b->shape.vertices, b->shape.vertex_count, path, &b->contacts);
    }
    return status;
}

/* "points": [{"position": [x, y, z], "mass": m}, ...] */
static tb_status load_points(tb__loader *ld, const json_t *shape, const char *path,
                             tb__body_build *b)
{
    const json_t *list = json_object_get(shape, "points");
    if (!json_is_array(list) || json_array_size(list) == 0) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "points: must be a non-empty array of {position, mass}");
    }
    const size_t n = json_array_size(list);
    double *positions = tb__malloc_array(n, 3 * sizeof(double));
    double *masses = tb__malloc_array(n, sizeof(double));
    tb_status status = positions != NULL && masses != NULL ? TB_STATUS_OK : TB_STATUS_OUT_OF_MEMORY;
    static const char *const keys[] = {"position", "mass", NULL};
    for (size_t k = 0; k < n && status == TB_STATUS_OK; ++k) {
        char item[160];
        tb__path_index(item, sizeof item, path, "points", k);
        const json_t *point = json_array_get(list, k);
        status = tb__json_object(ld, point, item, keys);
        if (status == TB_STATUS_OK) {
            status = tb__json_vector(ld, point, item, "position", 3, true, positions + 3 * k);
        }
        if (status == TB_STATUS_OK) {
            status = positive_number(ld, point, item, "mass", &masses[k]);
        }
    }
    tb_error error;
    if (status == TB_STATUS_OK) {
        status = tb__mass_result(
            ld, tb_mass_from_points(positions, masses, n, &b->def.mass, &error), path, &error);
    }
    if (status == TB_STATUS_OK) {
        status = vertex_contacts(ld, positions, n, path, &b->contacts);
    }
    b->shape.type = TB_SHAPE_POINTS; /* collides as the points' convex hull */
    b->shape.vertices = b->shape_vertices = positions;
    b->shape.vertex_count = n;
    free(masses);
    return status;
}

/* The keys each shape type takes. */
typedef struct shape_keys {
    const char *type;
    const char *const keys[5]; /* besides "type"; NULL-terminated */
} shape_keys;

static const shape_keys shape_types[] = {
    {"box", {"size", NULL}},
    {"sphere", {"radius", NULL}},
    {"cylinder", {"radius", "length", NULL}},
    {"capsule", {"radius", "length", NULL}},
    {"ellipsoid", {"semi_axes", NULL}},
    {"mesh", {"file", "vertices", "triangles", NULL}},
    {"points", {"points", NULL}},
};

static bool listed(const char *const *keys, const char *key)
{
    for (size_t k = 0; keys[k] != NULL; ++k) {
        if (strcmp(keys[k], key) == 0) {
            return true;
        }
    }
    return false;
}

/* The shape's type, after refusing keys of other types ("radius" on a box was ignored). Keys
 * of no type at all are refused by tb__json_object before; a piece's pose keys pass. */
static tb_status shape_type(tb__loader *ld, const json_t *shape, const char *path, bool piece,
                            const char **out_type)
{
    const char *type = NULL;
    tb_status status = tb__json_string(ld, shape, path, "type", true, &type);
    const size_t count = sizeof shape_types / sizeof shape_types[0];
    size_t t = 0;
    while (status == TB_STATUS_OK && t < count && strcmp(shape_types[t].type, type) != 0) {
        ++t;
    }
    if (status == TB_STATUS_OK && t == count) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "type: must be one of box, sphere, cylinder, capsule, ellipsoid, "
                             "mesh, points, got \"%s\"",
                             type);
    }
    const char *key;
    const json_t *member;
    json_object_foreach((json_t *)shape, key, member)
    {
        const bool pose =
            piece && (strcmp(key, "position") == 0 || strcmp(key, "orientation") == 0);
        if (status == TB_STATUS_OK && strcmp(key, "type") != 0 && !pose &&
            !listed(shape_types[t].keys, key)) {
            char own[64] = "";
            for (size_t k = 0; shape_types[t].keys[k] != NULL; ++k) {
                snprintf(own + strlen(own), sizeof own - strlen(own), "%s%s", k ? ", " : "",
                         shape_types[t].keys[k]);
            }
            status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                                   "%s: does not apply to %s %s shape (it takes %s)", key,
                                   strchr("aeiou", type[0]) != NULL ? "an" : "a", type, own);
        }
    }
    *out_type = type;
    return status;
}

tb_status tb__load_shape_object(tb__loader *ld, const json_t *shape, const char *shape_path,
                                bool piece, const char **out_type)
{
    static const char *const keys[] = {"type", "size",     "radius",    "length", "semi_axes",
                                       "file", "vertices", "triangles", "points", NULL};
    static const char *const piece_keys[] = {"type",      "size",        "radius",   "length",
                                             "semi_axes", "file",        "vertices", "triangles",
                                             "position",  "orientation", NULL};
    /* before the keys: a points piece with its "points" was refused as an unknown key */
    const char *type = json_string_value(json_object_get(shape, "type"));
    if (piece && type != NULL && strcmp(type, "points") == 0) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, shape_path,
                             "type: a points shape carries its own masses and cannot be a piece");
    }
    tb_status status = tb__json_object(ld, shape, shape_path, piece ? piece_keys : keys);
    return status == TB_STATUS_OK ? shape_type(ld, shape, shape_path, piece, out_type) : status;
}

tb_status tb__load_shape_mass(tb__loader *ld, const json_t *shape, const char *shape_path,
                              const char *mass_path, const char *type, tb_mass_mode mode,
                              double value, tb__body_build *b)
{
    tb_error error;
    tb__clear_error(&error);
    tb_status status;
    if (strcmp(type, "box") == 0 || strcmp(type, "sphere") == 0) {
        status = load_box_sphere(ld, shape, shape_path, type, mode, value, b, &error);
    } else if (strcmp(type, "mesh") == 0) {
        status = load_mesh(ld, shape, shape_path, mode, value, b, &error);
    } else {
        status = load_round(ld, shape, shape_path, type, mode, value, b, &error);
    }
    return error.message[0] ? tb__mass_result(ld, status, mass_path, &error) : status;
}

tb_status tb__load_body_mass_mode(tb__loader *ld, const json_t *body, const char *path,
                                  const tb__body_build *b, tb_mass_mode *mode, double *value)
{
    if (b->def.motion != TB_MOTION_DYNAMIC && !json_object_get(body, "mass") &&
        !json_object_get(body, "density")) {
        *mode = TB_MASS_DENSITY; /* a body with no state needs no mass: any will do, unused */
        *value = 1.0;
        return TB_STATUS_OK;
    }
    return tb__load_mass_mode(ld, body, path, mode, value);
}

tb_status tb__load_shape(tb__loader *ld, const json_t *body, const char *path, tb__body_build *b)
{
    char shape_path[160];
    snprintf(shape_path, sizeof shape_path, "%s.shape", path);
    const json_t *shape = json_object_get(body, "shape");
    if (json_is_array(shape)) {
        return tb__load_pieces(ld, body, path, b);
    }
    const char *type = NULL;
    tb_status status = tb__load_shape_object(ld, shape, shape_path, false, &type);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (strcmp(type, "points") == 0) {
        if (json_object_get(body, "mass") || json_object_get(body, "density")) {
            return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                                 "a points shape carries its own masses: no mass or density");
        }
        return load_points(ld, shape, shape_path, b);
    }
    tb_mass_mode mode = TB_MASS_DENSITY;
    double value = 1.0;
    status = tb__load_body_mass_mode(ld, body, path, b, &mode, &value);
    if (status != TB_STATUS_OK) {
        return status;
    }
    return tb__load_shape_mass(ld, shape, shape_path, path, type, mode, value, b);
}

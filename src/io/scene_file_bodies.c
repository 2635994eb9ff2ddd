/* Scene files: the "bodies" section. Each body has a name, mass properties from a shape (with
 * mass or density) or given directly (mass and inertia), a pose, velocities, and contact
 * points for ground planes (a shape's natural ones unless told otherwise). */
#include "io/scene_file_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Contact points a shape brings by default, and how many of them carry it at rest. */
#define TB__MAX_SHAPE_POINTS 32
typedef struct shape_contacts {
    tb_contact_point points[TB__MAX_SHAPE_POINTS];
    size_t count;
    size_t support;
    tb_contact_point *many; /* meshes and point sets: allocated, else NULL */
} shape_contacts;

typedef struct body_build {
    tb_body_def def;
    shape_contacts contacts;
    bool has_contacts;
} body_build;

/* mass from "mass" or "density" (exactly one) */
static tb_status mass_mode(tb__loader *ld, const json_t *body, const char *path, tb_mass_mode *mode,
                           double *value)
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
static tb_status mass_result(tb__loader *ld, tb_status status, const char *path,
                             const tb_error *error)
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
static void cylinder_contacts(double radius, double length, shape_contacts *c)
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
static void ellipsoid_contacts(const double a[3], shape_contacts *c)
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
                                 const char *type, tb_mass_mode mode, double value, body_build *b,
                                 tb_error *error)
{
    tb_status status;
    if (strcmp(type, "box") == 0) {
        double size[3];
        status = positive_vector(ld, shape, path, "size", size);
        if (status == TB_STATUS_OK) {
            status = tb_mass_from_box(mode, value, size, &b->def.mass, error);
            tb_contact_points_box(size, b->contacts.points, TB__MAX_SHAPE_POINTS,
                                  &b->contacts.count);
            b->contacts.support = 4;
        }
        return status;
    }
    double radius;
    status = positive_number(ld, shape, path, "radius", &radius);
    if (status == TB_STATUS_OK) {
        status = tb_mass_from_sphere(mode, value, radius, &b->def.mass, error);
        tb_contact_points_sphere(radius, b->contacts.points, TB__MAX_SHAPE_POINTS,
                                 &b->contacts.count);
        b->contacts.support = 1;
    }
    return status;
}

static tb_status load_round(tb__loader *ld, const json_t *shape, const char *path, const char *type,
                            tb_mass_mode mode, double value, body_build *b, tb_error *error)
{
    if (strcmp(type, "ellipsoid") == 0) {
        double semi_axes[3];
        tb_status status = positive_vector(ld, shape, path, "semi_axes", semi_axes);
        if (status == TB_STATUS_OK) {
            status = tb_mass_from_ellipsoid(mode, value, semi_axes, &b->def.mass, error);
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
    if (strcmp(type, "cylinder") == 0) {
        cylinder_contacts(radius, length, &b->contacts);
        return tb_mass_from_cylinder(mode, value, radius, length, &b->def.mass, error);
    }
    tb_contact_points_capsule(radius, length, b->contacts.points, TB__MAX_SHAPE_POINTS,
                              &b->contacts.count);
    b->contacts.support = 2;
    return tb_mass_from_capsule(mode, value, radius, length, &b->def.mass, error);
}

/* Vertices as contact points (radius 0); a mesh rests on at least 3 of them. */
static tb_status vertex_contacts(tb__loader *ld, const double *vertices, size_t count,
                                 const char *path, shape_contacts *c)
{
    c->many = malloc((count > 0 ? count : 1) * sizeof *c->many);
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
                           double value, body_build *b, tb_error *error)
{
    double *vertices = NULL;
    size_t count = 0;
    tb_status status =
        tb__load_mesh_shape(ld, shape, path, mode, value, &b->def.mass, &vertices, &count, error);
    if (status == TB_STATUS_OK) {
        status = vertex_contacts(ld, vertices, count, path, &b->contacts);
    }
    free(vertices);
    return status;
}

/* "points": [{"position": [x, y, z], "mass": m}, ...] */
static tb_status load_points(tb__loader *ld, const json_t *shape, const char *path, body_build *b)
{
    const json_t *list = json_object_get(shape, "points");
    if (!json_is_array(list) || json_array_size(list) == 0) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "points: must be a non-empty array of {position, mass}");
    }
    const size_t n = json_array_size(list);
    double *positions = malloc(3 * n * sizeof(double)), *masses = malloc(n * sizeof(double));
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
        status = mass_result(ld, tb_mass_from_points(positions, masses, n, &b->def.mass, &error),
                             path, &error);
    }
    if (status == TB_STATUS_OK) {
        status = vertex_contacts(ld, positions, n, path, &b->contacts);
    }
    free(positions);
    free(masses);
    return status;
}

static tb_status load_shape(tb__loader *ld, const json_t *body, const char *path, body_build *b)
{
    char shape_path[160];
    snprintf(shape_path, sizeof shape_path, "%s.shape", path);
    const json_t *shape = json_object_get(body, "shape");
    static const char *const keys[] = {"type", "size",     "radius",    "length", "semi_axes",
                                       "file", "vertices", "triangles", "points", NULL};
    const char *type = NULL;
    tb_status status = tb__json_object(ld, shape, shape_path, keys);
    if (status == TB_STATUS_OK) {
        status = tb__json_string(ld, shape, shape_path, "type", true, &type);
    }
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
    tb_mass_mode mode = TB_MASS_GIVEN;
    double value = 0.0;
    status = mass_mode(ld, body, path, &mode, &value);
    tb_error error;
    tb__clear_error(&error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (strcmp(type, "box") == 0 || strcmp(type, "sphere") == 0) {
        status = load_box_sphere(ld, shape, shape_path, type, mode, value, b, &error);
    } else if (!strcmp(type, "cylinder") || !strcmp(type, "capsule") ||
               !strcmp(type, "ellipsoid")) {
        status = load_round(ld, shape, shape_path, type, mode, value, b, &error);
    } else if (strcmp(type, "mesh") == 0) {
        status = load_mesh(ld, shape, shape_path, mode, value, b, &error);
    } else {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, shape_path,
                             "type: must be one of box, sphere, cylinder, capsule, ellipsoid, "
                             "mesh, points, got \"%s\"",
                             type);
    }
    return error.message[0] ? mass_result(ld, status, path, &error) : status;
}

/* "mass" with "inertia": three principal moments or a full 3 x 3 tensor (kg m^2, shape frame,
 * about the centre of mass), and an optional "center" (shape frame). */
static tb_status load_inertia(tb__loader *ld, const json_t *body, const char *path, body_build *b)
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
        status = mass_result(ld, tb_mass_from_tensor(mass, center, I, &b->def.mass, &error), path,
                             &error);
    }
    return status;
}

/* "contact": false, or {"points": [{"position", "radius"}], "support": n}. */
static tb_status load_contact(tb__loader *ld, const json_t *body, const char *path, body_build *b)
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
    static const char *const keys[] = {"points", "support", NULL};
    tb_status status = tb__json_object(ld, contact, where, keys);
    const json_t *list = json_object_get(contact, "points");
    if (status == TB_STATUS_OK && (!json_is_array(list) || json_array_size(list) == 0)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                             "points: must be a non-empty array of {position, radius}");
    }
    const size_t n = status == TB_STATUS_OK ? json_array_size(list) : 0;
    free(b->contacts.many);
    b->contacts.many = malloc((n > 0 ? n : 1) * sizeof *b->contacts.many);
    if (b->contacts.many == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, where, "%zu contact points", n);
    }
    static const char *const point_keys[] = {"position", "radius", NULL};
    for (size_t k = 0; k < n && status == TB_STATUS_OK; ++k) {
        char item[176];
        tb__path_index(item, sizeof item, where, "points", k);
        tb_contact_point *p = &b->contacts.many[k];
        p->radius = 0.0;
        status = tb__json_object(ld, json_array_get(list, k), item, point_keys);
        if (status == TB_STATUS_OK) {
            status = tb__json_vector(ld, json_array_get(list, k), item, "position", 3, true,
                                     p->position);
        }
        if (status == TB_STATUS_OK) {
            status =
                tb__json_number(ld, json_array_get(list, k), item, "radius", false, &p->radius);
        }
        if (status == TB_STATUS_OK) {
            status = tb__check_non_negative_at(ld, item, "radius", p->radius);
        }
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

static tb_status add_body(tb__loader *ld, const char *path, body_build *b)
{
    size_t id;
    tb_status status = tb_scene_add_body(ld->scene, &b->def, &id);
    if (status != TB_STATUS_OK) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path, "%s", tb_scene_detail(ld->scene));
    }
    if (b->has_contacts) {
        const tb_contact_point *points = b->contacts.many ? b->contacts.many : b->contacts.points;
        status = tb_scene_set_contact_points(ld->scene, id, points, b->contacts.count,
                                             b->contacts.support);
    }
    return status == TB_STATUS_OK
               ? status
               : tb__load_fail(ld, status, path, "contact: %s", tb_scene_detail(ld->scene));
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
                                       NULL};
    body_build b;
    memset(&b, 0, sizeof b);
    b.def = tb_body_def_default();
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
    const bool shaped = json_object_get(body, "shape") != NULL;
    if (status == TB_STATUS_OK && shaped &&
        (json_object_get(body, "inertia") || json_object_get(body, "center"))) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                               "inertia and center come from the shape: give one or the other");
    }
    if (status == TB_STATUS_OK) {
        status = shaped ? load_shape(ld, body, path, &b) : load_inertia(ld, body, path, &b);
    }
    if (status == TB_STATUS_OK) {
        status = load_contact(ld, body, path, &b);
    }
    if (status == TB_STATUS_OK) {
        status = load_motion(ld, body, path, &b.def);
    }
    if (status == TB_STATUS_OK) {
        status = add_body(ld, path, &b);
    }
    free(b.contacts.many);
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

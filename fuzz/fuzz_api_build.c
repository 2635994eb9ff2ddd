/* The C-API fuzz target's building operations: mass properties from every constructor, bodies,
 * effects of every kind, contact points, state setters. Each call is traced as C and checked
 * by fuzz_check. */
#include "fuzz_api.h"

#include <stdlib.h>

/* A field keeps its default three times in four, else takes any double. */
static void maybe(fuzz_harness *h, double *field)
{
    if (fuzz_byte(h->in) < 64) {
        *field = fuzz_double(h->in);
    }
}

static void maybe_vector(fuzz_harness *h, double *field, size_t count)
{
    if (fuzz_byte(h->in) < 64) {
        fuzz_vector(h->in, field, count);
    }
}

static tb_mass_mode mass_mode(fuzz_harness *h)
{
    const uint8_t selector = fuzz_byte(h->in);
    return selector == 255 ? (tb_mass_mode)7 : (tb_mass_mode)(selector & 1);
}

static tb_status check_mass(fuzz_harness *h, tb_status status, const tb_error *error,
                            const tb_mass_properties *props, const char *call)
{
    fuzz_check(h, NULL, status, error->message, call, FUZZ_UNCHANGED);
    if (status == TB_STATUS_OK) {
        if (error->message[0] != '\0') {
            fuzz_fail(call, "TB_STATUS_OK with message \"%s\"", error->message);
        }
        tb_error validation;
        const tb_status valid = tb_mass_validate(props, &validation);
        if (valid != TB_STATUS_OK) {
            fuzz_fail(call, "returned OK with properties tb_mass_validate refuses: %s",
                      validation.message);
        }
    }
    return status;
}

static tb_status primitive(fuzz_harness *h, unsigned kind, tb_mass_properties *out)
{
    static const char *names[] = {"sphere", "box", "cylinder", "capsule", "ellipsoid"};
    const tb_mass_mode mode = mass_mode(h);
    const double value = fuzz_size(h->in);
    double size[3] = {fuzz_size(h->in), fuzz_size(h->in), fuzz_size(h->in)};
    tb_error error;
    tb_status status;
    char call[32];
    snprintf(call, sizeof call, "tb_mass_from_%s", names[kind]);
    fuzz_trace(h, "tb_mass_from_%s(%d, %s, %s, &props, &error);", names[kind], (int)mode,
               fuzz_c_double(value), fuzz_c_vector(size, 3));
    switch (kind) {
    case 0:
        status = tb_mass_from_sphere(mode, value, size[0], out, &error);
        break;
    case 1:
        status = tb_mass_from_box(mode, value, size, out, &error);
        break;
    case 2:
        status = tb_mass_from_cylinder(mode, value, size[0], size[1], out, &error);
        break;
    case 3:
        status = tb_mass_from_capsule(mode, value, size[0], size[1], out, &error);
        break;
    default:
        status = tb_mass_from_ellipsoid(mode, value, size, out, &error);
        break;
    }
    return check_mass(h, status, &error, out, call);
}

static tb_status points(fuzz_harness *h, tb_mass_properties *out)
{
    double positions[3 * 4], masses[4];
    const size_t count = fuzz_choice(h->in, 5);
    for (size_t i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k) {
            positions[3 * i + k] =
                fuzz_byte(h->in) < 192 ? (double)fuzz_choice(h->in, 5) - 2.0 : fuzz_double(h->in);
        }
        masses[i] = fuzz_size(h->in);
    }
    tb_error error;
    fuzz_trace(h, "tb_mass_from_points(%s, %s, %zu, &props, &error);",
               fuzz_c_vector(positions, 3 * count), fuzz_c_vector(masses, count), count);
    const tb_status status = tb_mass_from_points(positions, masses, count, out, &error);
    return check_mass(h, status, &error, out, "tb_mass_from_points");
}

/* A closed tetrahedron, scaled and moved, sometimes with a far unused vertex, a flipped face or
 * an index past the end. */
static tb_status mesh(fuzz_harness *h, tb_mass_properties *out)
{
    const double scale = fuzz_size(h->in);
    double offset[3] = {0, 0, 0};
    maybe_vector(h, offset, 3);
    double vertices[3 * 5] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1e5, 1e5, 1e5};
    unsigned triangles[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    for (int i = 0; i < 15; ++i) {
        vertices[i] = vertices[i] * scale + offset[i % 3];
    }
    const uint8_t damage = fuzz_byte(h->in);
    const size_t vertex_count = damage & 1 ? 5 : 4; /* 5: an unused vertex far away */
    if (damage & 2) {
        triangles[1] = 1, triangles[2] = 2; /* one face turned inside out */
    }
    if (damage & 4) {
        triangles[fuzz_choice(h->in, 12)] = (unsigned)fuzz_choice(h->in, 8);
    }
    if (damage & 8) {
        vertices[fuzz_choice(h->in, 12)] = fuzz_double(h->in);
    }
    const size_t triangle_count = damage & 16 ? fuzz_choice(h->in, 5) : 4;
    const tb_mass_mode mode = mass_mode(h);
    const double value = fuzz_size(h->in);
    tb_error error;
    fuzz_trace(h,
               "tb_mass_from_mesh(%d, %s, %s, %zu, (unsigned[]){%u,%u,%u, %u,%u,%u, %u,%u,%u, "
               "%u,%u,%u}, %zu, &props, &error);",
               (int)mode, fuzz_c_double(value), fuzz_c_vector(vertices, 3 * vertex_count),
               vertex_count, triangles[0], triangles[1], triangles[2], triangles[3], triangles[4],
               triangles[5], triangles[6], triangles[7], triangles[8], triangles[9], triangles[10],
               triangles[11], triangle_count);
    const tb_status status = tb_mass_from_mesh(mode, value, vertices, vertex_count, triangles,
                                               triangle_count, out, &error);
    return check_mass(h, status, &error, out, "tb_mass_from_mesh");
}

static tb_status tensor(fuzz_harness *h, tb_mass_properties *out)
{
    const double mass = fuzz_size(h->in);
    double center[3] = {0, 0, 0};
    maybe_vector(h, center, 3);
    double inertia[9] = {2, 0, 0, 0, 3, 0, 0, 0, 4};
    const uint8_t selector = fuzz_byte(h->in);
    if (selector & 1) { /* every entry scaled, e.g. subnormal */
        const double scale = fuzz_double(h->in);
        for (int i = 0; i < 9; ++i) {
            inertia[i] *= scale;
        }
    }
    if (selector & 2) { /* symmetric off-diagonal entries */
        inertia[1] = inertia[3] = fuzz_double(h->in);
        inertia[5] = inertia[7] = fuzz_double(h->in);
    }
    if (selector & 4) {
        inertia[fuzz_choice(h->in, 9)] = fuzz_double(h->in);
    }
    tb_error error;
    fuzz_trace(h, "tb_mass_from_tensor(%s, %s, %s, &props, &error);", fuzz_c_double(mass),
               fuzz_c_vector(center, 3), fuzz_c_vector(inertia, 9));
    const tb_status status = tb_mass_from_tensor(mass, center, inertia, out, &error);
    return check_mass(h, status, &error, out, "tb_mass_from_tensor");
}

static tb_status combine(fuzz_harness *h, tb_mass_properties *out)
{
    tb_mass_part parts[3];
    const size_t count = fuzz_choice(h->in, 4);
    for (size_t i = 0; i < count; ++i) {
        tb_error ignored;
        if (tb_mass_from_sphere(TB_MASS_GIVEN, 1.0 + (double)i, 0.5, &parts[i].props, &ignored) !=
            TB_STATUS_OK) {
            abort();
        }
        double position[3] = {(double)i, 0, 0}, orientation[4] = {1, 0, 0, 0};
        maybe_vector(h, position, 3);
        maybe_vector(h, orientation, 4);
        maybe(h, &parts[i].props.mass);
        memcpy(parts[i].position, position, sizeof position);
        memcpy(parts[i].orientation, orientation, sizeof orientation);
        fuzz_trace(h, "parts[%zu] = (tb_mass_part){sphere of %s kg radius 0.5, %s, %s};", i,
                   fuzz_c_double(parts[i].props.mass), fuzz_c_vector(position, 3),
                   fuzz_c_vector(orientation, 4));
    }
    tb_error error;
    fuzz_trace(h, "tb_mass_combine(parts, %zu, &props, &error);", count);
    const tb_status status = tb_mass_combine(parts, count, out, &error);
    return check_mass(h, status, &error, out, "tb_mass_combine");
}

tb_status fuzz_mass_properties(fuzz_harness *h, tb_mass_properties *out)
{
    memset(out, 0, sizeof *out);
    const unsigned kind = fuzz_choice(h->in, 10);
    if (kind < 5) {
        return primitive(h, kind, out);
    }
    switch (kind) {
    case 5:
        return points(h, out);
    case 6:
        return mesh(h, out);
    case 7:
        return tensor(h, out);
    case 8:
        return combine(h, out);
    default: /* raw numbers, to reach tb_scene_add_body's own checks */
        out->mass = fuzz_size(h->in);
        out->moments[0] = fuzz_size(h->in);
        out->moments[1] = out->moments[0];
        out->moments[2] = out->moments[0];
        maybe_vector(h, out->moments, 3);
        out->rotation[0] = 1;
        maybe_vector(h, out->rotation, 4);
        maybe_vector(h, out->center, 3);
        fuzz_trace(h, "props = (tb_mass_properties){%s, %s, %s, %s};", fuzz_c_double(out->mass),
                   fuzz_c_vector(out->center, 3), fuzz_c_vector(out->moments, 3),
                   fuzz_c_vector(out->rotation, 4));
        return TB_STATUS_OK;
    }
}

void fuzz_op_mass(fuzz_harness *h)
{
    tb_mass_properties props;
    fuzz_mass_properties(h, &props);
}

static const char *body_name(fuzz_harness *h)
{
    static const char *names[] = {"a",
                                  "b",
                                  "with,comma",
                                  "with\nnewline",
                                  "",
                                  ("a name that is longer than the sixty-three characters a "
                                   "body name may have"),
                                  "body0"};
    const uint8_t selector = fuzz_byte(h->in);
    return selector < 128 ? NULL : names[selector % 7];
}

/* The derivative's dx = P / M and dq = (0, omega) q / 2 of a body just added depend on nothing
 * but the body: they must be finite for a body the scene accepted. */
static void check_new_body_rates(fuzz_harness *h, size_t id)
{
    const size_t n = tb_scene_state_size(h->scene);
    double *dydt = calloc(n, sizeof(double));
    if (dydt == NULL) {
        abort();
    }
    if (tb_scene_derivative(0.0, tb_scene_states_const(h->scene), dydt, h->scene) == 0) {
        for (int i = TB_STATE_X; i < TB_STATE_P; ++i) {
            if (!isfinite(dydt[TB_STATE_SIZE * id + (size_t)i])) {
                fuzz_fail("tb_scene_add_body", "accepted body %zu whose d(x, q)/dt[%d] = %g", id, i,
                          dydt[TB_STATE_SIZE * id + (size_t)i]);
            }
        }
    }
    free(dydt);
}

void fuzz_op_add_body(fuzz_harness *h)
{
    tb_body_def def = tb_body_def_default();
    fuzz_mass_properties(h, &def.mass);
    def.name = body_name(h);
    maybe_vector(h, def.position, 3);
    maybe_vector(h, def.orientation, 4);
    maybe_vector(h, def.velocity, 3);
    maybe_vector(h, def.angular_velocity, 3);
    if (tb_scene_body_count(h->scene) >= FUZZ_MAX_BODIES) {
        return;
    }
    fuzz_trace(h,
               "def = tb_body_def_default(); def.mass = props; def.name = %s%s%s;\n"
               "def.position = %s; def.orientation = %s;\n"
               "def.velocity = %s; def.angular_velocity = %s;\n"
               "tb_scene_add_body(scene, &def, &id);",
               def.name ? "\"" : "", def.name ? def.name : "NULL", def.name ? "\"" : "",
               fuzz_c_vector(def.position, 3), fuzz_c_vector(def.orientation, 4),
               fuzz_c_vector(def.velocity, 3), fuzz_c_vector(def.angular_velocity, 3));
    fuzz_snapshot before;
    fuzz_snapshot_take(h, &before);
    size_t id = (size_t)-1;
    const tb_status status = tb_scene_add_body(h->scene, &def, &id);
    fuzz_check(h, &before, status, tb_scene_detail(h->scene), "tb_scene_add_body", FUZZ_UNCHANGED);
    if (status == TB_STATUS_OK) {
        if (id != before.bodies || tb_scene_body_count(h->scene) != before.bodies + 1) {
            fuzz_fail("tb_scene_add_body", "OK but id %zu, count %zu after %zu bodies", id,
                      tb_scene_body_count(h->scene), before.bodies);
        }
        check_new_body_rates(h, id);
    }
    fuzz_snapshot_free(&before);
}

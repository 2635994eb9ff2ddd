/* The C-API fuzz target's effects (every kind, user effects that fail, re-enter or add loads to
 * any id), contact points and state setters. */
#include "fuzz_api.h"

#include <stdlib.h>

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

static tb_frame frame_of(fuzz_harness *h)
{
    const uint8_t selector = fuzz_byte(h->in);
    return selector == 255 ? (tb_frame)9 : (tb_frame)(selector & 1);
}

/* A load refused only for what its header names: an id past the count, NaN or infinity. */
static void check_load(tb_status status, const tb_scene *scene, const char *call)
{
    if (status != TB_STATUS_OK && status != TB_STATUS_OUT_OF_RANGE &&
        status != TB_STATUS_NOT_FINITE) {
        fuzz_fail(call, "refused with %s", tb_status_name(status));
    }
    if (status != TB_STATUS_OK && tb_scene_detail(scene)[0] == '\0') {
        fuzz_fail(call, "refused with %s and an empty detail", tb_status_name(status));
    }
}

/* Called by the derivative. Only the loads and the re-entrant call are the fuzzer's choice; the
 * input is not read here (it is read in program order only). */
static int user_effect(double t, const tb_scene *scene, const double *y, double *dydt, void *ctx)
{
    fuzz_user_effect *user = ctx;
    fuzz_harness *h = user->harness;
    (void)t;
    switch (user->kind) {
    case FUZZ_USER_FORCE:
        check_load(tb_effect_add_force(scene, y, dydt, user->id, user->vector, user->point), scene,
                   "tb_effect_add_force");
        return 0;
    case FUZZ_USER_TORQUE:
        check_load(tb_effect_add_torque(scene, dydt, user->id, user->vector), scene,
                   "tb_effect_add_torque");
        return 0;
    case FUZZ_USER_FAIL:
        return user->result;
    case FUZZ_USER_REENTER:
        for (int i = 0; h->in_derivative && i < FUZZ_MAX_INTEGRATORS; ++i) {
            tb_integrator *other = h->integrators[i];
            if (other == NULL) {
                continue;
            }
            const tb_status status = tb_integrator_advance(other, tb_integrator_time(other) + 1);
            if (status != TB_STATUS_BUSY && status != TB_STATUS_LAYOUT_CHANGED) {
                fuzz_fail("tb_integrator_advance (from inside the derivative)",
                          "returned %s, not BUSY: a scene stepped by two calls at once",
                          tb_status_name(status));
            }
        }
        return 0;
    default: {
        double v[3], omega[3];
        tb_scene_body_velocity(scene, y, user->id, v);
        tb_scene_body_angular_velocity(scene, y, user->id, omega);
        return 0;
    }
    }
}

static tb_status add_user_effect(fuzz_harness *h)
{
    if (h->user_count >= FUZZ_MAX_USER_EFFECTS) {
        return TB_STATUS_OK;
    }
    fuzz_user_effect *user = &h->users[h->user_count];
    user->harness = h;
    user->kind = (fuzz_user_kind)fuzz_choice(h->in, FUZZ_USER_KIND_COUNT);
    user->id = fuzz_body_id(h);
    fuzz_vector(h->in, user->vector, 3);
    fuzz_vector(h->in, user->point, 3);
    user->result = fuzz_byte(h->in) & 1 ? 1 : -1;
    fuzz_trace(h,
               "user[%zu] = {kind %d, id %s, vector %s, point %s, result %d};\n"
               "tb_scene_add_user_effect(scene, user_effect, &user[%zu]);",
               h->user_count, (int)user->kind, fuzz_c_id(user->id), fuzz_c_vector(user->vector, 3),
               fuzz_c_vector(user->point, 3), user->result, h->user_count);
    const tb_status status = tb_scene_add_user_effect(h->scene, user_effect, user);
    if (status == TB_STATUS_OK) {
        ++h->user_count;
    }
    return status;
}

static tb_status add_drag(fuzz_harness *h)
{
    tb_drag_def def = tb_drag_def_default();
    if (fuzz_byte(h->in) & 1) {
        def.body = fuzz_body_id(h);
    }
    maybe(h, &def.linear);
    maybe(h, &def.quadratic);
    maybe(h, &def.angular);
    maybe(h, &def.angular_quadratic);
    fuzz_trace(h,
               "drag = tb_drag_def_default(); drag.body = %s; drag.linear = %s; "
               "drag.quadratic = %s; drag.angular = %s; drag.angular_quadratic = %s;\n"
               "tb_scene_add_drag(scene, &drag);",
               fuzz_c_id(def.body), fuzz_c_double(def.linear), fuzz_c_double(def.quadratic),
               fuzz_c_double(def.angular), fuzz_c_double(def.angular_quadratic));
    return tb_scene_add_drag(h->scene, &def);
}

static tb_status add_spring(fuzz_harness *h)
{
    tb_spring_def def = tb_spring_def_default();
    def.body_a = fuzz_body_id(h);
    def.body_b = fuzz_byte(h->in) & 1 ? TB_WORLD : fuzz_body_id(h);
    maybe_vector(h, def.point_a, 3);
    maybe_vector(h, def.point_b, 3);
    def.stiffness = fuzz_size(h->in);
    maybe(h, &def.damping);
    maybe(h, &def.rest_length);
    fuzz_trace(h,
               "spring = tb_spring_def_default(); spring.body_a = %s; spring.body_b = %s;\n"
               "spring.point_a = %s; spring.point_b = %s;\n"
               "spring.stiffness = %s; spring.damping = %s; spring.rest_length = %s;\n"
               "tb_scene_add_spring(scene, &spring);",
               fuzz_c_id(def.body_a), fuzz_c_id(def.body_b), fuzz_c_vector(def.point_a, 3),
               fuzz_c_vector(def.point_b, 3), fuzz_c_double(def.stiffness),
               fuzz_c_double(def.damping), fuzz_c_double(def.rest_length));
    return tb_scene_add_spring(h->scene, &def);
}

static tb_status add_ground(fuzz_harness *h)
{
    tb_ground_def def = tb_ground_def_default();
    maybe_vector(h, def.normal, 3);
    maybe(h, &def.offset);
    maybe(h, &def.gravity);
    maybe(h, &def.penetration);
    maybe(h, &def.restitution);
    maybe(h, &def.static_friction);
    maybe(h, &def.kinetic_friction);
    maybe(h, &def.stribeck_velocity);
    maybe(h, &def.presliding);
    fuzz_trace(h,
               "ground = tb_ground_def_default(); ground.normal = %s; ground.offset = %s;\n"
               "ground.gravity = %s; ground.penetration = %s; ground.restitution = %s;\n"
               "ground.static_friction = %s; ground.kinetic_friction = %s;\n"
               "ground.stribeck_velocity = %s; ground.presliding = %s;\n"
               "tb_scene_add_ground(scene, &ground);",
               fuzz_c_vector(def.normal, 3), fuzz_c_double(def.offset), fuzz_c_double(def.gravity),
               fuzz_c_double(def.penetration), fuzz_c_double(def.restitution),
               fuzz_c_double(def.static_friction), fuzz_c_double(def.kinetic_friction),
               fuzz_c_double(def.stribeck_velocity), fuzz_c_double(def.presliding));
    return tb_scene_add_ground(h->scene, &def);
}

static tb_status add_load(fuzz_harness *h, unsigned kind)
{
    double vector[3] = {0, 0, -9.81}, point[3] = {0, 0, 0};
    maybe_vector(h, vector, 3);
    if (kind == 0) {
        fuzz_trace(h, "tb_scene_add_gravity(scene, %s);", fuzz_c_vector(vector, 3));
        return tb_scene_add_gravity(h->scene, vector);
    }
    const size_t id = fuzz_body_id(h);
    const tb_frame frame = frame_of(h);
    if (kind == 1) {
        maybe_vector(h, point, 3);
        fuzz_trace(h, "tb_scene_add_force(scene, %s, %s, %s, %d);", fuzz_c_id(id),
                   fuzz_c_vector(vector, 3), fuzz_c_vector(point, 3), (int)frame);
        return tb_scene_add_force(h->scene, id, vector, point, frame);
    }
    fuzz_trace(h, "tb_scene_add_torque(scene, %s, %s, %d);", fuzz_c_id(id),
               fuzz_c_vector(vector, 3), (int)frame);
    return tb_scene_add_torque(h->scene, id, vector, frame);
}

void fuzz_op_add_effect(fuzz_harness *h)
{
    const unsigned kind = fuzz_choice(h->in, 7);
    fuzz_snapshot before;
    fuzz_snapshot_take(h, &before);
    static const char *calls[] = {"tb_scene_add_gravity",    "tb_scene_add_force",
                                  "tb_scene_add_torque",     "tb_scene_add_drag",
                                  "tb_scene_add_spring",     "tb_scene_add_ground",
                                  "tb_scene_add_user_effect"};
    tb_status status;
    switch (kind) {
    case 0:
    case 1:
    case 2:
        status = add_load(h, kind);
        break;
    case 3:
        status = add_drag(h);
        break;
    case 4:
        status = add_spring(h);
        break;
    case 5:
        status = add_ground(h);
        break;
    default:
        status = add_user_effect(h);
        break;
    }
    fuzz_check(h, &before, status, tb_scene_detail(h->scene), calls[kind], FUZZ_UNCHANGED);
    if (status == TB_STATUS_OK && kind != 6 &&
        tb_scene_effect_count(h->scene) != before.effects + 1) {
        fuzz_fail(calls[kind], "OK but the effect count went %zu -> %zu", before.effects,
                  tb_scene_effect_count(h->scene));
    }
    fuzz_snapshot_free(&before);
}

/* Contact points given one by one, or from the box, sphere and capsule generators. */
static size_t contact_points(fuzz_harness *h, tb_contact_point *points, size_t room)
{
    const unsigned source = fuzz_choice(h->in, 4);
    size_t count = 0;
    if (source == 0) {
        count = fuzz_choice(h->in, (unsigned)room + 1);
        for (size_t i = 0; i < count; ++i) {
            fuzz_vector(h->in, points[i].position, 3);
            points[i].radius = fuzz_byte(h->in) & 1 ? 0.0 : fuzz_double(h->in);
        }
        return count;
    }
    double size[3] = {fuzz_size(h->in), fuzz_size(h->in), fuzz_size(h->in)};
    const size_t capacity = fuzz_choice(h->in, (unsigned)room + 1);
    tb_status status;
    static const char *names[] = {"", "box", "sphere", "capsule"};
    fuzz_trace(h, "tb_contact_points_%s(%s, points, %zu, &count);", names[source],
               fuzz_c_vector(size, 3), capacity);
    if (source == 1) {
        status = tb_contact_points_box(size, points, capacity, &count);
    } else if (source == 2) {
        status = tb_contact_points_sphere(size[0], points, capacity, &count);
    } else {
        status = tb_contact_points_capsule(size[0], size[1], points, capacity, &count);
    }
    fuzz_check(h, NULL, status, NULL, "tb_contact_points_*", FUZZ_UNCHANGED);
    if (status == TB_STATUS_OK && count > capacity) {
        fuzz_fail("tb_contact_points_*", "wrote %zu points into room for %zu", count, capacity);
    }
    return status == TB_STATUS_OK ? count : 0;
}

void fuzz_op_contact_points(fuzz_harness *h)
{
    tb_contact_point points[8];
    const size_t count = contact_points(h, points, 8);
    const size_t id = fuzz_body_id(h);
    const size_t support = fuzz_choice(h->in, (unsigned)count + 2);
    fuzz_trace(h, "tb_scene_set_contact_points(scene, %s, points, %zu, %zu);", fuzz_c_id(id), count,
               support);
    fuzz_snapshot before;
    fuzz_snapshot_take(h, &before);
    const tb_status status = tb_scene_set_contact_points(h->scene, id, points, count, support);
    fuzz_check(h, &before, status, tb_scene_detail(h->scene), "tb_scene_set_contact_points",
               FUZZ_UNCHANGED);
    fuzz_snapshot_free(&before);
}

static tb_status set_state(fuzz_harness *h, size_t id)
{
    tb_body_state state = {{0, 0, 0}, {1, 0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    tb_scene_get_state(h->scene, id, &state);
    maybe_vector(h, state.x, 3);
    if (fuzz_byte(h->in) < 64) { /* off the unit sphere by a chosen amount */
        const double stretch = 1.0 + fuzz_double(h->in);
        for (int i = 0; i < 4; ++i) {
            state.q[i] *= stretch;
        }
    }
    maybe_vector(h, state.q, 4);
    maybe_vector(h, state.P, 3);
    maybe_vector(h, state.L, 3);
    fuzz_trace(h,
               "state = (tb_body_state){%s, %s, %s, %s};\n"
               "tb_scene_set_state(scene, %s, &state);",
               fuzz_c_vector(state.x, 3), fuzz_c_vector(state.q, 4), fuzz_c_vector(state.P, 3),
               fuzz_c_vector(state.L, 3), fuzz_c_id(id));
    return tb_scene_set_state(h->scene, id, &state);
}

void fuzz_op_set_state(fuzz_harness *h)
{
    const size_t id = fuzz_body_id(h);
    const unsigned kind = fuzz_choice(h->in, 3);
    if (kind == 2) {
        const bool on = fuzz_byte(h->in) & 1;
        fuzz_trace(h, "tb_scene_set_renormalize(scene, %d);", on);
        tb_scene_set_renormalize(h->scene, on);
        return;
    }
    fuzz_snapshot before;
    fuzz_snapshot_take(h, &before);
    tb_status status;
    if (kind == 0) {
        status = set_state(h, id);
    } else {
        double velocity[3], angular_velocity[3];
        fuzz_vector(h->in, velocity, 3);
        fuzz_vector(h->in, angular_velocity, 3);
        fuzz_trace(h, "tb_scene_set_velocity(scene, %s, %s, %s);", fuzz_c_id(id),
                   fuzz_c_vector(velocity, 3), fuzz_c_vector(angular_velocity, 3));
        status = tb_scene_set_velocity(h->scene, id, velocity, angular_velocity);
    }
    fuzz_check(h, &before, status, tb_scene_detail(h->scene),
               kind == 0 ? "tb_scene_set_state" : "tb_scene_set_velocity", FUZZ_UNCHANGED);
    fuzz_snapshot_free(&before);
}

/* libFuzzer target: contact between bodies through the public C API. The input (fuzz_input.h)
 * is a program on one scene of at most FUZZ_BODIES bodies: add bodies (any mass, position and
 * velocity: often at the same spot or inside each other), give them collision shapes of every
 * type (sizes at the ends of the range, hulls of 0 to 8 points that are often coplanar or
 * repeated), add contact effects (any parameters, body lists with bad or repeated ids, counts
 * near the wrap of size_t), ground planes and gravity, move bodies onto each other (also between
 * steps), make integrators of every method and advance them a bounded time, or step a
 * fixed-step method one step at a time. After every call:
 *   - the status is OK or an error with a detail;
 *   - a refused call changed nothing (state bit-identical, same body and effect counts);
 *   - after OK the state is finite; a failed step left a finite state;
 *   - with only contact effects in the scene, a fixed step keeps the total linear momentum to
 *     round-off (the forces on a pair are equal and opposite at the same point).
 * A violation aborts, so libFuzzer keeps the input. TUMBLE_FUZZ_TRACE=1 prints every call. */
#include "fuzz_input.h"

#include "tumble/tumble.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_BODIES 6
#define FUZZ_OPERATIONS 24
#define FUZZ_STEPS 300       /* max_steps of every integrator */
#define FUZZ_SINGLE_STEPS 40 /* steps of one step-by-step operation */

typedef struct harness {
    fuzz_input *in;
    tb_scene *scene;
    int trace;
    int only_contact; /* every effect of the scene is a contact effect */
    double vertices[3 * 8], radii[8];
} harness;

static void fail(const char *call, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3), noreturn))
#endif
    ;

static void fail(const char *call, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    fprintf(stderr, "fuzz_contact: invariant broken after %s: ", call);
    vfprintf(stderr, format, args);
    fputc('\n', stderr);
    va_end(args);
    abort();
}

static void trace(const harness *h, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void trace(const harness *h, const char *format, ...)
{
    if (h->trace) {
        va_list args;
        va_start(args, format);
        vfprintf(stderr, format, args);
        fputc('\n', stderr);
        va_end(args);
    }
}

typedef struct snapshot {
    /* bodies, ground friction states, and the friction slots of contact effects (at most one
     * per pair of bodies, 6 slots of 3 doubles per body of an effect by default) */
    double y[13 * FUZZ_BODIES + 2 * 64 * 4 + FUZZ_BODIES * FUZZ_BODIES * 6 * 3 * 6];
    size_t size, bodies, effects;
} snapshot;

static void take(const harness *h, snapshot *s)
{
    s->size = tb_scene_state_size(h->scene);
    s->bodies = tb_scene_body_count(h->scene);
    s->effects = tb_scene_effect_count(h->scene);
    if (s->size > sizeof s->y / sizeof s->y[0]) {
        abort(); /* the harness's bounds keep the state small */
    }
    memcpy(s->y, tb_scene_states_const(h->scene), s->size * sizeof(double));
}

static void check_finite(const harness *h, const char *call, const char *when)
{
    const double *y = tb_scene_states_const(h->scene);
    for (size_t i = 0; i < tb_scene_state_size(h->scene); ++i) {
        if (!isfinite(y[i])) {
            fail(call, "state[%zu] = %g is not finite %s", i, y[i], when);
        }
    }
}

/* The contract after a call; a failed step may leave the last good state (stepped), any other
 * failure must leave everything as it was. */
static void check(const harness *h, const snapshot *before, tb_status status, const char *detail,
                  const char *call, int stepped)
{
    trace(h, "    -> %s%s%s", tb_status_name(status), detail != NULL ? ": " : "",
          detail != NULL ? detail : "");
    if (status > 0 || strcmp(tb_status_name(status), "UNKNOWN") == 0) {
        fail(call, "returned %d, not a tb_status", (int)status);
    }
    if (status == TB_STATUS_OK) {
        check_finite(h, call, "after TB_STATUS_OK");
        return;
    }
    if (detail != NULL && detail[0] == '\0') {
        fail(call, "returned %s with an empty detail", tb_status_name(status));
    }
    if (stepped) {
        check_finite(h, call, "after a failed step");
        return;
    }
    snapshot after;
    take(h, &after);
    if (after.size != before->size || after.bodies != before->bodies ||
        after.effects != before->effects ||
        memcmp(after.y, before->y, after.size * sizeof(double)) != 0) {
        fail(call, "refused (%s) but the scene changed", tb_status_name(status));
    }
}

/* A coordinate: mostly on a coarse grid (so bodies coincide and hull points repeat), sometimes
 * any double. */
static double coordinate(harness *h)
{
    const uint8_t selector = fuzz_byte(h->in);
    return selector < 200 ? (double)(selector % 9) * 0.05 - 0.2 : fuzz_double(h->in);
}

static size_t body_id(harness *h)
{
    const size_t count = tb_scene_body_count(h->scene);
    const uint8_t selector = fuzz_byte(h->in);
    return selector < 240 || count == 0 ? (count > 0 ? selector % count : 0)
                                        : (selector & 1 ? count : (size_t)-1);
}

static void add_body(harness *h)
{
    if (tb_scene_body_count(h->scene) >= FUZZ_BODIES) {
        return;
    }
    tb_body_def def = tb_body_def_default();
    const double mass = fuzz_size(h->in), radius = fuzz_size(h->in);
    tb_error error;
    if (tb_mass_from_sphere(TB_MASS_GIVEN, mass, radius, &def.mass, &error) != TB_STATUS_OK) {
        return;
    }
    for (int k = 0; k < 3; ++k) {
        def.position[k] = coordinate(h);
        def.velocity[k] = fuzz_byte(h->in) < 200 ? coordinate(h) * 10.0 : fuzz_double(h->in);
        def.angular_velocity[k] = fuzz_byte(h->in) < 220 ? coordinate(h) : fuzz_double(h->in);
    }
    snapshot before;
    take(h, &before);
    trace(h, "add_body(mass %a, radius %a, x (%a, %a, %a), v (%a, %a, %a), w (%a, %a, %a))", mass,
          radius, def.position[0], def.position[1], def.position[2], def.velocity[0],
          def.velocity[1], def.velocity[2], def.angular_velocity[0], def.angular_velocity[1],
          def.angular_velocity[2]);
    const tb_status status = tb_scene_add_body(h->scene, &def, NULL);
    check(h, &before, status, tb_scene_detail(h->scene), "tb_scene_add_body", 0);
}

/* Hull or point-set vertices: 0 to 8, on the grid (often coplanar or repeated) or anywhere. */
static size_t vertices(harness *h, int with_radii)
{
    const size_t count = fuzz_choice(h->in, 9);
    const double scale = fuzz_byte(h->in) < 200 ? 1.0 : fuzz_double(h->in);
    for (size_t i = 0; i < 3 * count; ++i) {
        h->vertices[i] = coordinate(h) * scale;
    }
    for (size_t i = 0; with_radii && i < count; ++i) {
        h->radii[i] = fuzz_byte(h->in) < 128 ? 0.0 : fuzz_size(h->in);
    }
    return count;
}

static void set_shape(harness *h)
{
    tb_shape shape = tb_shape_default();
    const uint8_t type = fuzz_byte(h->in);
    shape.type = type < 252 ? (tb_shape_type)(type % 8) : (tb_shape_type)(type - 240);
    shape.radius = fuzz_size(h->in) * 0.1;
    shape.length = fuzz_size(h->in) * 0.1;
    for (int k = 0; k < 3; ++k) {
        shape.size[k] = fuzz_size(h->in) * 0.1;
        shape.semi_axes[k] = fuzz_size(h->in) * 0.1;
    }
    if (shape.type == TB_SHAPE_CONVEX || shape.type == TB_SHAPE_POINTS) {
        shape.vertex_count = vertices(h, shape.type == TB_SHAPE_POINTS && fuzz_byte(h->in) & 1);
        shape.vertices = fuzz_byte(h->in) < 250 ? h->vertices : NULL;
        shape.radii = shape.type == TB_SHAPE_POINTS && fuzz_byte(h->in) & 1 ? h->radii : NULL;
    }
    const size_t id = body_id(h);
    snapshot before;
    take(h, &before);
    trace(h,
          "set_body_shape(%zu, type %d, radius %a, length %a, size (%a, %a, %a), semi_axes (%a, "
          "%a, %a), %zu vertices)",
          id, (int)shape.type, shape.radius, shape.length, shape.size[0], shape.size[1],
          shape.size[2], shape.semi_axes[0], shape.semi_axes[1], shape.semi_axes[2],
          shape.vertex_count);
    for (size_t i = 0; shape.vertices != NULL && i < shape.vertex_count; ++i) {
        trace(h, "    vertex (%a, %a, %a) radius %a", shape.vertices[3 * i],
              shape.vertices[3 * i + 1], shape.vertices[3 * i + 2],
              shape.radii != NULL ? shape.radii[i] : 0.0);
    }
    const tb_status status = tb_scene_set_body_shape(h->scene, id, &shape);
    check(h, &before, status, tb_scene_detail(h->scene), "tb_scene_set_body_shape", 0);
}

static void maybe(harness *h, double *field)
{
    if (fuzz_byte(h->in) < 48) {
        *field = fuzz_double(h->in);
    }
}

static void add_contact(harness *h)
{
    tb_contact_def def = tb_contact_def_default();
    maybe(h, &def.restitution);
    maybe(h, &def.static_friction);
    maybe(h, &def.kinetic_friction);
    maybe(h, &def.penetration);
    maybe(h, &def.gravity);
    maybe(h, &def.stribeck_velocity);
    size_t ids[FUZZ_BODIES + 2];
    const uint8_t listed = fuzz_byte(h->in);
    if (listed & 1) {
        def.body_count = fuzz_choice(h->in, FUZZ_BODIES + 3);
        for (size_t k = 0; k < def.body_count; ++k) {
            ids[k] = body_id(h);
        }
        def.bodies = listed & 2 ? NULL : ids;
        if ((listed & 0x0c) == 0x0c && def.bodies != NULL) {
            /* a count near the wrap of its byte size (issue 19: 2^61 + 1 ids wrapped to 8
             * bytes): ids holds FUZZ_BODIES + 2, so the library must refuse before reading on */
            def.body_count = ((size_t)-1) / sizeof(size_t) - 3 + fuzz_choice(h->in, 8);
        }
    }
    snapshot before;
    take(h, &before);
    trace(h,
          "add_contact(e %a, mu_s %a, mu_k %a, penetration %a, gravity %a, stribeck %a, %zu "
          "bodies%s)",
          def.restitution, def.static_friction, def.kinetic_friction, def.penetration, def.gravity,
          def.stribeck_velocity, def.body_count, def.bodies == NULL ? " (NULL)" : "");
    for (size_t k = 0; def.bodies != NULL && k < def.body_count && k < FUZZ_BODIES + 2; ++k) {
        trace(h, "    body %zu", ids[k]);
    }
    const tb_status status = tb_scene_add_contact(h->scene, &def);
    check(h, &before, status, tb_scene_detail(h->scene), "tb_scene_add_contact", 0);
}

static void add_other_effect(harness *h)
{
    snapshot before;
    take(h, &before);
    tb_status status;
    if (fuzz_byte(h->in) & 1) {
        trace(h, "add_gravity(0, 0, -9.81)");
        status = tb_scene_add_gravity(h->scene, (const double[]){0, 0, -9.81});
    } else {
        tb_ground_def ground = tb_ground_def_default();
        ground.offset = coordinate(h);
        trace(h, "add_ground(offset %a)", ground.offset);
        status = tb_scene_add_ground(h->scene, &ground);
    }
    h->only_contact &= status != TB_STATUS_OK;
    check(h, &before, status, tb_scene_detail(h->scene), "tb_scene_add_<effect>", 0);
}

/* Moves a body onto another (the same position, or a small offset), or anywhere. */
static void move_body(harness *h)
{
    const size_t id = body_id(h), onto = body_id(h);
    tb_body_state state;
    if (tb_scene_get_state(h->scene, onto, &state) != TB_STATUS_OK) {
        return;
    }
    const uint8_t how = fuzz_byte(h->in);
    for (int k = 0; k < 3 && how & 1; ++k) {
        state.x[k] += how & 2 ? fuzz_double(h->in) : coordinate(h) * 0.01;
    }
    snapshot before;
    take(h, &before);
    trace(h, "set_state(%zu, x of %zu + (%a, %a, %a))", id, onto, state.x[0], state.x[1],
          state.x[2]);
    const tb_status status = tb_scene_set_state(h->scene, id, &state);
    check(h, &before, status, tb_scene_detail(h->scene), "tb_scene_set_state", 0);
}

static tb_integrator *make_integrator(harness *h, tb_method method)
{
    tb_integrator_def def = tb_integrator_def_default();
    if (tb_integrator_def_set_method(&def, method) != TB_STATUS_OK) {
        abort();
    }
    def.max_steps = FUZZ_STEPS;
    if (!tb_method_is_adaptive(method)) {
        def.dt = fuzz_byte(h->in) < 200 ? 0.0 : fuzz_double(h->in); /* 0: the default step */
    } else if (fuzz_byte(h->in) >= 200) {
        def.rtol = fuzz_double(h->in);
    }
    snapshot before;
    take(h, &before);
    trace(h, "integrator(%s, dt %a, rtol %a)", tb_method_name(method), def.dt, def.rtol);
    tb_integrator *integrator = NULL;
    const tb_status status = tb_scene_integrator_create(h->scene, &def, 0.0, &integrator);
    check(h, &before, status, tb_scene_detail(h->scene), "tb_scene_integrator_create", 0);
    if ((status == TB_STATUS_OK) != (integrator != NULL)) {
        fail("tb_scene_integrator_create", "status %s with integrator %p", tb_status_name(status),
             (void *)integrator);
    }
    return integrator;
}

static void advance(harness *h)
{
    const tb_method method = (tb_method)fuzz_choice(h->in, 5);
    tb_integrator *integrator = make_integrator(h, method);
    if (integrator == NULL) {
        return;
    }
    const double t =
        fuzz_byte(h->in) < 220 ? 0.001 * (1 + fuzz_choice(h->in, 20)) : fuzz_double(h->in);
    snapshot before;
    take(h, &before);
    trace(h, "advance(%a)", t);
    const tb_status status = tb_integrator_advance(integrator, t);
    check(h, &before, status, tb_integrator_detail(integrator), "tb_integrator_advance", 1);
    tb_integrator_destroy(integrator);
}

static void momentum(const harness *h, double P[3], double *sum)
{
    *sum = 0.0;
    P[0] = P[1] = P[2] = 0.0;
    for (size_t i = 0; i < tb_scene_body_count(h->scene); ++i) {
        tb_body_state s;
        tb_scene_get_state(h->scene, i, &s);
        for (int k = 0; k < 3; ++k) {
            P[k] += s.P[k];
            *sum += fabs(s.P[k]);
        }
    }
}

/* A fixed-step method one step at a time; with only contact effects, each step keeps the total
 * linear momentum: the loads on a pair sum to zero exactly, so only the rounding of each body's
 * own sums is left, a few ulps of the momenta involved (64 ulps of their sum allowed, against
 * an error of order the momentum change itself if a load lost its opposite). */
static void single_steps(harness *h)
{
    const tb_method method = (tb_method)fuzz_choice(h->in, 3);
    tb_integrator *integrator = make_integrator(h, method);
    for (int step = 0; integrator != NULL && step < FUZZ_SINGLE_STEPS; ++step) {
        if (fuzz_byte(h->in) < 24) {
            move_body(h); /* a state change between steps: checked as a start (F26) */
        }
        double P0[3], P1[3], sum0, sum1;
        momentum(h, P0, &sum0);
        snapshot before;
        take(h, &before);
        trace(h, "step()");
        const tb_status status = tb_integrator_step(integrator);
        check(h, &before, status, tb_integrator_detail(integrator), "tb_integrator_step", 1);
        if (status != TB_STATUS_OK) {
            break;
        }
        momentum(h, P1, &sum1);
        double change = 0.0;
        for (size_t i = 0; i < 13 * tb_scene_body_count(h->scene); i += 13) {
            for (int k = 7; k < 10; ++k) { /* P's place in the body state */
                change += fabs(tb_scene_states_const(h->scene)[i + k] - before.y[i + k]);
            }
        }
        for (int k = 0; k < 3 && h->only_contact; ++k) {
            if (fabs(P1[k] - P0[k]) > 64.0 * DBL_EPSILON * (sum0 + sum1 + change)) {
                fail("tb_integrator_step", "total P[%d] %.17g -> %.17g with only contact", k, P0[k],
                     P1[k]);
            }
        }
    }
    tb_integrator_destroy(integrator);
}

static void read_out(harness *h)
{
    const size_t id = body_id(h);
    double low[3], high[3];
    tb_shape_type type;
    const tb_status status =
        tb_scene_body_shape_bounds(h->scene, tb_scene_states_const(h->scene), id, low, high);
    if (status == TB_STATUS_OK) {
        for (int k = 0; k < 3; ++k) {
            if (!(low[k] <= high[k])) {
                fail("tb_scene_body_shape_bounds", "body %zu: bounds [%g, %g] on axis %d", id,
                     low[k], high[k], k);
            }
        }
    }
    if (tb_scene_body_shape_type(h->scene, id, &type) == TB_STATUS_OK &&
        (status == TB_STATUS_OK) != (type != TB_SHAPE_NONE)) {
        fail("tb_scene_body_shape_bounds", "body %zu: bounds %s for shape type %d", id,
             tb_status_name(status), (int)type);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = {data, size, 0};
    harness h = {.in = &in, .only_contact = 1};
    const char *trace_env = getenv("TUMBLE_FUZZ_TRACE");
    h.trace = trace_env != NULL && trace_env[0] == '1';
    tb_scene_def def = tb_scene_def_default();
    if (tb_scene_create(&def, &h.scene, NULL) != TB_STATUS_OK) {
        abort();
    }
    for (int op = 0; op < FUZZ_OPERATIONS && !fuzz_exhausted(&in); ++op) {
        switch (fuzz_choice(&in, 9)) {
        case 0:
        case 1:
            add_body(&h);
            break;
        case 2:
        case 3:
            set_shape(&h);
            break;
        case 4:
            add_contact(&h);
            break;
        case 5:
            fuzz_byte(&in) < 64 ? add_other_effect(&h) : move_body(&h);
            break;
        case 6:
            advance(&h);
            break;
        case 7:
            single_steps(&h);
            break;
        default:
            read_out(&h);
            break;
        }
    }
    tb_scene_destroy(h.scene);
    return 0;
}

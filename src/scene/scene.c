/* The scene object: creation, bodies, states. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "mass/mass_internal.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TB__SCENE_COOKIE 0x5ce2e
#define TB__BODY_COOKIE 0xb0d1e5

_Static_assert(sizeof(tb_body_state) == TB_STATE_SIZE * sizeof(double),
               "tb_body_state must be 13 doubles with no padding");
_Static_assert(offsetof(tb_body_state, q) == 3 * sizeof(double), "q follows x");
_Static_assert(offsetof(tb_body_state, P) == 7 * sizeof(double), "P follows q");
_Static_assert(offsetof(tb_body_state, L) == 10 * sizeof(double), "L follows P");

tb_scene_def tb_scene_def_default(void)
{
    tb_scene_def def;
    memset(&def, 0, sizeof def);
    def.body_capacity = 16;
    def.effect_capacity = 8;
    def.renormalize_quaternions = true;
    def.internal_cookie = TB__SCENE_COOKIE;
    return def;
}

tb_body_def tb_body_def_default(void)
{
    tb_body_def def;
    memset(&def, 0, sizeof def);
    def.mass.rotation[0] = 1.0;
    def.orientation[0] = 1.0;
    def.internal_cookie = TB__BODY_COOKIE;
    return def;
}

tb_status tb__scene_fail(tb_scene *scene, tb_status status, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    tb__vformat_detail(scene->detail, status, format, args);
    va_end(args);
    return status;
}

tb_status tb__scene_check_id(const tb_scene *scene, size_t id, const char *what)
{
    if (id >= scene->body_count) {
        /* The detail is the one mutable part of a scene read through a const pointer. */
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_OUT_OF_RANGE,
                              "%s: body id %zu out of range (%zu bodies)", what, id,
                              scene->body_count);
    }
    return TB_STATUS_OK;
}

/* Grows the body arrays to hold at least capacity bodies; nothing is lost on failure. */
static tb_status reserve_bodies(tb_scene *scene, size_t capacity)
{
    if (capacity <= scene->body_capacity) {
        return TB_STATUS_OK;
    }
    if (capacity > SIZE_MAX / (TB_STATE_SIZE * sizeof(double) + sizeof(tb_mass_properties))) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "%zu bodies", capacity);
    }
    tb__body *bodies = realloc(scene->bodies, capacity * sizeof(tb__body));
    if (bodies != NULL) {
        scene->bodies = bodies;
    }
    tb_mass_properties *props = realloc(scene->mass_props, capacity * sizeof(tb_mass_properties));
    if (props != NULL) {
        scene->mass_props = props;
    }
    char(*names)[TB_NAME_SIZE] = realloc(scene->names, capacity * sizeof *names);
    if (names != NULL) {
        scene->names = names;
    }
    if (bodies == NULL || props == NULL || names == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "room for %zu bodies", capacity);
    }
    scene->body_capacity = capacity;
    return TB_STATUS_OK;
}

/* Grows the state array to hold at least size doubles; nothing is lost on failure. */
static tb_status reserve_states(tb_scene *scene, size_t size)
{
    if (size <= scene->state_capacity) {
        return TB_STATUS_OK;
    }
    const size_t capacity = size > 2 * scene->state_capacity ? size : 2 * scene->state_capacity;
    double *states = realloc(scene->states, capacity * sizeof(double));
    if (states == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "state array of %zu doubles",
                              capacity);
    }
    scene->states = states;
    scene->state_capacity = capacity;
    return TB_STATUS_OK;
}

tb_status tb__scene_layout_states(tb_scene *scene, size_t body_count)
{
    size_t extra = 0;
    for (size_t e = 0; e < scene->effect_count; ++e) {
        extra += scene->effects[e].states_per_contact * scene->contact_count;
    }
    tb_status status = reserve_states(scene, TB_STATE_SIZE * body_count + extra);
    if (status != TB_STATUS_OK) {
        return status;
    }
    size_t offset = TB_STATE_SIZE * body_count;
    for (size_t e = 0; e < scene->effect_count; ++e) {
        scene->effects[e].state_offset = offset;
        offset += scene->effects[e].states_per_contact * scene->contact_count;
    }
    memset(scene->states + TB_STATE_SIZE * body_count, 0, extra * sizeof(double));
    scene->extra_count = extra;
    return TB_STATUS_OK;
}

size_t tb_scene_state_size(const tb_scene *scene)
{
    return scene == NULL ? 0 : TB_STATE_SIZE * scene->body_count + scene->extra_count;
}

tb_status tb_scene_create(const tb_scene_def *def, tb_scene **out_scene, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (def == NULL || out_scene == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             def == NULL ? "def" : "out_scene");
    }
    *out_scene = NULL;
    if (def->internal_cookie != TB__SCENE_COOKIE) {
        return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT,
                             "def: not initialised by tb_scene_def_default()");
    }
    tb_scene *scene = calloc(1, sizeof *scene);
    if (scene == NULL) {
        return tb__set_error(out_error, TB_STATUS_OUT_OF_MEMORY, "scene");
    }
    scene->renormalize = def->renormalize_quaternions;
    const size_t capacity = def->body_capacity > 0 ? def->body_capacity : 1;
    tb_status status = reserve_bodies(scene, capacity);
    if (status == TB_STATUS_OK) {
        status = reserve_states(scene, TB_STATE_SIZE * capacity);
    }
    if (status == TB_STATUS_OK && def->effect_capacity > 0) {
        status = tb__scene_reserve_effects(scene, def->effect_capacity);
    }
    if (status != TB_STATUS_OK) {
        tb_scene_destroy(scene);
        return tb__set_error(out_error, status, "scene with room for %zu bodies, %zu effects",
                             def->body_capacity, def->effect_capacity);
    }
    *out_scene = scene;
    return TB_STATUS_OK;
}

void tb_scene_destroy(tb_scene *scene)
{
    if (scene != NULL) {
        free(scene->states);
        free(scene->bodies);
        free(scene->mass_props);
        free(scene->names);
        free(scene->effects);
        free(scene->effect_order);
        free(scene->contacts);
        free(scene);
    }
}

const char *tb_scene_detail(const tb_scene *scene)
{
    return scene == NULL ? "scene is NULL" : scene->detail;
}

tb_status tb__check_vector(tb_scene *scene, const double *v, const char *what)
{
    if (v == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "%s is NULL", what);
    }
    if (!tb__all_finite(v, 3)) {
        return tb__scene_fail(scene, TB_STATUS_NOT_FINITE,
                              "%s: contains NaN or infinity (%g, %g, %g)", what, v[0], v[1], v[2]);
    }
    return TB_STATUS_OK;
}

static tb_status validate_name(tb_scene *scene, const char *name)
{
    if (name == NULL) {
        return TB_STATUS_OK;
    }
    const size_t length = strlen(name);
    if (length == 0 || length >= TB_NAME_SIZE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.name: must have 1 to %d characters, got %zu", TB_NAME_SIZE - 1,
                              length);
    }
    size_t existing;
    if (tb_scene_find_body(scene, name, &existing) == TB_STATUS_OK) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.name: \"%s\" is already body %zu's name", name, existing);
    }
    return TB_STATUS_OK;
}

static tb_status validate_body_def(tb_scene *scene, const tb_body_def *def)
{
    if (def->internal_cookie != TB__BODY_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_body_def_default()");
    }
    if (validate_name(scene, def->name) != TB_STATUS_OK) {
        return TB_STATUS_INVALID_ARGUMENT;
    }
    tb_error error;
    tb_status status = tb_mass_validate(&def->mass, &error);
    if (status != TB_STATUS_OK) {
        return tb__scene_fail(scene, status, "def.mass.%s", error.message);
    }
    status = tb__check_unit_quaternion(def->orientation, "def.orientation", &error);
    if (status != TB_STATUS_OK) {
        return tb__scene_fail(scene, status, "%s", error.message);
    }
    status = tb__check_vector(scene, def->position, "def.position");
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, def->velocity, "def.velocity");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, def->angular_velocity, "def.angular_velocity");
    }
    return status;
}

/* P = M v and L = R diag(I) R^T omega for body i at its state's orientation. */
static void set_momenta(tb_scene *scene, size_t i, const double v[3], const double omega[3])
{
    double *s = scene->states + TB_STATE_SIZE * i;
    const tb_mass_properties *props = &scene->mass_props[i];
    double q[4], omega_body[3];
    tb__unit_quaternion(scene->states, i, q);
    tb__q_rotate_inverse(omega_body, q, omega);
    for (int k = 0; k < 3; ++k) {
        s[7 + k] = props->mass * v[k];
        omega_body[k] *= props->moments[k];
    }
    tb__q_rotate(s + 10, q, omega_body);
}

tb_status tb_scene_add_body(tb_scene *scene, const tb_body_def *def, size_t *out_id)
{
    if (scene == NULL || def == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    tb_status status = validate_body_def(scene, def);
    if (status == TB_STATUS_OK && scene->body_count == scene->body_capacity) {
        status = reserve_bodies(scene, 2 * scene->body_capacity);
    }
    if (status == TB_STATUS_OK) {
        /* Effect-owned states move up by one body and restart from zero. */
        status = tb__scene_layout_states(scene, scene->body_count + 1);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const size_t i = scene->body_count;
    const tb_mass_properties *props = &def->mass;
    scene->mass_props[i] = *props;
    if (def->name != NULL) {
        snprintf(scene->names[i], TB_NAME_SIZE, "%s", def->name);
    } else {
        snprintf(scene->names[i], TB_NAME_SIZE, "body%zu", i);
    }
    scene->bodies[i].mass = props->mass;
    scene->bodies[i].inv_mass = 1.0 / props->mass;
    for (int k = 0; k < 3; ++k) {
        scene->bodies[i].inv_moments[k] = 1.0 / props->moments[k];
    }
    double *s = scene->states + TB_STATE_SIZE * i;
    double orientation[4];
    const double norm = tb__q_norm(def->orientation);
    for (int k = 0; k < 4; ++k) {
        orientation[k] = def->orientation[k] / norm;
    }
    tb__v3_copy(s, def->position);
    tb__q_mul(s + 3, orientation, props->rotation); /* principal -> shape -> world */
    const double qn = tb__q_norm(s + 3);
    for (int k = 0; k < 4; ++k) {
        s[3 + k] /= qn;
    }
    set_momenta(scene, i, def->velocity, def->angular_velocity);
    scene->body_count++;
    if (out_id != NULL) {
        *out_id = i;
    }
    return TB_STATUS_OK;
}

size_t tb_scene_body_count(const tb_scene *scene)
{
    return scene == NULL ? 0 : scene->body_count;
}

const char *tb_scene_body_name(const tb_scene *scene, size_t id)
{
    return scene == NULL || id >= scene->body_count ? NULL : scene->names[id];
}

tb_status tb_scene_find_body(const tb_scene *scene, const char *name, size_t *out_id)
{
    if (scene == NULL || name == NULL || out_id == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    for (size_t i = 0; i < scene->body_count; ++i) {
        if (strcmp(scene->names[i], name) == 0) {
            *out_id = i;
            return TB_STATUS_OK;
        }
    }
    return TB_STATUS_OUT_OF_RANGE;
}

double *tb_scene_states(tb_scene *scene)
{
    return scene == NULL ? NULL : scene->states;
}

const double *tb_scene_states_const(const tb_scene *scene)
{
    return scene == NULL ? NULL : scene->states;
}

tb_status tb_scene_get_state(const tb_scene *scene, size_t id, tb_body_state *out_state)
{
    if (scene == NULL || out_state == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        memcpy(out_state, scene->states + TB_STATE_SIZE * id, sizeof *out_state);
    }
    return status;
}

tb_status tb_scene_set_state(tb_scene *scene, size_t id, const tb_body_state *state)
{
    if (scene == NULL || state == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double *values = &state->x[0];
    if (!tb__all_finite(values, TB_STATE_SIZE)) {
        return tb__scene_fail(scene, TB_STATUS_NOT_FINITE,
                              "state of body %zu: contains NaN or infinity", id);
    }
    tb_error error;
    status = tb__check_unit_quaternion(state->q, "q", &error);
    if (status != TB_STATUS_OK) {
        return tb__scene_fail(scene, status, "state of body %zu: %s", id, error.message);
    }
    double *s = scene->states + TB_STATE_SIZE * id;
    memcpy(s, values, TB_STATE_SIZE * sizeof(double));
    const double norm = tb__q_norm(state->q);
    for (int k = 0; k < 4; ++k) {
        s[3 + k] = state->q[k] / norm;
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_set_velocity(tb_scene *scene, size_t id, const double velocity[3],
                                const double angular_velocity[3])
{
    if (scene == NULL || velocity == NULL || angular_velocity == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, velocity, "velocity");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, angular_velocity, "angular_velocity");
    }
    if (status == TB_STATUS_OK) {
        set_momenta(scene, id, velocity, angular_velocity);
    }
    return status;
}

tb_status tb_scene_get_mass(const tb_scene *scene, size_t id, tb_mass_properties *out_mass)
{
    if (scene == NULL || out_mass == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        *out_mass = scene->mass_props[id];
    }
    return status;
}

tb_status tb_scene_ode_system(tb_scene *scene, tb_ode_system *out_system)
{
    if (scene == NULL || out_system == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    if (scene->body_count == 0) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "scene has no bodies: nothing to integrate");
    }
    *out_system = (tb_ode_system){
        .n = tb_scene_state_size(scene),
        .derivative = tb_scene_derivative,
        .post_step = scene->renormalize ? tb_scene_normalize_quaternions : NULL,
        .ctx = scene,
    };
    /* Bodies that do not interact are the system's blocks. */
    if (tb__scene_separable(scene)) {
        out_system->block_size = TB_STATE_SIZE;
        out_system->block_derivative = tb__scene_block_derivative;
        out_system->block_post_step = scene->renormalize ? tb__scene_block_normalize : NULL;
    }
    return TB_STATUS_OK;
}

void tb_scene_set_renormalize(tb_scene *scene, bool renormalize)
{
    if (scene != NULL) {
        scene->renormalize = renormalize;
    }
}

double tb_scene_quaternion_drift(const tb_scene *scene)
{
    return scene == NULL ? NAN : scene->quaternion_drift;
}

void tb_scene_reset_quaternion_drift(tb_scene *scene)
{
    if (scene != NULL) {
        scene->quaternion_drift = 0.0;
    }
}

tb_status tb_scene_absolute_tolerances(const tb_scene *scene, double scale, double *out_atol)
{
    if (scene == NULL || out_atol == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    if (!(scale > 0) || !isfinite(scale)) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_INVALID_ARGUMENT,
                              "scale: must be finite and > 0, got %g", scale);
    }
    for (size_t i = 0; i < scene->body_count; ++i) {
        const tb_mass_properties *props = &scene->mass_props[i];
        const double largest = fmax(props->moments[0], fmax(props->moments[1], props->moments[2]));
        const double length = sqrt(largest / props->mass);
        const double block[TB_STATE_SIZE] = {length,
                                             length,
                                             length,
                                             1.0,
                                             1.0,
                                             1.0,
                                             1.0,
                                             props->mass * length,
                                             props->mass * length,
                                             props->mass * length,
                                             largest,
                                             largest,
                                             largest};
        for (int k = 0; k < TB_STATE_SIZE; ++k) {
            out_atol[TB_STATE_SIZE * i + k] = scale * block[k];
        }
    }
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *effect = &scene->effects[e];
        const size_t count = effect->states_per_contact * scene->contact_count;
        for (size_t k = 0; k < count; ++k) {
            out_atol[effect->state_offset + k] = scale * effect->state_scale;
        }
    }
    return TB_STATUS_OK;
}

/* The automatic absolute tolerance is this fraction of rtol times each component's natural
 * scale: it matters only for components smaller than 1% of their scale. */
#define TB__ATOL_FRACTION 1e-2

/* Half-bandwidth that covers one body's 13 x 13 Jacobian block. */
#define TB__BODY_HALF_BANDWIDTH (TB_STATE_SIZE - 1)

tb_status tb_scene_integrator_create(tb_scene *scene, const tb_integrator_def *def, double t0,
                                     tb_integrator **out_integrator)
{
    tb_ode_system system;
    tb_status status = tb_scene_ode_system(scene, &system);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (def == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "def is NULL");
    }
    tb_integrator_def scene_def = *def;
    double *atol = NULL;
    if (tb_method_is_adaptive(def->method) && def->atol == 0.0 && def->atol_vector == NULL &&
        def->rtol > 0 && isfinite(def->rtol)) {
        atol = malloc(system.n * sizeof(double));
        if (atol == NULL) {
            return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "tolerance vector");
        }
        tb_scene_absolute_tolerances(scene, TB__ATOL_FRACTION * def->rtol, atol);
        scene_def.atol_vector = atol;
    }
    if (scene_def.preconditioner_half_bandwidth < 0) {
        scene_def.preconditioner_half_bandwidth = TB__BODY_HALF_BANDWIDTH;
    }
    if (!tb_method_is_adaptive(def->method) && !def->allow_unstable) {
        double max_dt;
        char which[TB_DETAIL_SIZE];
        tb_scene_max_stable_step(scene, def->method, &max_dt, which);
        if (def->dt > max_dt) {
            free(atol);
            return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                  "def.dt: %g s is beyond %s's stability limit for %s: use dt "
                                  "<= %.3g s, or cvode-bdf",
                                  def->dt, tb_method_name(def->method), which, max_dt);
        }
    }
    tb_error error;
    status = tb_integrator_create(&system, &scene_def, t0, scene->states, out_integrator, &error);
    free(atol); /* the integrator copied it */
    if (status != TB_STATUS_OK) {
        tb__scene_fail(scene, status, "integrator: %s", error.message);
    }
    return status;
}

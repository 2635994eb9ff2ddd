/* The scene object: creation, bodies, states. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "mass/mass_internal.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TB__SCENE_COOKIE 0x5ce2e

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
    def.sleeping = true;
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
    if (capacity > SIZE_MAX / (TB_STATE_SIZE * sizeof(double) + sizeof(tb_mass_properties) +
                               sizeof(tb__motion) + 3 * sizeof(size_t) + sizeof(tb__body_kind))) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "%zu bodies", capacity);
    }
    tb__body *bodies = tb__realloc_array(scene->bodies, capacity, sizeof(tb__body));
    if (bodies != NULL) {
        scene->bodies = bodies;
    }
    tb_mass_properties *props =
        tb__realloc_array(scene->mass_props, capacity, sizeof(tb_mass_properties));
    if (props != NULL) {
        scene->mass_props = props;
    }
    char(*names)[TB_NAME_SIZE] = tb__realloc_array(scene->names, capacity, sizeof *names);
    if (names != NULL) {
        scene->names = names;
    }
    tb__motion *motions = realloc(scene->motions, capacity * sizeof(tb__motion));
    if (motions != NULL) {
        scene->motions = motions;
    }
    size_t *slots = tb__realloc_array(scene->slots, capacity, sizeof(size_t));
    if (slots != NULL) {
        scene->slots = slots;
    }
    size_t *slot_ids = tb__realloc_array(scene->slot_ids, capacity, sizeof(size_t));
    if (slot_ids != NULL) {
        scene->slot_ids = slot_ids;
    }
    size_t *fixed_ids = tb__realloc_array(scene->fixed_ids, capacity, sizeof(size_t));
    if (fixed_ids != NULL) {
        scene->fixed_ids = fixed_ids;
    }
    tb__body_kind *kinds = tb__realloc_array(scene->kinds, capacity, sizeof(tb__body_kind));
    if (kinds != NULL) {
        scene->kinds = kinds;
    }
    if (bodies == NULL || props == NULL || names == NULL || motions == NULL || slots == NULL ||
        slot_ids == NULL || fixed_ids == NULL || kinds == NULL) {
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
    double *states = tb__realloc_array(scene->states, capacity, sizeof(double));
    if (states == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "state array of %zu doubles",
                              capacity);
    }
    scene->states = states;
    scene->state_capacity = capacity;
    return TB_STATUS_OK;
}

tb_status tb__scene_layout_states(tb_scene *scene, size_t slot_count)
{
    tb_status status = tb__scene_check_idle(scene, "changing the scene's layout");
    if (status != TB_STATUS_OK) {
        return status;
    }
    size_t extra = 0;
    for (size_t e = 0; e < scene->effect_count; ++e) {
        extra += tb__effect_state_count(&scene->effects[e], scene);
    }
    status = reserve_states(scene, TB_STATE_SIZE * slot_count + extra);
    if (status != TB_STATUS_OK) {
        return status;
    }
    size_t offset = TB_STATE_SIZE * slot_count;
    for (size_t e = 0; e < scene->effect_count; ++e) {
        scene->effects[e].state_offset = offset;
        offset += tb__effect_state_count(&scene->effects[e], scene);
    }
    memset(scene->states + TB_STATE_SIZE * slot_count, 0, extra * sizeof(double));
    scene->extra_count = extra;
    if (slot_count > scene->slot_count) {
        tb__scene_layout_changed(scene, "body %zu added", scene->body_count);
    } else {
        tb__scene_layout_changed(scene, "effect-owned states laid out again (%zu contact points)",
                                 scene->contact_count);
    }
    return TB_STATUS_OK;
}

size_t tb_scene_state_size(const tb_scene *scene)
{
    return scene == NULL ? 0 : TB_STATE_SIZE * scene->slot_count + scene->extra_count;
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
    scene->sleeping = def->sleeping;
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
        for (size_t k = 0; k < scene->effect_count; ++k) {
            if (scene->effects[k].ops->release != NULL) {
                scene->effects[k].ops->release(&scene->effects[k]);
            }
            free(scene->effects[k].params);
        }
        if (scene->constraint_ops != NULL) {
            scene->constraint_ops->destroy(scene->constraints);
        }
        free(scene->states);
        free(scene->bodies);
        free(scene->motions);
        free(scene->slots);
        free(scene->slot_ids);
        free(scene->fixed_ids);
        tb__scene_release_motion_sources(scene);
        free(scene->kinds);
        free(scene->lane_constants);
        free(scene->states_left);
        free(scene->mass_props);
        free(scene->names);
        free(scene->effects);
        free(scene->effect_order);
        free(scene->contacts);
        for (size_t i = 0; i < scene->shape_capacity; ++i) {
            free(scene->shapes[i]);
        }
        free(scene->shapes);
        for (size_t i = 0; i < scene->visual_capacity; ++i) {
            for (size_t k = 0; scene->visuals[i] != NULL && k < scene->visuals[i]->count; ++k) {
                free(scene->visuals[i]->meshes[k]);
            }
            free(scene->visuals[i]);
        }
        free(scene->visuals);
        free(scene->name_slots);
        tb__scene_sleep_free(scene);
        tb__scene_events_free(scene);
        tb__scene_impacts_free(scene);
        tb__scene_jacobian_free(scene);
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

void tb__scene_clear_detail(const tb_scene *scene)
{
    ((tb_scene *)scene)->detail[0] = '\0';
}

/* P (if not NULL) and L (if not NULL) finite, and the velocities made from them too:
 * |P| / M and |L| / I_min, bounded through the largest component times sqrt(3). */
static bool rates_finite(const tb_mass_properties *props, const double P[3], const double L[3])
{
    const double root3 = 1.7320508075688772;
    if (P != NULL) {
        const double largest = fmax(fabs(P[0]), fmax(fabs(P[1]), fabs(P[2])));
        if (!isfinite(largest) || !isfinite(root3 * largest / props->mass)) {
            return false;
        }
    }
    if (L != NULL) {
        const double largest = fmax(fabs(L[0]), fmax(fabs(L[1]), fabs(L[2])));
        const double smallest = fmin(props->moments[0], fmin(props->moments[1], props->moments[2]));
        if (!isfinite(largest) || !isfinite(root3 * largest / smallest)) {
            return false;
        }
    }
    return true;
}

/* P = M v and L = R diag(I) R^T omega for a body of mass properties props at orientation q
 * (principal -> world, unit). Refuses momenta that overflow (1e308 kg at 10 m/s), naming the
 * argument (`velocity`, `angular_velocity`, with `prefix` before it). */
static tb_status momenta(tb_scene *scene, const tb_mass_properties *props, const double q[4],
                         const double v[3], const double omega[3], const char *prefix,
                         double out_P[3], double out_L[3])
{
    double omega_body[3];
    tb__q_rotate_inverse(omega_body, q, omega);
    for (int k = 0; k < 3; ++k) {
        out_P[k] = props->mass * v[k];
        omega_body[k] *= props->moments[k];
    }
    tb__q_rotate(out_L, q, omega_body);
    /* P and L finite, and so are the rates made from them: dx/dt = P / M (v = -1.8e308 m/s
     * rounds to a finite P whose P / M is not) and omega = I^-1 L */
    if (!rates_finite(props, out_P, NULL)) {
        return tb__scene_fail(scene, TB_STATUS_NOT_FINITE,
                              "%svelocity: (%g, %g, %g) m/s: the momentum M v or the speed "
                              "|P| / M overflows (M = %g kg)",
                              prefix, v[0], v[1], v[2], props->mass);
    }
    if (!rates_finite(props, NULL, out_L)) {
        return tb__scene_fail(scene, TB_STATUS_NOT_FINITE,
                              "%sangular_velocity: (%g, %g, %g) rad/s: the angular momentum "
                              "I omega or the rate I^-1 L overflows",
                              prefix, omega[0], omega[1], omega[2]);
    }
    return TB_STATUS_OK;
}

/* The new body's state from its def: x, q = orientation (x) principal rotation, P, L. */
static tb_status initial_state(tb_scene *scene, const tb_body_def *def, double s[TB_STATE_SIZE])
{
    const tb_mass_properties *props = &def->mass;
    double orientation[4];
    const double norm = tb__q_norm(def->orientation);
    for (int k = 0; k < 4; ++k) {
        orientation[k] = def->orientation[k] / norm;
    }
    tb__v3_copy(s + TB_STATE_X, def->position);
    double *q = s + TB_STATE_Q;
    tb__q_mul(q, orientation, props->rotation); /* principal -> shape -> world */
    const double qn = tb__q_norm(q);
    for (int k = 0; k < 4; ++k) {
        q[k] /= qn;
    }
    return momenta(scene, props, q, def->velocity, def->angular_velocity, "def.", s + TB_STATE_P,
                   s + TB_STATE_L);
}

/* Room for one more body everywhere it is kept; nothing is lost on failure. */
static tb_status make_room_for_body(tb_scene *scene, bool dynamic)
{
    /* first: growing the arrays would move what a step in progress is reading */
    tb_status status = tb__scene_check_idle(scene, "adding a body");
    if (status == TB_STATUS_OK && scene->body_count == scene->body_capacity) {
        status = reserve_bodies(scene, 2 * scene->body_capacity);
    }
    if (status == TB_STATUS_OK) {
        status = tb__scene_reserve_names(scene, scene->body_count + 1);
    }
    if (status == TB_STATUS_OK) {
        /* Effect-owned states move up by one body and restart from zero. */
        status = tb__scene_layout_states(scene, scene->slot_count + (dynamic ? 1 : 0));
    }
    return status;
}

tb_status tb_scene_add_body(tb_scene *scene, const tb_body_def *def, size_t *out_id)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (def == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "def is NULL");
    }
    tb__body constants;
    tb__body_kind kind = {.motion = TB_MOTION_DYNAMIC};
    double s[TB_STATE_SIZE];
    tb_status status = tb__scene_validate_body_def(scene, def);
    const bool dynamic = def->motion == TB_MOTION_DYNAMIC;
    if (status == TB_STATUS_OK && dynamic) {
        status = tb__scene_body_constants(scene, &def->mass, &constants);
    }
    if (status == TB_STATUS_OK) {
        status = dynamic ? initial_state(scene, def, s) : tb__body_kind_from_def(scene, def, &kind);
    }
    if (status == TB_STATUS_OK) {
        status = make_room_for_body(scene, dynamic);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const size_t i = scene->body_count;
    scene->mass_props[i] = dynamic ? def->mass : tb__fixed_mass_properties();
    scene->kinds[i] = kind;
    if (def->name != NULL) {
        snprintf(scene->names[i], TB_NAME_SIZE, "%s", def->name);
    } else {
        snprintf(scene->names[i], TB_NAME_SIZE, "body%zu", i);
    }
    scene->slots[i] = TB_NO_SLOT;
    if (dynamic) {
        const size_t slot = scene->slot_count++;
        scene->slots[i] = slot;
        scene->slot_ids[slot] = i;
        scene->bodies[slot] = constants;
        memcpy(tb__body_state_mut(scene, scene->states, i), s, sizeof s);
    } else {
        scene->fixed_ids[i - scene->slot_count] = i;
        tb__scene_layout_changed(scene, "body %zu added", i);
    }
    scene->body_count++;
    tb__scene_insert_name(scene, i);
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
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (name == NULL || out_id == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "%s is NULL",
                              name == NULL ? "name" : "out_id");
    }
    if (!tb__scene_lookup_name(scene, name, out_id)) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_OUT_OF_RANGE,
                              "name: no body is called \"%.*s\"", TB_NAME_SIZE, name);
    }
    return TB_STATUS_OK;
}

double *tb_scene_states(tb_scene *scene)
{
    return scene == NULL ? NULL : scene->states;
}

const double *tb_scene_states_const(const tb_scene *scene)
{
    return scene == NULL ? NULL : scene->states;
}

/* The prologue of a function on body id with one required pointer: clears the detail, then
 * refuses a NULL pointer (named) or an id out of range. */
static tb_status begin_body_call(const tb_scene *scene, size_t id, const void *pointer,
                                 const char *pointer_name)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (pointer == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "%s is NULL",
                              pointer_name);
    }
    return tb__scene_check_id(scene, id, "id");
}

tb_status tb_scene_get_state(const tb_scene *scene, size_t id, tb_body_state *out_state)
{
    tb_status status = begin_body_call(scene, id, out_state, "out_state");
    if (status == TB_STATUS_OK && tb__body_fixed(scene, id)) { /* its pose, no momenta */
        tb__motion motion;
        tb__body_motion_at(scene, scene->time, scene->states, id, &motion);
        *out_state = (tb_body_state){.x = {motion.x[0], motion.x[1], motion.x[2]},
                                     .q = {motion.q[0], motion.q[1], motion.q[2], motion.q[3]}};
    } else if (status == TB_STATUS_OK) {
        memcpy(out_state, tb__body_state(scene, scene->states, id), sizeof *out_state);
    }
    return status;
}

tb_status tb_scene_set_state(tb_scene *scene, size_t id, const tb_body_state *state)
{
    tb_status status = begin_body_call(scene, id, state, "state");
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_dynamic(scene, id, "set_state");
    }
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_idle(scene, "set_state");
    }
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
    if (!rates_finite(&scene->mass_props[id], state->P, state->L)) {
        return tb__scene_fail(scene, TB_STATUS_NOT_FINITE,
                              "state of body %zu: P / M or I^-1 L overflows (|P| %g, |L| %g)", id,
                              tb__v3_norm(state->P), tb__v3_norm(state->L));
    }
    double *s = tb__body_state_mut(scene, scene->states, id);
    memcpy(s, values, TB_STATE_SIZE * sizeof(double));
    const double norm = tb__q_norm(state->q);
    for (int k = 0; k < 4; ++k) {
        s[TB_STATE_Q + k] = state->q[k] / norm;
    }
    tb__scene_wake_body(scene, id);
    return TB_STATUS_OK;
}

tb_status tb_scene_set_velocity(tb_scene *scene, size_t id, const double velocity[3],
                                const double angular_velocity[3])
{
    tb_status status = begin_body_call(scene, id, velocity, "velocity");
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_dynamic(scene, id, "set_velocity");
    }
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_idle(scene, "set_velocity");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, velocity, "velocity");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, angular_velocity, "angular_velocity");
    }
    double q[4], P[3], L[3];
    if (status == TB_STATUS_OK) {
        tb__unit_quaternion(tb__body_state(scene, scene->states, id), 0, q);
        status = momenta(scene, &scene->mass_props[id], q, velocity, angular_velocity, "", P, L);
    }
    if (status == TB_STATUS_OK) {
        double *s = tb__body_state_mut(scene, scene->states, id);
        tb__v3_copy(s + TB_STATE_P, P);
        tb__v3_copy(s + TB_STATE_L, L);
        tb__scene_wake_body(scene, id);
    }
    return status;
}

tb_status tb_scene_get_mass(const tb_scene *scene, size_t id, tb_mass_properties *out_mass)
{
    tb_status status = begin_body_call(scene, id, out_mass, "out_mass");
    if (status == TB_STATUS_OK) {
        *out_mass = scene->mass_props[id];
    }
    return status;
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

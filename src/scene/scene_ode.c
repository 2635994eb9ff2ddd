/* The scene as an ODE system: its derivative and hooks for the generic integrators, the
 * lifetimes that keep an integrator from stepping a scene whose layout changed under it (or
 * that another call is stepping), tolerances, and integrator creation with the stability
 * gate. */
#include "scene/lanes.h"
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"
#include "core/validate.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* --- lifetimes --------------------------------------------------------------------------- */

tb_status tb__scene_check_idle(tb_scene *scene, const char *what)
{
    if (!scene->busy) {
        return TB_STATUS_OK;
    }
    return tb__scene_fail(scene, TB_STATUS_BUSY,
                          "%s: the scene is being stepped (called from inside a derivative, "
                          "hook or user effect)",
                          what);
}

void tb__scene_layout_changed(tb_scene *scene, const char *format, ...)
{
    scene->layout_generation++;
    va_list args;
    va_start(args, format);
    vsnprintf(scene->layout_change, sizeof scene->layout_change, format, args);
    va_end(args);
}

/* Whether an effect checks the state an integrator starts from (a ground plane, contact). */
static bool has_start_checks(const tb_scene *scene)
{
    for (size_t k = 0; k < scene->effect_count; ++k) {
        if (scene->effects[k].ops->check_start != NULL) {
            return true;
        }
    }
    return false;
}

/* Every effect's check of y as a state to start from (a body moved deep into a ground plane
 * or into another body); detail (TB_DETAIL_SIZE bytes) names the effect and what it found. */
static tb_status check_start(const tb_scene *scene, const double *y, char *detail)
{
    char found[TB_DETAIL_SIZE];
    for (size_t k = 0; k < scene->effect_count; ++k) {
        const tb__effect *effect = &scene->effects[k];
        if (effect->ops->check_start == NULL) {
            continue;
        }
        const tb_status status = effect->ops->check_start(effect, scene, y, found);
        if (status != TB_STATUS_OK) {
            return tb__set_detail(detail, status, "effect %zu (a %s): %.*s", k, effect->ops->name,
                                  TB_DETAIL_SIZE - 64, found);
        }
    }
    return tb__scene_check_impacts(scene, y, detail); /* bodies too fast for a thin one */
}

/* Remembers the state as the newest integrator leaves it (room made by tb_scene_ode_system;
 * without room, or without effects that check starts, nothing is remembered). */
static void remember_state(tb_scene *scene)
{
    const size_t n = tb_scene_state_size(scene);
    scene->states_left_size = 0;
    scene->set_since = NULL;
    if (n <= scene->states_left_capacity && has_start_checks(scene)) {
        memcpy(scene->states_left, scene->states, n * sizeof(double));
        scene->states_left_size = n;
    }
}

/* Whether a body's position or orientation differs from the state the newest integrator left.
 * Only a pose can move a body into another: momenta (tb_scene_set_velocity) and the effects'
 * own states cannot, so changing them alone is never refused here, even in a settled stack
 * whose lowest pair, carrying every weight above it, is deeper than a start may be. */
static bool poses_changed(const tb_scene *scene)
{
    for (size_t slot = 0; slot < scene->slot_count; ++slot) {
        const size_t k = TB_STATE_SIZE * slot + TB_STATE_X;
        if (memcmp(scene->states_left + k, scene->states + k,
                   (TB_STATE_P - TB_STATE_X) * sizeof(double)) != 0) {
            return true;
        }
    }
    return false;
}

/* A state changed since the newest integrator left it gets the checks of a start: every path
 * that changes it (tb_scene_set_state, tb_scene_set_velocity, writes through tb_scene_states,
 * the bindings' assignments) meets here, at the next advance, step or reset of every method.
 * So does a shape set since (tb_scene_set_body_shape, _pieces: a ball grown into another was
 * thrown out at 580 m/s under CVODE) or a keyframed body's motion (tb_scene_set_body_keys,
 * _motion_fn: a slab moved up through a ball threw it at 246 m/s); once they pass, they are the
 * start's. */
static tb_status check_changed_state(tb_scene *scene, char *detail)
{
    const size_t n = scene->states_left_size;
    if (n == 0 || n != tb_scene_state_size(scene) ||
        !(scene->set_since != NULL || poses_changed(scene))) {
        return TB_STATUS_OK;
    }
    char found[TB_DETAIL_SIZE];
    const tb_status status = check_start(scene, scene->states, found);
    if (status == TB_STATUS_OK) {
        scene->set_since = NULL;
        return status;
    }
    return tb__set_detail(detail, status,
                          "the %s changed since the last step, and the state is refused as a "
                          "start would be: %.*s",
                          scene->set_since != NULL ? scene->set_since : "state was",
                          TB_DETAIL_SIZE - 96, found);
}

/* Whether the bodies' states are the ones the newest integrator left (nothing set since). */
static bool left_as_it_was(const tb_scene *scene)
{
    const size_t n = TB_STATE_SIZE * scene->slot_count;
    return scene->states_left_size == tb_scene_state_size(scene) &&
           memcmp(scene->states_left, scene->states, n * sizeof(double)) == 0;
}

/* The impact check refused a state the run itself reached (every start was checked when the
 * integrator was made, or when it was set): bodies that fell fast onto a thin one, or a method
 * that lost the motion (CVODE BDF at rtol 1e-3 on the example dice threw a die at 2.5 km/s).
 * The status stays the check's; the detail says when, and that the run reached it. */
static tb_status reached_by_the_run(const tb_scene *scene, tb_status status, char *detail)
{
    char found[TB_DETAIL_SIZE];
    memcpy(found, detail, sizeof found);
    return tb__set_detail(detail, status,
                          "at t = %g s the run reached a state the contact cannot stop (if no "
                          "body should move this fast, the method lost the motion: a tighter "
                          "rtol or a shorter step): %.*s",
                          scene->time, TB_DETAIL_SIZE - 192, found);
}

/* tb_ode_system.lifetime.layout_generation: an integrator is being made on the scene. It claims the
 * scene: the generation moves on, so integrators made before refuse to step (two integrators
 * stepping one scene would each take the other's steps as changes from outside). */
static unsigned long long claim(void *ctx)
{
    tb_scene *scene = ctx;
    tb__scene_layout_changed(scene, "a newer integrator was made on the scene");
    scene->separable_at_claim = tb__scene_separable(scene);
    scene->guard_dt = 0.0;
    remember_state(scene);
    return scene->layout_generation;
}

/* tb_ode_system.events.check_break (and every advance's or step's start): where a keyframed body's
 * keys jump at t (a step key), the state there gets the checks of a start, so that a body the
 * jump put inside another is refused rather than thrown out (F117); continuous keys pass. */
static tb_status check_break(double t, const double *y, void *ctx, char *detail)
{
    tb_scene *scene = ctx;
    if (!has_start_checks(scene) || !tb__scene_fixed_poses_jump(scene, t)) {
        return TB_STATUS_OK;
    }
    const double time_before = scene->time;
    scene->time = t; /* the bodies without a state where the jump put them */
    char found[TB_DETAIL_SIZE];
    const tb_status status = check_start(scene, y, found);
    scene->time = status == TB_STATUS_OK ? time_before : t;
    return status == TB_STATUS_OK
               ? status
               : tb__set_detail(detail, status,
                                "at t = %.17g a keyframed body's keys jump, and the state there "
                                "is refused as a start would be: %.*s",
                                t, TB_DETAIL_SIZE - 128, found);
}

static tb_status acquire(void *ctx, unsigned long long generation, char *detail)
{
    tb_scene *scene = ctx;
    if (scene->busy) {
        return tb__set_detail(detail, TB_STATUS_BUSY,
                              "the scene is already being stepped by a call in progress (an "
                              "integrator advanced from inside a callback of another)");
    }
    if (generation != scene->layout_generation) {
        return tb__set_detail(detail, TB_STATUS_LAYOUT_CHANGED,
                              "the scene changed after this integrator was made (last: %s): "
                              "make a new integrator",
                              scene->layout_change);
    }
    if (scene->separable_at_claim && !tb__scene_separable(scene)) {
        return tb__set_detail(detail, TB_STATUS_LAYOUT_CHANGED,
                              "an effect coupling bodies was added after this integrator was "
                              "made for independent bodies: make a new integrator");
    }
    const tb_status changed = check_changed_state(scene, detail);
    if (changed != TB_STATUS_OK) {
        return changed;
    }
    if (scene->guard_dt > 0.0) {
        const tb_status status = tb__scene_check_step(scene, scene->states, scene->guard_method,
                                                      scene->guard_dt, detail);
        if (status != TB_STATUS_OK) {
            return status;
        }
    }
    const tb_status status = tb__scene_check_impacts(scene, scene->states, detail);
    if (status != TB_STATUS_OK) {
        return left_as_it_was(scene) ? reached_by_the_run(scene, status, detail) : status;
    }
    if (scene->constraint_ops != NULL && tb_method_is_adaptive(scene->guard_method) &&
        scene->constraint_ops->at_output(scene->constraints, scene, scene->time, scene->states) !=
            0) { /* joints breaking at the last output; CVODE restarts on it (rhs_generation) */
        return tb__set_detail(detail, TB_STATUS_DERIVATIVE_FAILED,
                              "the joints' check at t = %g: the derivative failed", scene->time);
    }
    tb__scene_sleep_apply_pending(scene); /* CVODE restarts on it (rhs_generation) */
    scene->busy = true;
    return TB_STATUS_OK;
}

/* tb_ode_system.lifetime.check_reset: keys may put a keyframed body inside another at the new time,
 * so a reset that moves one gets the checks of a start there (as creation does at t0); the scene's
 * time becomes t, or stays on a refusal. */
static tb_status check_reset(double t, const double *y, void *ctx, char *detail)
{
    tb_scene *scene = ctx;
    if (!has_start_checks(scene) || !tb__scene_fixed_poses_move(scene, t)) {
        scene->time = t;
        tb__scene_restart(scene, t, y);
        tb__scene_impacts_reset(scene, t);
        return TB_STATUS_OK;
    }
    const double time_before = scene->time;
    scene->time = t;
    char found[TB_DETAIL_SIZE];
    const tb_status status = check_start(scene, y, found);
    if (status != TB_STATUS_OK) {
        scene->time = time_before;
        return tb__set_detail(detail, status, "reset to t = %.17g is refused as a start: %.*s", t,
                              TB_DETAIL_SIZE - 96, found);
    }
    tb__scene_restart(scene, t, y);
    tb__scene_impacts_reset(scene, t);
    return TB_STATUS_OK;
}

/* tb_ode_system.lifetime.rhs_generation: effects added since (a force, a drag) change the
 * right-hand side without changing the layout; CVODE restarts on them. */
static unsigned long long rhs_generation(void *ctx)
{
    const tb_scene *scene = ctx;
    return scene->effects_generation + tb__scene_sleep_generation(scene);
}

static void release(void *ctx)
{
    tb_scene *scene = ctx;
    scene->busy = false;
    remember_state(scene);
}

/* --- the ODE system ---------------------------------------------------------------------- */

/* The rooms an integrator's runs need, made before it exists: the sleeping flags of a scene
 * whose bodies interact, and the copy of the n states it leaves (check_changed_state). */
static tb_status prepare_rooms(tb_scene *scene, size_t n)
{
    if (!tb__scene_separable(scene) && tb__scene_sleep_prepare(scene) != TB_STATUS_OK) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    if (n > scene->states_left_capacity && has_start_checks(scene)) {
        double *grown = tb__realloc_array(scene->states_left, n, sizeof(double));
        if (grown == NULL) {
            return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "a copy of %zu states", n);
        }
        scene->states_left = grown;
        scene->states_left_capacity = n;
    }
    return TB_STATUS_OK;
}

/* The full hook where effects or sleep need it, or where bodies without a state are read at the
 * scene's time, which it keeps; else the renormalisation alone (or nothing). */
static tb_ode_hook post_step_hook(const tb_scene *scene)
{
    return tb__scene_has_post_step_effects(scene) || !tb__scene_separable(scene) ||
                   scene->slot_count < scene->body_count
               ? tb__scene_post_step
               : (scene->renormalize ? tb_scene_normalize_quaternions : NULL);
}

/* Contact: a gap per body for CVODE's root finding, and steps kept short near contacts
 * (scene_events.c); bodies that can sleep add a second gap per body, to the nearest body of the
 * other sleep state, so that CVODE stops before an awake body touches an asleep one and wakes it
 * there (sleep.c). The constraints' events (joint stops) come after those. Bodies that interact:
 * the contact's sparse Jacobian, its pattern their contact graph (scene_jacobian.c). ark-imex
 * takes the loads without a mode of their own explicitly (tb__scene_explicit_part). */
static void set_events_and_jacobian(const tb_scene *scene, tb_ode_system *out_system)
{
    if (tb__scene_has_events(scene)) {
        out_system->events.step_limit = tb__scene_step_limit;
        out_system->events.split_limit = tb__scene_split_limit;
        out_system->events.at_event =
            scene->sleep != NULL || scene->contact_events != NULL ? tb__scene_at_event : NULL;
    }
    out_system->events.root_count = tb__scene_root_count(scene);
    out_system->events.roots = out_system->events.root_count > 0 ? tb__scene_roots : NULL;
    out_system->events.root_signs = out_system->events.root_count > 0 ? tb__scene_root_signs : NULL;
    out_system->events.root_signs_for = out_system->events.roots;
    if (scene->constraint_ops != NULL && out_system->events.root_count > 0) {
        out_system->events.at_event = tb__scene_at_event;
    }
    if (!tb__scene_separable(scene)) { /* bodies that can sleep: a rest to jump over */
        out_system->events.rest_until = tb__scene_rest_until;
    }
    out_system->split.explicit_part = tb__scene_explicit_part;
    if (tb__scene_has_jacobian(scene)) {
        out_system->jacobian.capacity = tb__scene_jacobian_capacity;
        out_system->jacobian.evaluate = tb__scene_jacobian;
    }
}

tb_status tb_scene_ode_system(tb_scene *scene, tb_ode_system *out_system)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_system == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "out_system is NULL");
    }
    if (scene->slot_count == 0) { /* no body, or none with a state */
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "scene has no %sbodies: nothing to integrate",
                              scene->body_count > 0 ? "dynamic " : "");
    }
    *out_system = (tb_ode_system){
        .n = tb_scene_state_size(scene),
        .derivative = tb_scene_derivative,
        .post_step = post_step_hook(scene),
        .ctx = scene,
        .lifetime = {.layout_generation = claim,
                     .acquire = acquire,
                     .release = release,
                     .rhs_generation = rhs_generation,
                     .check_reset = check_reset},
        /* the key times of bodies without a state */
        .events.next_break = scene->slot_count < scene->body_count ? tb__scene_next_break : NULL,
        .events.check_break = scene->slot_count < scene->body_count ? check_break : NULL,
    };
    const tb_status rooms = prepare_rooms(scene, out_system->n);
    if (rooms != TB_STATUS_OK) {
        return rooms;
    }
    set_events_and_jacobian(scene, out_system);
    /* Bodies that do not interact are the system's blocks. */
    if (tb__scene_separable(scene)) {
        out_system->blocks.size = TB_STATE_SIZE;
        out_system->blocks.derivative = tb__scene_block_derivative;
        out_system->blocks.post_step = scene->renormalize ? tb__scene_block_normalize : NULL;
        const tb__lanes_kernels *kernels = tb__scene_lanes_kernels(scene);
        if (kernels != NULL && tb__scene_prepare_lanes(scene) != TB_STATUS_OK) {
            return TB_STATUS_OUT_OF_MEMORY;
        }
        if (kernels != NULL) {
            out_system->blocks.lanes = tb__lanes_for(scene->slot_count);
            out_system->blocks.lanes_derivative = kernels->derivative;
            out_system->blocks.lanes_post_step = scene->renormalize ? kernels->normalize : NULL;
        }
    }
    return TB_STATUS_OK;
}

void tb_scene_set_allow_unstable(tb_scene *scene, bool allow)
{
    if (scene != NULL) {
        scene->allow_unstable = allow;
    }
}

bool tb_scene_allow_unstable(const tb_scene *scene)
{
    return scene != NULL && scene->allow_unstable;
}

tb_status tb_scene_absolute_tolerances(const tb_scene *scene, double scale, double *out_atol)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_atol == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_atol is NULL");
    }
    if (!(scale > 0) || !isfinite(scale)) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_INVALID_ARGUMENT,
                              "scale: must be finite and > 0, got %g", scale);
    }
    for (size_t i = 0; i < scene->slot_count; ++i) {
        const tb_mass_properties *props = &scene->mass_props[scene->slot_ids[i]];
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
        const size_t count = tb__effect_state_count(effect, scene);
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

/* A fixed step must stay a step at t0: where doubles are spaced more than this fraction of dt
 * apart, t0 + dt rounds to a step of another length (t0 = 1e15 s: spacing 0.125 s, so steps of
 * 1/240 s would be 0 s). */
#define TB__TIME_RESOLUTION 1e-6

/* What tb_integrator_create does not know: the stability gate for the scene at its state, and
 * the time resolution at t0. */
static tb_status check_fixed_step(tb_scene *scene, const tb_integrator_def *def, double t0)
{
    if (tb_method_is_adaptive(def->method) || !(def->dt > 0) || !isfinite(def->dt) ||
        !isfinite(t0)) {
        return TB_STATUS_OK; /* tb_integrator_create names what is wrong */
    }
    const double spacing = nextafter(fabs(t0), INFINITY) - fabs(t0);
    if (spacing > TB__TIME_RESOLUTION * def->dt && fabs(t0) <= def->dt) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.dt: %g s is too small to step: doubles near t0 = %g s are %g s "
                              "apart, so every step would be rounded by %.2g of itself (at most "
                              "%g)",
                              def->dt, t0, spacing, spacing / def->dt, TB__TIME_RESOLUTION);
    }
    if (spacing > TB__TIME_RESOLUTION * def->dt) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "t0: %g s is too large for def.dt = %g s: doubles near t0 are %g s "
                              "apart, so every step would be rounded by %.2g of itself (at most "
                              "%g): start the time nearer 0",
                              t0, def->dt, spacing, spacing / def->dt, TB__TIME_RESOLUTION);
    }
    char detail[TB_DETAIL_SIZE];
    const tb_status status =
        tb__scene_check_step(scene, scene->states, def->method, def->dt, detail);
    return status == TB_STATUS_OK ? status : tb__scene_fail(scene, status, "def.%s", detail);
}

/* def with the scene's automatic tolerances (atol_vector, allocated into *out_atol) and
 * preconditioner bandwidth filled in, and the count of unresolved impacts for its step
 * (impact_watch.c; NULL where the step resolves every impact). */
static tb_status scene_integrator_def(tb_scene *scene, const tb_integrator_def *def,
                                      tb_integrator_def *out_def, double **out_atol,
                                      struct tb__impacts **out_impacts)
{
    *out_def = *def;
    *out_atol = NULL;
    const tb_status status =
        tb__scene_impacts_prepare(scene, scene->states, def->method, def->dt, out_impacts);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (tb_method_is_adaptive(def->method) && def->atol == 0.0 && def->atol_vector == NULL &&
        def->rtol > 0 && isfinite(def->rtol)) {
        double *atol = tb__malloc_array(tb_scene_state_size(scene), sizeof(double));
        if (atol == NULL) {
            tb__scene_impacts_discard(*out_impacts);
            return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "tolerance vector");
        }
        tb_scene_absolute_tolerances(scene, TB__ATOL_FRACTION * def->rtol, atol);
        out_def->atol_vector = atol;
        *out_atol = atol;
    }
    if (out_def->preconditioner_half_bandwidth < 0) {
        out_def->preconditioner_half_bandwidth = TB__BODY_HALF_BANDWIDTH;
    }
    return TB_STATUS_OK;
}

static tb_status create_at(tb_scene *scene, const tb_integrator_def *def, double t0,
                           tb_integrator **out_integrator)
{
    tb_ode_system system;
    tb_status status = tb_scene_ode_system(scene, &system);
    if (status == TB_STATUS_OK && (def == NULL || out_integrator == NULL)) {
        status = tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "%s is NULL",
                                def == NULL ? "def" : "out_integrator");
    }
    tb_integrator_def stepped; /* def.dt 0: the scene's default step */
    if (status == TB_STATUS_OK) {
        stepped = *def;
        if (!tb_method_is_adaptive(def->method) && def->dt == 0.0) { /* none: the rate named */
            status = tb_scene_default_step(scene, def->method, &stepped.dt);
        }
        def = &stepped;
        status = status != TB_STATUS_OK ? status : check_fixed_step(scene, def, t0);
    }
    if (status == TB_STATUS_OK) {
        char detail[TB_DETAIL_SIZE];
        status = check_start(scene, scene->states, detail);
        if (status != TB_STATUS_OK) {
            tb__scene_fail(scene, status, "%s", detail);
        }
    }
    tb_integrator_def scene_def;
    double *atol = NULL;
    struct tb__impacts *impacts = NULL; /* the count of unresolved impacts, if dt can leave any */
    if (status == TB_STATUS_OK) {
        status = scene_integrator_def(scene, def, &scene_def, &atol, &impacts);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    /* A failed creation leaves older integrators as they were. */
    const unsigned long long generation = scene->layout_generation;
    const bool separable = scene->separable_at_claim;
    const double guard_dt = scene->guard_dt;
    const bool stabilise = scene->stabilise_constraints;
    /* CVODE Adams has no projection (SUNDIALS 6 projects with BDF only): its steps keep to the
     * joints by the constraint stage's Baumgarte terms */
    scene->stabilise_constraints = def->method == TB_METHOD_CVODE_ADAMS;
    tb_error error;
    status = tb_integrator_create(&system, &scene_def, t0, scene->states, out_integrator, &error);
    free(atol); /* the integrator copied it */
    if (status != TB_STATUS_OK) {
        scene->layout_generation = generation;
        scene->separable_at_claim = separable;
        scene->guard_dt = guard_dt;
        scene->stabilise_constraints = stabilise;
        tb__scene_impacts_discard(impacts);
        return tb__scene_fail(scene, status, "integrator: %s", error.message);
    }
    tb__scene_impacts_commit(scene, impacts);
    scene->guard_method = def->method;
    scene->guard_dt = tb_method_is_adaptive(def->method) ? 0.0 : def->dt;
    tb__scene_events_start(scene, t0, !tb_method_is_adaptive(def->method));
    tb__scene_restart(scene, t0, scene->states);
    return TB_STATUS_OK;
}

tb_status tb_scene_integrator_create(tb_scene *scene, const tb_integrator_def *def, double t0,
                                     tb_integrator **out_integrator)
{
    if (out_integrator != NULL) {
        *out_integrator = NULL; /* also on failure */
    }
    /* The checks (start, default step, stability) read bodies without a state at t0, where
     * the states start; a refusal leaves the scene's time as it was. */
    const double time_before = scene != NULL ? scene->time : 0.0;
    if (scene != NULL && !scene->busy && isfinite(t0)) {
        scene->time = t0;
    }
    const tb_status status = create_at(scene, def, t0, out_integrator);
    if (status != TB_STATUS_OK && scene != NULL) {
        scene->time = time_before;
    }
    return status;
}

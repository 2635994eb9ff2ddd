/* The body-motion accessor: a body's slot in y, its constants and its motion at (t, y), by id.
 * Every read of a body's state goes through here, so that a body with no state is a case of
 * these functions and not of their callers. */
#include "scene/scene_internal.h"

#include "tumble/keys.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const kind_names[] = {"dynamic", "static", "keyframed"};

/* What a body that cannot move offers every law: no inverse mass, no inverse inertia. */
static const tb__body immovable = {.mass = INFINITY};

const tb__body *tb__body_constants(const tb_scene *scene, size_t id)
{
    const size_t slot = scene->slots[id];
    return slot == TB_NO_SLOT ? &immovable : &scene->bodies[slot];
}

/* A static body's motion: its pose, at rest. */
static void fixed_motion(const tb__body_kind *kind, tb__motion *out)
{
    for (int k = 0; k < 3; ++k) {
        out->x[k] = kind->x[k];
        out->v[k] = 0.0;
        out->omega[k] = 0.0;
    }
    for (int k = 0; k < 4; ++k) {
        out->q[k] = kind->q[k];
    }
}

/* A keyframed body's motion from its source at t: the shape origin is its centre, the shape
 * frame its principal frame. */
static int sampled_motion(const tb__body_kind *kind, double t, tb__motion *out)
{
    tb_body_motion_sample sample;
    const int rc = kind->fn(t, kind->ctx, &sample);
    const double norm = rc == 0 ? tb__q_norm(sample.orientation) : 0.0;
    /* a source that says 0 but gives a NaN, an infinity or a zero quaternion fails too */
    const bool usable =
        rc == 0 && norm > 0.0 && isfinite(norm) && tb__all_finite(sample.position, 3) &&
        tb__all_finite(sample.velocity, 3) && tb__all_finite(sample.angular_velocity, 3) &&
        tb__all_finite(sample.acceleration, 3) && tb__all_finite(sample.angular_acceleration, 3);
    if (!usable) {
        fixed_motion(kind, out);
        return rc != 0 ? rc : -1;
    }
    for (int k = 0; k < 3; ++k) {
        out->x[k] = sample.position[k];
        out->v[k] = sample.velocity[k];
        out->omega[k] = sample.angular_velocity[k];
    }
    for (int k = 0; k < 4; ++k) {
        out->q[k] = sample.orientation[k] / norm;
    }
    return 0;
}

int tb__body_motion_at(const tb_scene *scene, double t, const double *y, size_t id, tb__motion *out)
{
    const size_t slot = scene->slots[id];
    if (slot == TB_NO_SLOT) {
        const tb__body_kind *kind = &scene->kinds[id];
        if (kind->fn != NULL) {
            return sampled_motion(kind, t, out);
        }
        fixed_motion(kind, out);
        return 0;
    }
    tb__body_motion(&scene->bodies[slot], y + TB_STATE_SIZE * slot, out);
    return 0;
}

/* A bound of |q(s)| on [0, 1] for q quadratic in s, from q(0) = a, q(1/2) = m and q(1) = b: the
 * largest of its Bezier points a, 2 m - (a + b) / 2 and b, which hold the curve in their hull. */
static double quadratic_bound(const double a[3], const double m[3], const double b[3])
{
    double c[3];
    for (int k = 0; k < 3; ++k) {
        c[k] = 2.0 * m[k] - 0.5 * (a[k] + b[k]);
    }
    return fmax(tb__v3_norm(a), fmax(tb__v3_norm(c), tb__v3_norm(b)));
}

/* Keyframed body id's speeds after each break k (pieces [b_j, b_j+1], j >= k, of its curve):
 * the largest |v| into break_times[n + k], |omega| into break_times[2 n + k], each piece bounded
 * by the velocity taken as quadratic in time through its ends and middle (exact for linear and
 * cubic positions; an estimate for the rotation). Made once when the source is set, so that
 * each check reads them in O(log n) (a curve of 1e5 keys at every frame's check). */
static void fill_speeds_after(const tb_scene *scene, size_t id)
{
    const tb__body_kind *kind = &scene->kinds[id];
    const size_t n = kind->break_count;
    double *times = kind->break_times, fastest_v = 0.0, fastest_w = 0.0;
    for (size_t k = n; k-- > 0;) {
        if (k + 1 < n) {
            const double from = times[k], to = times[k + 1];
            tb__motion a, m, b; /* the piece's start, middle and end (the left limit) */
            tb__body_motion_at(scene, from, scene->states, id, &a);
            tb__body_motion_at(scene, from + 0.5 * (to - from), scene->states, id, &m);
            tb__body_motion_at(scene, nextafter(to, from), scene->states, id, &b);
            fastest_v = fmax(fastest_v, quadratic_bound(a.v, m.v, b.v));
            fastest_w = fmax(fastest_w, quadratic_bound(a.omega, m.omega, b.omega));
        }
        times[n + k] = fastest_v;
        times[2 * n + k] = fastest_w;
    }
}

/* The first of kind's break times at or after t (break_count: none). */
static size_t first_break_from(const tb__body_kind *kind, double t)
{
    size_t low = 0, high = kind->break_count;
    while (low < high) {
        const size_t middle = low + (high - low) / 2;
        if (kind->break_times[middle] < t) {
            low = middle + 1;
        } else {
            high = middle;
        }
    }
    return low;
}

double tb__body_fastest_from(const tb_scene *scene, double t, const double *y, size_t id,
                             double reach)
{
    tb__motion now;
    tb__body_motion_at(scene, t, y, id, &now);
    double fastest = tb__v3_norm(now.v) + tb__v3_norm(now.omega) * reach;
    if (!tb__body_fixed(scene, id) || scene->kinds[id].break_count == 0) {
        return fastest;
    }
    const tb__body_kind *kind = &scene->kinds[id];
    const size_t n = kind->break_count, next = first_break_from(kind, t);
    /* the piece t lies in (the whole of it), and every one after */
    const size_t k = next > 0 && next < n && t < kind->break_times[next] ? next - 1 : next;
    if (k < n) {
        fastest = fmax(fastest, kind->break_times[n + k] + kind->break_times[2 * n + k] * reach);
    }
    return fastest;
}

bool tb__scene_fixed_poses_move(const tb_scene *scene, double t)
{
    for (size_t k = 0; k < scene->body_count - scene->slot_count; ++k) {
        const size_t id = scene->fixed_ids[k];
        double x[3], q[4], x_t[3], q_t[4];
        tb__body_pose_at(scene, scene->time, scene->states, id, x, q);
        tb__body_pose_at(scene, t, scene->states, id, x_t, q_t);
        if (memcmp(x, x_t, sizeof x) != 0 || memcmp(q, q_t, sizeof q) != 0) {
            return true;
        }
    }
    return false;
}

/* Whether keyframed body id jumps at its break t: its pose there (the piece that starts at t)
 * lies farther from the limit from the left than a continuous curve moves in one rounding of t
 * (1e-9 m and 1e-9 rad leave room for the latter at any speed a contact takes). */
static bool jumps_at(const tb_scene *scene, size_t id, double t)
{
    tb__motion left, right;
    tb__body_motion_at(scene, nextafter(t, -INFINITY), scene->states, id, &left);
    tb__body_motion_at(scene, t, scene->states, id, &right);
    double dx[3], minus = 0.0, plus = 0.0; /* q and -q: one rotation */
    for (int k = 0; k < 3; ++k) {
        dx[k] = right.x[k] - left.x[k];
    }
    for (int k = 0; k < 4; ++k) {
        minus += (right.q[k] - left.q[k]) * (right.q[k] - left.q[k]);
        plus += (right.q[k] + left.q[k]) * (right.q[k] + left.q[k]);
    }
    /* |q_r - q_l| is about half the angle between them */
    return tb__v3_hypot(dx) > 1e-9 + 1e-12 * tb__v3_hypot(right.x) || fmin(minus, plus) > 1e-18;
}

bool tb__scene_fixed_poses_jump(const tb_scene *scene, double t)
{
    for (size_t k = 0; k < scene->body_count - scene->slot_count; ++k) {
        const size_t id = scene->fixed_ids[k];
        const tb__body_kind *kind = &scene->kinds[id];
        const double near = 8.0 * DBL_EPSILON * fabs(t); /* CVODE's t_origin + tau */
        for (size_t b = first_break_from(kind, t - near);
             b < kind->break_count && kind->break_times[b] <= t + near; ++b) {
            if (jumps_at(scene, id, kind->break_times[b])) {
                return true;
            }
        }
    }
    return false;
}

void tb__body_pose_at(const tb_scene *scene, double t, const double *y, size_t id, double out_x[3],
                      double out_q[4])
{
    const size_t slot = scene->slots[id];
    if (slot == TB_NO_SLOT) {
        tb__motion motion;
        tb__body_motion_at(scene, t, y, id, &motion);
        memcpy(out_x, motion.x, sizeof motion.x);
        memcpy(out_q, motion.q, sizeof motion.q);
        return;
    }
    const double *s = y + TB_STATE_SIZE * slot;
    out_x[0] = s[TB_STATE_X];
    out_x[1] = s[TB_STATE_X + 1];
    out_x[2] = s[TB_STATE_X + 2];
    tb__unit_quaternion(s, 0, out_q);
}

tb_status tb_scene_body_slot(const tb_scene *scene, size_t id, size_t *out_slot)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_slot == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_slot is NULL");
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        *out_slot = scene->slots[id];
    }
    return status;
}

tb_mass_properties tb__fixed_mass_properties(void)
{
    return (tb_mass_properties){.mass = INFINITY,
                                .moments = {INFINITY, INFINITY, INFINITY},
                                .rotation = {1.0, 0.0, 0.0, 0.0}};
}

tb_status tb__body_kind_from_def(tb_scene *scene, const tb_body_def *def, tb__body_kind *out)
{
    if (def->motion != TB_MOTION_STATIC && def->motion != TB_MOTION_KEYFRAMED) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.motion: %d is not a motion kind (TB_MOTION_DYNAMIC, "
                              "TB_MOTION_STATIC or TB_MOTION_KEYFRAMED)",
                              (int)def->motion);
    }
    const double *v = def->velocity, *w = def->angular_velocity;
    if (def->motion == TB_MOTION_STATIC &&
        (v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 || w[0] != 0.0 || w[1] != 0.0 || w[2] != 0.0)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.%svelocity: a static body does not move, got (%g, %g, %g)",
                              v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 ? "" : "angular_",
                              v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 ? v[0] : w[0],
                              v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 ? v[1] : w[1],
                              v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 ? v[2] : w[2]);
    }
    out->motion = def->motion;
    const double norm = tb__q_norm(def->orientation);
    for (int k = 0; k < 4; ++k) {
        out->q[k] = def->orientation[k] / norm;
    }
    tb__v3_copy(out->x, def->position);
    return TB_STATUS_OK;
}

tb_status tb__scene_check_dynamic(const tb_scene *scene, size_t id, const char *what)
{
    if (scene->slots[id] == TB_NO_SLOT) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_INVALID_ARGUMENT,
                              "%s: body %zu (\"%s\") is %s: it has no state to change", what, id,
                              scene->names[id], kind_names[scene->kinds[id].motion]);
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_body_motion_kind(const tb_scene *scene, size_t id, tb_body_motion *out_motion)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_motion == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_motion is NULL");
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        *out_motion = scene->kinds[id].motion;
    }
    return status;
}

static int compare_times(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void release_source(tb__body_kind *kind)
{
    if (kind->release != NULL) {
        kind->release(kind->ctx);
    }
    free(kind->break_times);
    kind->fn = NULL;
    kind->ctx = NULL;
    kind->release = NULL;
    kind->break_times = NULL;
    kind->break_count = 0;
}

/* The checks of a new source for body id; the detail names what is wrong. */
static tb_status check_source(tb_scene *scene, size_t id, const double *break_times,
                              size_t break_count)
{
    tb_status status = tb__scene_check_idle(scene, "setting a body's motion");
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_id(scene, id, "id");
    }
    if (status == TB_STATUS_OK && scene->kinds[id].motion != TB_MOTION_KEYFRAMED) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "id: body %zu (\"%s\") is %s, not keyframed", id, scene->names[id],
                                kind_names[scene->kinds[id].motion]);
    }
    if (status == TB_STATUS_OK && break_times == NULL && break_count > 0) {
        status = tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "break_times is NULL (count %zu)",
                                break_count);
    }
    for (size_t k = 0; status == TB_STATUS_OK && k < break_count; ++k) {
        if (!isfinite(break_times[k])) {
            status = tb__scene_fail(scene, TB_STATUS_NOT_FINITE,
                                    "break_times[%zu]: must be finite, got %g", k, break_times[k]);
        }
    }
    return status;
}

tb_status tb__scene_set_body_motion_source(tb_scene *scene, size_t id, tb_body_motion_fn fn,
                                           void *ctx, const double *break_times, size_t break_count,
                                           void (*release)(void *ctx))
{
    tb_status status = check_source(scene, id, break_times, break_count);
    double *times = NULL;
    if (status == TB_STATUS_OK && break_count > 0) {
        times = tb__malloc_array(break_count, 3 * sizeof(double)); /* with the speeds after */
        status = times == NULL ? tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "%zu break times",
                                                break_count)
                               : TB_STATUS_OK;
    }
    if (status != TB_STATUS_OK) {
        if (release != NULL) {
            release(ctx); /* owned from the call on */
        }
        return status;
    }
    if (times != NULL) {
        memcpy(times, break_times, break_count * sizeof(double));
        qsort(times, break_count, sizeof(double), compare_times);
    }
    tb__body_kind *kind = &scene->kinds[id];
    release_source(kind);
    kind->fn = fn;
    kind->ctx = ctx;
    kind->release = release;
    kind->break_times = times;
    kind->break_count = break_count;
    fill_speeds_after(scene, id);
    scene->effects_generation++; /* the right-hand side changed: CVODE restarts */
    scene->set_since = "keyframed bodies' motions were"; /* checked as a start (scene_ode.c) */
    tb__scene_wake_all(scene);
    return TB_STATUS_OK;
}

tb_status tb_scene_set_body_motion_fn(tb_scene *scene, size_t id, tb_body_motion_fn fn, void *ctx)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    return tb__scene_set_body_motion_source(scene, id, fn, ctx, NULL, 0, NULL);
}

static void release_keyframes(void *ctx)
{
    tb_keyframes_destroy(ctx);
}

tb_status tb_scene_set_body_keys(tb_scene *scene, size_t id, const tb_body_key *keys, size_t count,
                                 tb_interpolation interpolation)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    /* the source's own checks (idle, id, kind) before the curve is made */
    tb_status status = check_source(scene, id, NULL, 0);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb_keyframes *curve = NULL;
    tb_error error;
    status = tb_keyframes_create(keys, count, interpolation, &curve, &error);
    if (status != TB_STATUS_OK) {
        return tb__scene_fail(scene, status, "%s", error.message);
    }
    size_t times = 0;
    const double *at = tb_keyframes_times(curve, &times);
    return tb__scene_set_body_motion_source(scene, id, tb_keyframes_sample, curve, at, times,
                                            release_keyframes);
}

void tb__scene_release_motion_sources(tb_scene *scene)
{
    for (size_t id = 0; scene->kinds != NULL && id < scene->body_count; ++id) {
        release_source(&scene->kinds[id]);
    }
}

double tb__scene_next_break(double t, void *ctx)
{
    const tb_scene *scene = ctx;
    double next = INFINITY;
    for (size_t k = 0; k < scene->body_count - scene->slot_count; ++k) {
        const tb__body_kind *kind = &scene->kinds[scene->fixed_ids[k]];
        for (size_t b = 0; b < kind->break_count; ++b) {
            if (kind->break_times[b] > t) {
                next = fmin(next, kind->break_times[b]);
                break;
            }
        }
    }
    return next;
}

double tb_scene_time(const tb_scene *scene)
{
    return scene == NULL ? NAN : scene->time;
}

tb_status tb_scene_set_time(tb_scene *scene, double t)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = tb__scene_check_idle(scene, "setting the scene's time");
    if (status == TB_STATUS_OK && !isfinite(t)) {
        status = tb__scene_fail(scene, TB_STATUS_NOT_FINITE, "t: must be finite, got %g", t);
    }
    if (status == TB_STATUS_OK) {
        scene->time = t;
    }
    return status;
}

tb_status tb_scene_body_reaction(tb_scene *scene, const double *y, size_t id, double out_force[3],
                                 double out_torque[3])
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (y == NULL || out_force == NULL || out_torque == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "%s is NULL",
                              y == NULL           ? "y"
                              : out_force == NULL ? "out_force"
                                                  : "out_torque");
    }
    tb_status status = tb__scene_check_idle(scene, "a reaction read-out");
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_id(scene, id, "id");
    }
    if (status == TB_STATUS_OK && !tb__body_fixed(scene, id)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "id: body %zu (\"%s\") is dynamic: its loads move it", id,
                                scene->names[id]);
    }
    const size_t n = tb_scene_state_size(scene);
    double *dydt = status == TB_STATUS_OK ? tb__malloc_array(n > 0 ? n : 1, sizeof(double)) : NULL;
    double *reactions =
        status == TB_STATUS_OK ? calloc(6 * scene->body_count, sizeof(double)) : NULL;
    if (status == TB_STATUS_OK && (dydt == NULL || reactions == NULL)) {
        status = tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "a derivative's scratch");
    }
    if (status == TB_STATUS_OK) {
        scene->reactions = reactions;
        const int rc = tb_scene_derivative(scene->time, y, dydt, scene);
        scene->reactions = NULL;
        status = rc == 0 ? TB_STATUS_OK
                         : tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                          "the derivative failed at t = %g (%d)", scene->time, rc);
    }
    if (status == TB_STATUS_OK) {
        memcpy(out_force, reactions + 6 * id, 3 * sizeof(double));
        memcpy(out_torque, reactions + 6 * id + 3, 3 * sizeof(double));
    }
    free(dydt);
    free(reactions);
    return status;
}

void tb__fixed_body_acceleration_at(const tb_scene *scene, double t, size_t id, double out_a[3],
                                    double out_alpha[3])
{
    const tb__body_kind *kind = &scene->kinds[id];
    tb_body_motion_sample sample;
    const bool sampled =
        scene->slots[id] == TB_NO_SLOT && kind->fn != NULL && kind->fn(t, kind->ctx, &sample) == 0;
    for (int k = 0; k < 3; ++k) {
        out_a[k] = sampled ? sample.acceleration[k] : 0.0;
        out_alpha[k] = sampled ? sample.angular_acceleration[k] : 0.0;
    }
}

/* Contact with a ground plane: penalty normal force and LuGre friction at the bodies' contact
 * points. The friction model (Canudas de Wit, Olsson, Astrom, Lischinsky, IEEE Trans.
 * Automatic Control 40(3), 1995) gives each contact point a bristle deflection z, here two
 * components in the plane, with dz/dt = v_t - s0 |v_t| z / mu(|v_t|) and friction
 * F_t = -N (s0 z + s1 dz/dt), normalised by the normal force N. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

#define TB__GROUND_COOKIE 0x960d
/* Rate (1/s) at which a lifted point's bristles relax: fast against motion, slow enough for
 * RK4 at 60 steps per second (h * rate = 1.7 < 2.78). */
#define TB__BRISTLE_RELEASE_RATE 100.0
/* LuGre's bristles relax towards their sliding deflection at s0 |v| / mu per second: 24000/s
 * at 2 m/s with the defaults, beyond any explicit step an animator would take. The rate is
 * capped here, so RK4 at 240 steps per second stays stable (h * 400 = 1.7 < 2.78); below
 * |v| = 400 mu / s0 (3 cm/s with the defaults) the model is LuGre's exactly, and above it the
 * bristles reach their sliding deflection in a few milliseconds instead of microseconds. */
#define TB__BRISTLE_MAX_RATE 400.0

enum { /* param slots */
       OFFSET,
       GRAVITY,
       PENETRATION,
       DAMPING_RATIO,
       MU_STATIC,
       MU_KINETIC,
       STRIBECK,
       S0,
       S1
};

/* Normal force magnitude for a point of a body of mass M carrying share of its weight. */
static double normal_force(const tb__effect *effect, double mass, double share, double depth,
                           double normal_speed)
{
    const double *p = effect->param;
    const double stiffness = mass * p[GRAVITY] * share / p[PENETRATION];
    const double damping = 2.0 * p[DAMPING_RATIO] * sqrt(stiffness * mass * share);
    const double force = stiffness * depth - damping * normal_speed;
    return force > 0.0 ? force : 0.0;
}

/* LuGre at one point: writes dz and returns the friction force per unit normal force in
 * the tangent basis. dz/dt = v - s0 |v| z / mu is written as rate (z_sliding - z) with
 * rate = s0 |v| / mu and z_sliding = mu v / (s0 |v|), so the rate can be capped. The bristle
 * damping fades with speed, s1 exp(-(v / v_s)^2), as Canudas de Wit et al. suggest, so that
 * it damps presliding and does not add to sliding friction. */
static void bristles(const tb__effect *effect, const double v_t[2], const double z[2], double dz[2],
                     double friction[2])
{
    const double *p = effect->param;
    const double speed = hypot(v_t[0], v_t[1]);
    const double ratio = speed / p[STRIBECK];
    const double fade = exp(-ratio * ratio);
    const double mu = p[MU_KINETIC] + (p[MU_STATIC] - p[MU_KINETIC]) * fade;
    if (!(mu > 0.0)) { /* frictionless */
        for (int k = 0; k < 2; ++k) {
            dz[k] = -TB__BRISTLE_RELEASE_RATE * z[k];
            friction[k] = 0.0;
        }
        return;
    }
    const double rate = p[S0] * speed / mu;
    for (int k = 0; k < 2; ++k) {
        if (rate <= TB__BRISTLE_MAX_RATE) {
            dz[k] = v_t[k] - rate * z[k];
        } else {
            const double sliding = mu * v_t[k] / (p[S0] * speed);
            dz[k] = TB__BRISTLE_MAX_RATE * (sliding - z[k]);
        }
        friction[k] = -(p[S0] * z[k] + p[S1] * fade * dz[k]);
    }
}

static void contact(const tb__effect *effect, const tb_scene *scene, const tb__contact *c,
                    const tb__motion *motion, const double *z, double *dz, double *dydt)
{
    const double *n = effect->vector, *t1 = effect->point, *t2 = effect->other_point;
    double arm[3];
    tb__point_arm(motion, c->r, arm);
    const double height = tb__v3_dot(n, motion->x) + tb__v3_dot(n, arm) - effect->param[OFFSET];
    const double depth = c->radius - height;
    if (depth <= 0.0) {
        dz[0] = -TB__BRISTLE_RELEASE_RATE * z[0];
        dz[1] = -TB__BRISTLE_RELEASE_RATE * z[1];
        return;
    }
    tb__v3_axpy(arm, -c->radius, n); /* the sphere's lowest point touches */
    double velocity[3];
    tb__point_velocity(motion, arm, velocity);
    const double mass = scene->bodies[c->body].mass;
    const double N = normal_force(effect, mass, c->share, depth, tb__v3_dot(n, velocity));
    const double v_t[2] = {tb__v3_dot(t1, velocity), tb__v3_dot(t2, velocity)};
    double friction[2];
    bristles(effect, v_t, z, dz, friction);
    double f[3];
    for (int k = 0; k < 3; ++k) {
        f[k] = N * (n[k] + friction[0] * t1[k] + friction[1] * t2[k]);
    }
    tb__add_load(dydt, c->body, arm, f);
}

static int apply_ground(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                        double *dydt)
{
    (void)t;
    tb__motion motion;
    size_t current = TB_ALL_BODIES;
    for (size_t j = 0; j < scene->contact_count; ++j) {
        const tb__contact *c = &scene->contacts[j];
        if (c->body != current) { /* a body's points are contiguous: read its motion once */
            current = c->body;
            tb__body_motion(&scene->bodies[current], y + TB_STATE_SIZE * current, &motion);
        }
        const size_t k = effect->state_offset + 2 * j;
        contact(effect, scene, c, &motion, y + k, dydt + k, dydt);
    }
    return 0;
}

tb_ground_def tb_ground_def_default(void)
{
    tb_ground_def def;
    memset(&def, 0, sizeof def);
    def.normal[2] = 1.0;
    def.gravity = 9.81;
    def.penetration = 1e-3;
    def.damping_ratio = 1.0;
    def.static_friction = 0.6;
    def.kinetic_friction = 0.5;
    def.stribeck_velocity = 0.01;
    def.presliding = 1e-4;
    def.internal_cookie = TB__GROUND_COOKIE;
    return def;
}

static tb_status check_positive(tb_scene *scene, double value, const char *what)
{
    if (!(value > 0) || !isfinite(value)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "%s: must be finite and > 0, got %g", what, value);
    }
    return TB_STATUS_OK;
}

static tb_status validate_ground(tb_scene *scene, const tb_ground_def *def)
{
    if (def->internal_cookie != TB__GROUND_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_ground_def_default()");
    }
    const double length = tb__v3_norm(def->normal);
    if (!isfinite(length) || fabs(length - 1.0) > 1e-6 || !isfinite(def->offset)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "%s: must be a finite unit vector and number, got |normal| = %g, "
                              "offset = %g",
                              isfinite(def->offset) ? "normal" : "offset", length, def->offset);
    }
    tb_status status = check_positive(scene, def->gravity, "gravity");
    if (status == TB_STATUS_OK) {
        status = check_positive(scene, def->penetration, "penetration");
    }
    if (status == TB_STATUS_OK) {
        status = check_positive(scene, def->stribeck_velocity, "stribeck_velocity");
    }
    if (status == TB_STATUS_OK) {
        status = check_positive(scene, def->presliding, "presliding");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_coefficient(scene, def->damping_ratio, "damping_ratio");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_coefficient(scene, def->kinetic_friction, "kinetic_friction");
    }
    if (status == TB_STATUS_OK &&
        !(def->static_friction >= def->kinetic_friction && isfinite(def->static_friction))) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "static_friction: must be finite and >= kinetic_friction (%g), "
                                "got %g",
                                def->kinetic_friction, def->static_friction);
    }
    return status;
}

/* t1, t2: an orthonormal basis of the plane, right-handed with n. */
static void tangent_basis(const double n[3], double t1[3], double t2[3])
{
    const double axis[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    tb__v3_cross(t1, n, axis);
    const double length = tb__v3_norm(t1);
    tb__v3_set(t1, t1[0] / length, t1[1] / length, t1[2] / length);
    tb__v3_cross(t2, n, t1);
}

tb_status tb_scene_add_ground(tb_scene *scene, const tb_ground_def *def)
{
    if (scene == NULL || def == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    tb_status status = validate_ground(scene, def);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__effect effect = {
        .apply = apply_ground, .kind = TB__GROUND, .body = TB_ALL_BODIES, .states_per_contact = 2};
    const double length = tb__v3_norm(def->normal);
    tb__v3_set(effect.vector, def->normal[0] / length, def->normal[1] / length,
               def->normal[2] / length);
    tangent_basis(effect.vector, effect.point, effect.other_point);
    double *p = effect.param;
    p[OFFSET] = def->offset;
    p[GRAVITY] = def->gravity;
    p[PENETRATION] = def->penetration;
    p[DAMPING_RATIO] = def->damping_ratio;
    p[MU_STATIC] = def->static_friction;
    p[MU_KINETIC] = def->kinetic_friction;
    p[STRIBECK] = def->stribeck_velocity;
    /* s0 sets the breakaway deflection. s1 gives the bristles of one point, loaded by the mass
     * m = N / g it carries, a damping ratio of 1/2: sigma1 = 2 (1/2) sqrt(sigma0 m) with
     * sigma = N s. Not 1: a flat body's yaw mode on its corners is sqrt(3) times stiffer and
     * sqrt(3) times more damped than one point, and overdamped at 1.73 its fast eigenvalue
     * (5.4 omega) would leave RK4's stability region at 240 steps per second. */
    p[S0] = def->static_friction / def->presliding;
    p[S1] = sqrt(p[S0] / def->gravity);
    effect.state_scale = def->presliding;
    return tb__scene_push_effect(scene, &effect);
}

/* --- contact points ---------------------------------------------------------------------- */

static tb_status check_points(tb_scene *scene, const tb_contact_point *points, size_t count)
{
    for (size_t k = 0; k < count; ++k) {
        if (!tb__all_finite(points[k].position, 3) || !(points[k].radius >= 0) ||
            !isfinite(points[k].radius)) {
            return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                  "points[%zu]: position must be finite and radius finite and "
                                  ">= 0, got radius %g",
                                  k, points[k].radius);
        }
    }
    return TB_STATUS_OK;
}

/* Removes body id's points and appends the new ones at the end (keeps each body's points
 * contiguous). Works on a copy so that a failure changes nothing. */
tb_status tb_scene_set_contact_points(tb_scene *scene, size_t id, const tb_contact_point *points,
                                      size_t count, size_t support)
{
    if (scene == NULL || (points == NULL && count > 0)) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        status = check_points(scene, points, count);
    }
    if (status == TB_STATUS_OK && count > 0 && (support == 0 || support > count)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "support: must be in [1, %zu] (the points that carry the body at "
                                "rest), got %zu",
                                count, support);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    size_t kept = 0;
    for (size_t j = 0; j < scene->contact_count; ++j) {
        kept += scene->contacts[j].body != id;
    }
    const size_t total = kept + count;
    tb__contact *contacts = malloc((total > 0 ? total : 1) * sizeof *contacts);
    if (contacts == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "%zu contact points", total);
    }
    size_t w = 0;
    for (size_t j = 0; j < scene->contact_count; ++j) {
        if (scene->contacts[j].body != id) {
            contacts[w++] = scene->contacts[j];
        }
    }
    for (size_t k = 0; k < count; ++k, ++w) {
        contacts[w].body = id;
        tb__shape_point_to_principal(&scene->mass_props[id], points[k].position, contacts[w].r);
        contacts[w].radius = points[k].radius;
        contacts[w].share = 1.0 / (double)support;
    }
    tb__contact *old = scene->contacts;
    const size_t old_count = scene->contact_count, old_capacity = scene->contact_capacity;
    scene->contacts = contacts;
    scene->contact_count = total;
    scene->contact_capacity = total;
    status = tb__scene_layout_states(scene, scene->body_count);
    if (status != TB_STATUS_OK) {
        scene->contacts = old;
        scene->contact_count = old_count;
        scene->contact_capacity = old_capacity;
        free(contacts);
        return status;
    }
    free(old);
    return TB_STATUS_OK;
}

static tb_status room(size_t needed, size_t capacity, tb_contact_point *out, size_t *out_count)
{
    if (out == NULL || out_count == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    return needed <= capacity ? TB_STATUS_OK : TB_STATUS_OUT_OF_RANGE;
}

tb_status tb_contact_points_box(const double size[3], tb_contact_point *out, size_t capacity,
                                size_t *out_count)
{
    tb_status status = room(8, capacity, out, out_count);
    if (status != TB_STATUS_OK || size == NULL) {
        return status != TB_STATUS_OK ? status : TB_STATUS_NULL_POINTER;
    }
    for (unsigned c = 0; c < 8; ++c) {
        for (int i = 0; i < 3; ++i) {
            out[c].position[i] = ((c >> i) & 1 ? 0.5 : -0.5) * size[i];
        }
        out[c].radius = 0.0;
    }
    *out_count = 8;
    return TB_STATUS_OK;
}

tb_status tb_contact_points_sphere(double radius, tb_contact_point *out, size_t capacity,
                                   size_t *out_count)
{
    tb_status status = room(1, capacity, out, out_count);
    if (status == TB_STATUS_OK) {
        memset(out, 0, sizeof *out);
        out[0].radius = radius;
        *out_count = 1;
    }
    return status;
}

tb_status tb_contact_points_capsule(double radius, double length, tb_contact_point *out,
                                    size_t capacity, size_t *out_count)
{
    tb_status status = room(2, capacity, out, out_count);
    if (status == TB_STATUS_OK) {
        memset(out, 0, 2 * sizeof *out);
        out[0].position[2] = -0.5 * length;
        out[1].position[2] = 0.5 * length;
        out[0].radius = out[1].radius = radius;
        *out_count = 2;
    }
    return status;
}

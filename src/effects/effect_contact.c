/* Contact between bodies: the geometry branch's pairs (contact/contact_pairs.h: broad phase,
 * narrow phase, a manifold of up to 4 points with a normal from A to B) turned into forces by the
 * shared normal law (contact/contact_law.h) and Coulomb friction. Each point's force acts on
 * both bodies at the same world point with opposite signs, so the effect conserves linear and
 * angular momentum to round-off. Friction here keeps no state: a regularised Coulomb law,
 * F_t = -mu(|v_t|) N v_t / sqrt(|v_t|^2 + v_reg^2), which slides at mu_k N but creeps under a
 * static load (docs/effects.md says what is left). */
#include "scene/scene_internal.h"

#include "contact/contact_law.h"
#include "contact/contact_pairs.h"
#include "effects/contact_events.h"
#include "core/detail.h"
#include "core/validate.h"
#include "effects/effect_contact_check.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

#define TB__CONTACT_COOKIE 0xc0c7
/* Pairs are found this far apart (m), so points appear before they touch, at zero force. */
#define TB__CONTACT_MARGIN 1e-3
/* Pairs handled per batch of the pass (a stack buffer). */
#define TB__CONTACT_BATCH 16
/* Below this tangential speed (m/s) friction fades linearly to zero: the regularisation. */
#define TB__FRICTION_REGULARISATION 1e-3

/* One manifold point of pair (a, b): the force on b is N n + friction, on a its opposite, both at
 * the point's world position. */
static void point_load(const tb__contact_params *contact, const tb_scene *scene,
                       const tb__pair_contact *pair, const tb__motion motion[2],
                       const tb__contact_point *point, double share, double *dydt)
{
    const tb__body *a = &scene->bodies[pair->body_a], *b = &scene->bodies[pair->body_b];
    const double *n = pair->manifold.normal;
    double arm_a[3], arm_b[3], v_a[3], v_b[3];
    for (int k = 0; k < 3; ++k) {
        arm_a[k] = point->position[k] - motion[0].x[k];
        arm_b[k] = point->position[k] - motion[1].x[k];
    }
    tb__point_velocity(&motion[0], arm_a, v_a);
    tb__point_velocity(&motion[1], arm_b, v_b);
    const double relative[3] = {v_b[0] - v_a[0], v_b[1] - v_a[1], v_b[2] - v_a[2]};
    const double approach = tb__v3_dot(relative, n);
    /* k = M_min omega^2 share and c = 2 zeta sqrt(k m_r share): one point between free bodies
     * is the law's oscillator at the reduced mass m_r, so its restitution is the user's */
    const double light = fmin(a->mass, b->mass);
    const double reduced = a->mass * b->mass / (a->mass + b->mass);
    const double omega = contact->omega * sqrt(light / reduced);
    const double N = tb__contact_normal_force(reduced * share, omega, contact->damping_ratio,
                                              point->depth, -approach);
    if (!(N > 0.0)) {
        return;
    }
    double tangent[3];
    for (int k = 0; k < 3; ++k) {
        tangent[k] = relative[k] - approach * n[k];
    }
    const double speed = tb__v3_norm(tangent);
    const double ratio = speed / contact->stribeck_velocity;
    const double mu = contact->kinetic_friction +
                      (contact->static_friction - contact->kinetic_friction) * exp(-ratio * ratio);
    const double scale =
        mu * N / sqrt(speed * speed + TB__FRICTION_REGULARISATION * TB__FRICTION_REGULARISATION);
    double f[3], minus[3];
    for (int k = 0; k < 3; ++k) {
        f[k] = N * n[k] - scale * tangent[k];
        minus[k] = -f[k];
    }
    tb__add_load(dydt, pair->body_b, arm_b, f);
    tb__add_load(dydt, pair->body_a, arm_a, minus);
}

static void pair_loads(const tb__contact_params *contact, const tb_scene *scene, const double *y,
                       const tb__pair_contact *pair, double *dydt)
{
    tb__motion motion[2];
    tb__body_motion(&scene->bodies[pair->body_a], y + TB_STATE_SIZE * pair->body_a, &motion[0]);
    tb__body_motion(&scene->bodies[pair->body_b], y + TB_STATE_SIZE * pair->body_b, &motion[1]);
    const double share = 1.0 / (double)pair->manifold.count;
    for (int j = 0; j < pair->manifold.count; ++j) {
        point_load(contact, scene, pair, motion, &pair->manifold.points[j], share, dydt);
    }
}

static int apply_contact(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                         double *dydt)
{
    (void)t;
    const tb__contact_params *contact = &effect->params.contact;
    tb__pair_contact batch[TB__CONTACT_BATCH];
    tb__contact_pairs_begin(contact->pairs, scene, y);
    size_t count;
    while ((count = tb__contact_pairs_next(contact->pairs, scene, y, batch, TB__CONTACT_BATCH)) >
           0) {
        for (size_t k = 0; k < count; ++k) {
            pair_loads(contact, scene, y, &batch[k], dydt);
        }
    }
    return 0;
}

/* M |r|^2 / I at the reach of body id's shape (the farthest corner of its world bounds at y from
 * the centre of mass), plus 1: how much lighter a point of the body's surface is than the body. */
static double lightness(const tb_scene *scene, const double *y, size_t id)
{
    double low[3], high[3];
    if (tb_scene_body_shape_bounds(scene, y, id, low, high) != TB_STATUS_OK) {
        return 1.0;
    }
    const double *x = y + TB_STATE_SIZE * id;
    double reach[3];
    for (int k = 0; k < 3; ++k) {
        reach[k] = fmax(fabs(low[k] - x[k]), fabs(high[k] - x[k]));
    }
    return scene->bodies[id].mass * tb__inverse_mass_at(&scene->bodies[id], reach);
}

/* The modes of the pairs the effect can form, bounded from its bodies: a point of stiffness
 * k <= M_min omega^2 between bodies whose inverse masses at the point sum to at most
 * 2 max(lightness) / M_min rings at up to omega a, a^2 = 2 max lightness, with damping ratio
 * zeta a (as the ground's rocking); the regularised friction decays at mu_s g a^2 / v_reg under
 * a load of the body's weight. */
static void contact_rate(const tb__effect *effect, const tb_scene *scene, const double *y,
                         tb__effect_rate *out)
{
    const tb__contact_params *contact = &effect->params.contact;
    *out = (tb__effect_rate){0.0, TB_ALL_BODIES, 0.0, TB_ALL_BODIES};
    double worst = 0.0;
    size_t body = TB_ALL_BODIES;
    for (size_t k = 0; k < contact->body_count; ++k) {
        const size_t id = contact->bodies[k];
        if (id < scene->body_count && tb__scene_body_collision_shape(scene, id) != NULL) {
            const double l = lightness(scene, y, id);
            if (l > worst) {
                worst = l;
                body = id;
            }
        }
    }
    if (body == TB_ALL_BODIES) {
        return;
    }
    const double a = sqrt(2.0 * worst), omega = contact->omega * a,
                 zeta = contact->damping_ratio * a;
    if (zeta > 1.0) {
        out->decay = omega * (zeta + sqrt(zeta * zeta - 1.0));
        out->decay_body = body;
    } else {
        out->oscillation = omega;
        out->oscillation_body = body;
    }
    const double friction =
        contact->static_friction * contact->gravity * a * a / TB__FRICTION_REGULARISATION;
    if (friction > out->decay) {
        out->decay = friction;
        out->decay_body = body;
    }
}

static void release_contact(tb__effect *effect)
{
    tb__contact_events_release(&effect->params.contact);
    tb__contact_pairs_destroy(effect->params.contact.pairs);
    free(effect->params.contact.bodies);
    effect->params.contact.pairs = NULL;
    effect->params.contact.bodies = NULL;
}

static const tb__effect_ops contact_ops = {
    .name = "contact",
    .apply = apply_contact,
    .couples_bodies = true,
    .conserves_momentum = true,
    .rate = contact_rate,
    .release = release_contact,
    .check_start = tb__contact_check_start,
    .event_gaps = tb__contact_event_gaps,          /* effect_contact_events.c */
    .adaptive_step_limit = tb__contact_step_limit, /* at least half the shortest push */
    .tunnel_step = tb__contact_tunnel_step,
};

tb_contact_def tb_contact_def_default(void)
{
    tb_contact_def def;
    memset(&def, 0, sizeof def);
    def.restitution = 0.3;
    def.static_friction = 0.6;
    def.kinetic_friction = 0.5;
    def.penetration = 8e-7;
    def.gravity = 9.81;
    def.stribeck_velocity = 0.01;
    def.internal_cookie = TB__CONTACT_COOKIE;
    return def;
}

static tb_status validate_contact(tb_scene *scene, const tb_contact_def *def)
{
    if (def->internal_cookie != TB__CONTACT_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_contact_def_default()");
    }
    char *detail = scene->detail;
    tb_status status = tb__validate_positive(detail, def->penetration, "penetration");
    if (status == TB_STATUS_OK) {
        status = tb__validate_positive(detail, def->gravity, "gravity");
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_positive(detail, def->stribeck_velocity, "stribeck_velocity");
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_nonnegative(detail, def->kinetic_friction, "kinetic_friction");
    }
    if (status == TB_STATUS_OK && !(def->restitution >= 0.0 && def->restitution <= 1.0)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "restitution: must be in [0, 1], got %g", def->restitution);
    }
    if (status == TB_STATUS_OK &&
        !(isfinite(def->static_friction) && def->static_friction >= def->kinetic_friction)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "static_friction: must be finite and >= kinetic_friction (%g), "
                                "got %g",
                                def->kinetic_friction, def->static_friction);
    }
    const double omega = status == TB_STATUS_OK ? sqrt(def->gravity / def->penetration) : 1.0;
    if (!(isfinite(omega) && omega > 0.0)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "penetration: %g m with gravity %g m/s^2 makes the contact's rate "
                                "sqrt(gravity / penetration) overflow or vanish",
                                def->penetration, def->gravity);
    }
    if (status == TB_STATUS_OK && def->bodies == NULL && def->body_count > 0) {
        status = tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "bodies is NULL (body_count %zu)",
                                def->body_count);
    }
    return status;
}

/* The ids the effect acts on: def's, or every body of the scene now. */
static tb_status copy_bodies(tb_scene *scene, const tb_contact_def *def, tb__contact_params *out)
{
    const bool all = def->bodies == NULL;
    out->body_count = all ? scene->body_count : def->body_count;
    out->every_body = all;
    out->bodies = malloc((out->body_count > 0 ? out->body_count : 1) * sizeof(size_t));
    if (out->bodies == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "%zu contact bodies",
                              out->body_count);
    }
    for (size_t k = 0; k < out->body_count; ++k) {
        out->bodies[k] = all ? k : def->bodies[k];
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_add_contact(tb_scene *scene, const tb_contact_def *def)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (def == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "def is NULL");
    }
    tb_status status = validate_contact(scene, def);
    tb__effect effect = {.ops = &contact_ops, .body = TB_ALL_BODIES};
    tb__contact_params *contact = &effect.params.contact;
    if (status == TB_STATUS_OK) {
        status = copy_bodies(scene, def, contact);
    }
    if (status == TB_STATUS_OK) {
        status = tb__contact_pairs_create(scene, contact->bodies, contact->body_count,
                                          TB__CONTACT_MARGIN, &contact->pairs, scene->detail);
    }
    /* after the pair finder, which checked the ids */
    if (status == TB_STATUS_OK) {
        status = tb__contact_check_shared_pairs(scene, &contact_ops, contact->bodies,
                                                contact->body_count);
    }
    if (status == TB_STATUS_OK) {
        status = tb__contact_events_create(scene, contact);
    }
    if (status == TB_STATUS_OK) {
        contact->omega = sqrt(def->gravity / def->penetration);
        contact->damping_ratio = tb__contact_damping_ratio(def->restitution);
        /* a pair rings at omega sqrt(M_light / m_reduced) <= omega sqrt(2) (apply_contact) */
        contact->push_duration =
            tb__contact_push_duration(contact->damping_ratio) / (sqrt(2.0) * contact->omega);
        contact->static_friction = def->static_friction;
        contact->kinetic_friction = def->kinetic_friction;
        contact->stribeck_velocity = def->stribeck_velocity;
        contact->gravity = def->gravity;
        status = tb__scene_push_effect(scene, &effect);
    }
    if (status != TB_STATUS_OK && def->internal_cookie == TB__CONTACT_COOKIE) {
        release_contact(&effect);
    }
    return status;
}

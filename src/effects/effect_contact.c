/* Contact between bodies: the geometry branch's pairs (contact/contact_pairs.h: broad phase,
 * narrow phase, a manifold of up to 4 points with a normal from A to B) turned into forces by the
 * shared normal law (contact/contact_law.h) and Coulomb friction. Each point's force acts on
 * both bodies at the same world point with opposite signs, so the effect conserves linear and
 * angular momentum to round-off. Friction is the ground's stick anchor at the points that hold
 * a slot of the effect's friction pool (effects/contact_friction.h), the memoryless law at the
 * others. */
#include "scene/scene_internal.h"

#include "contact/contact_law.h"
#include "contact/contact_pairs.h"
#include "effects/contact_events.h"
#include "core/detail.h"
#include "core/validate.h"
#include "effects/effect_contact_check.h"
#include "effects/contact_friction.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

#define TB__CONTACT_COOKIE 0xc0c7
/* Pairs are found this far apart (m), so points appear before they touch, at zero force. */
#define TB__CONTACT_MARGIN 1e-3
/* Pairs handled per batch of the pass (a stack buffer). */
#define TB__CONTACT_BATCH 16
/* Friction slots per body of the effect when the def leaves friction_points at 0. */
#define TB__FRICTION_POINTS_PER_BODY 6

/* A pair's two bodies as one point of its manifold sees them. */
typedef struct tb__pair_motion {
    tb__motion body[2];
    double light, reduced; /* kg: the lighter mass and the reduced mass */
} tb__pair_motion;

/* One manifold point of pair (a, b) holding friction slot `slot` (TB__NO_SLOT: none): the force
 * on b is N n + friction, on a its opposite, both at the point's world position. */
static void point_load(const tb__effect *effect, const tb__pair_contact *pair,
                       const tb__pair_motion *m, const tb__contact_point *point, double share,
                       size_t slot, const double *y, double *dydt)
{
    const tb__contact_params *contact = &effect->params.contact;
    const double *n = pair->manifold.normal;
    double arm_a[3], arm_b[3], v_a[3], v_b[3];
    for (int k = 0; k < 3; ++k) {
        arm_a[k] = point->position[k] - m->body[0].x[k];
        arm_b[k] = point->position[k] - m->body[1].x[k];
    }
    tb__point_velocity(&m->body[0], arm_a, v_a);
    tb__point_velocity(&m->body[1], arm_b, v_b);
    const double relative[3] = {v_b[0] - v_a[0], v_b[1] - v_a[1], v_b[2] - v_a[2]};
    const double approach = tb__v3_dot(relative, n);
    /* k = M_min omega^2 share and c = 2 zeta sqrt(k m_r share): one point between free bodies
     * is the law's oscillator at the reduced mass m_r, so its restitution is the user's */
    const double omega = contact->omega * sqrt(m->light / m->reduced);
    const double N = tb__contact_normal_force(m->reduced * share, omega, contact->damping_ratio,
                                              point->depth, -approach);
    if (!(N > 0.0)) {
        return; /* a slot held here relaxes (tb__friction_relax_all) */
    }
    double tangent[3], friction[3];
    for (int k = 0; k < 3; ++k) {
        tangent[k] = relative[k] - approach * n[k];
    }
    /* the spring sized as the normal one, k_t = M_min g s0 share, damped at ratio 1/2 at the
     * reduced mass */
    const double stiffness = m->light * share * contact->gravity * contact->bristle_stiffness;
    const double damping = sqrt(stiffness * m->reduced * share);
    const size_t k = effect->state_offset + TB__FRICTION_SLOT_STATES * slot;
    const bool held = slot != TB__NO_SLOT;
    tb__friction_force(contact, stiffness, damping, N, n, tangent, m->body[0].q,
                       held ? y + k : NULL, held ? dydt + k : NULL, friction);
    double f[3], minus[3];
    for (int i = 0; i < 3; ++i) {
        f[i] = N * n[i] + friction[i];
        minus[i] = -f[i];
    }
    tb__add_load(dydt, pair->body_b, arm_b, f);
    tb__add_load(dydt, pair->body_a, arm_a, minus);
}

static void pair_loads(const tb__effect *effect, const tb_scene *scene, const double *y,
                       const tb__pair_contact *pair, size_t *fresh, double *dydt)
{
    const tb__body *a = &scene->bodies[pair->body_a], *b = &scene->bodies[pair->body_b];
    tb__pair_motion m;
    tb__body_motion(a, y + TB_STATE_SIZE * pair->body_a, &m.body[0]);
    tb__body_motion(b, y + TB_STATE_SIZE * pair->body_b, &m.body[1]);
    m.light = fmin(a->mass, b->mass);
    m.reduced = a->mass * b->mass / (a->mass + b->mass);
    size_t slots[TB__MANIFOLD_POINTS];
    tb__friction_match(effect->params.contact.friction, pair, &m.body[0], fresh, slots);
    const double share = 1.0 / (double)pair->manifold.count;
    for (int j = 0; j < pair->manifold.count; ++j) {
        point_load(effect, pair, &m, &pair->manifold.points[j], share, slots[j], y, dydt);
    }
}

static int apply_contact(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                         double *dydt)
{
    (void)t;
    const tb__contact_params *contact = &effect->params.contact;
    tb__friction_relax_all(contact->friction, y + effect->state_offset,
                           dydt + effect->state_offset);
    tb__pair_contact batch[TB__CONTACT_BATCH];
    tb__contact_pairs_begin(contact->pairs, scene, y);
    size_t count, fresh = 0;
    while ((count = tb__contact_pairs_next(contact->pairs, scene, y, batch, TB__CONTACT_BATCH)) >
           0) {
        for (size_t k = 0; k < count; ++k) {
            pair_loads(effect, scene, y, &batch[k], &fresh, dydt);
        }
    }
    return 0;
}

/* M |r|^2 / I at the reach of body id's shape, plus 1: how much lighter a point of the body's
 * surface is than the body. The reach is the farthest corner of the shape's bounds in its own
 * frame (closed forms per type; a sphere's corner is sqrt 3 radii out, a margin the default
 * steps of ball scenes were measured with) from the centre of mass. It is fixed in the body, so
 * the bound does not change as the body turns: the world bounds' corner did (up to sqrt 3
 * farther for a tumbling die, so a default step chosen at the start was refused mid-throw). */
static double lightness(const tb_scene *scene, const double *y, size_t id)
{
    const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
    const double identity[TB__POSE_SIZE] = {0, 0, 0, 1, 0, 0, 0};
    double low[3], high[3], pose[TB__POSE_SIZE];
    tb__collision_shape_bounds(shape, identity, low, high); /* in the shape frame */
    tb__shape_pose(scene, y, id, pose);
    const double *x = y + TB_STATE_SIZE * id;
    double reach2 = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        double local[3], world[3];
        for (int k = 0; k < 3; ++k) {
            local[k] = (corner >> k) & 1 ? high[k] : low[k];
        }
        tb__q_rotate(world, pose + 3, local);
        for (int k = 0; k < 3; ++k) {
            world[k] += pose[k] - x[k];
        }
        reach2 = fmax(reach2, tb__v3_dot(world, world));
    }
    const double reach[3] = {sqrt(reach2), 0.0, 0.0};
    return scene->bodies[id].mass * tb__inverse_mass_at(&scene->bodies[id], reach);
}

/* The modes of the pairs the effect can form, bounded from its bodies: a point of stiffness
 * k <= M_min omega^2 between bodies whose inverse masses at the point sum to at most
 * 2 max(lightness) / M_min rings at up to omega a, a^2 = 2 max lightness, with damping ratio
 * zeta a (as the ground's rocking); the friction spring, k_t = M_min g s0 share damped at ratio
 * 1/2 at the reduced mass, at up to sqrt(g s0) a with ratio a / 2, and the anchor's slip
 * relaxes at TB__BRISTLE_MAX_RATE. A point that finds no slot has the regularised law, which
 * decays at mu_s g a^2 / v_reg under a load of the body's weight: counted too, since any point
 * may find the pool full. */
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
    const double a = sqrt(2.0 * worst);
    tb__effect_rate_add_damped_mode(out, contact->omega * a, contact->damping_ratio * a, body);
    if (contact->static_friction > 0.0) {
        tb__effect_rate_add_damped_mode(
            out, sqrt(contact->gravity * contact->bristle_stiffness) * a, 0.5 * a, body);
        tb__effect_rate_add_decay(out, TB__BRISTLE_MAX_RATE, body);
    }
    tb__effect_rate_add_decay(out, TB__BRISTLE_RELEASE_RATE, body);
    tb__effect_rate_add_decay(
        out, contact->static_friction * contact->gravity * a * a / contact->slip_velocity, body);
}

static void release_contact(tb__effect *effect)
{
    tb__contact_events_release(&effect->params.contact);
    tb__contact_pairs_destroy(effect->params.contact.pairs);
    tb__friction_pool_destroy(effect->params.contact.friction);
    effect->params.contact.friction = NULL;
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
    .owns_states = true,
    .post_step = tb__friction_post_step,
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
    def.presliding = 5e-7;
    def.internal_cookie = TB__CONTACT_COOKIE;
    return def;
}

/* Whether def's gravity is further from its default than its penetration (by their ratios):
 * the field a refused contact rate names. */
static bool far_from_default(const tb_contact_def *def)
{
    const tb_contact_def usual = tb_contact_def_default();
    return fabs(log(def->gravity / usual.gravity)) >=
           fabs(log(def->penetration / usual.penetration));
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
    if (!(isfinite(omega) && omega > 0.0 && omega <= TB__CONTACT_RATE_MAX)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "%s: penetration %g m with gravity %g m/s^2 makes the contact's "
                                "rate sqrt(gravity / penetration) %g rad/s (at most %g: an impact "
                                "of pi / rate no shorter than 3 ns)",
                                far_from_default(def) ? "gravity" : "penetration", def->penetration,
                                def->gravity, omega, TB__CONTACT_RATE_MAX);
    }
    if (status == TB_STATUS_OK && def->bodies == NULL && def->body_count > 0) {
        status = tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "bodies is NULL (body_count %zu)",
                                def->body_count);
    }
    /* before copy_bodies sizes its copy by body_count: the ids, checked in order, show a count
     * past the scene's by a repeat or an id out of range among the first body_count + 1 */
    if (status == TB_STATUS_OK && def->bodies != NULL) {
        status = tb__contact_pairs_check_ids(scene, def->bodies, def->body_count, detail);
    }
    return status;
}

/* The ids the effect acts on: def's, or every body of the scene now. */
static tb_status copy_bodies(tb_scene *scene, const tb_contact_def *def, tb__contact_params *out)
{
    const bool all = def->bodies == NULL;
    out->body_count = all ? scene->body_count : def->body_count;
    out->every_body = all;
    out->bodies = tb__malloc_array(out->body_count > 0 ? out->body_count : 1, sizeof(size_t));
    if (out->bodies == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "%zu contact bodies",
                              out->body_count);
    }
    for (size_t k = 0; k < out->body_count; ++k) {
        out->bodies[k] = all ? k : def->bodies[k];
    }
    return TB_STATUS_OK;
}

/* The friction spring's parameters are numbers (as the ground's: presliding 1e-310 m would make
 * s0 = mu_s / presliding infinite) and the pool fits in memory. */
static tb_status validate_friction(tb_scene *scene, const tb_contact_def *def)
{
    tb_status status = tb__validate_positive(scene->detail, def->presliding, "presliding");
    const double s0 = def->static_friction / def->presliding;
    if (status == TB_STATUS_OK &&
        (!isfinite(s0) || !isfinite(def->gravity * s0) || !isfinite(s0 / def->gravity))) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "presliding: %g m makes the friction spring's stiffness "
                                "static_friction / presliding (%g 1/m) or its rate under gravity "
                                "%g m/s^2 overflow",
                                def->presliding, s0, def->gravity);
    }
    size_t bytes;
    if (status == TB_STATUS_OK) {
        status = tb__validate_size_product(scene->detail, def->friction_points,
                                           TB__FRICTION_SLOT_STATES * sizeof(double),
                                           "friction_points", &bytes);
    }
    return status;
}

/* The friction pool: def's points, or TB__FRICTION_POINTS_PER_BODY per body, at least 1. */
static tb_status make_pool(tb_scene *scene, const tb_contact_def *def, tb__effect *effect)
{
    tb__contact_params *contact = &effect->params.contact;
    /* body_count ids were allocated, so 6 body_count does not overflow */
    const size_t bodies = contact->body_count > 0 ? contact->body_count : 1;
    const size_t slots =
        def->friction_points > 0 ? def->friction_points : TB__FRICTION_POINTS_PER_BODY * bodies;
    contact->friction = tb__friction_pool_create(slots, def->presliding);
    if (contact->friction == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "friction_points: %zu slots", slots);
    }
    effect->fixed_states = TB__FRICTION_SLOT_STATES * slots;
    effect->state_scale = def->presliding;
    /* per unit of the weight M_min share a point carries, as the ground's (ground_params) */
    contact->bristle_stiffness = def->static_friction / def->presliding;
    contact->bristle_damping = sqrt(contact->bristle_stiffness / def->gravity);
    /* The memoryless fallback's regularisation: its decay mu_s g a^2 / v_reg then stays within
     * the friction spring's own fastest mode (about sqrt(g mu_s / presliding) a^2 at the arms,
     * contact_rate), so a full pool costs no shorter step; 1.7 mm/s at the defaults. */
    contact->slip_velocity = fmax(TB__FRICTION_REGULARISATION,
                                  sqrt(def->static_friction * def->gravity * def->presliding));
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
    if (status == TB_STATUS_OK) {
        status = validate_friction(scene, def);
    }
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
    if (status == TB_STATUS_OK && !contact->every_body) {
        status = tb__contact_check_shapes(scene, contact->bodies, contact->body_count);
    }
    if (status == TB_STATUS_OK) {
        status = tb__contact_check_shared_pairs(scene, &contact_ops, contact->bodies,
                                                contact->body_count);
    }
    if (status == TB_STATUS_OK) {
        status = tb__contact_events_create(scene, contact);
    }
    if (status == TB_STATUS_OK) {
        status = make_pool(scene, def, &effect);
    }
    if (status == TB_STATUS_OK) {
        contact->omega = sqrt(def->gravity / def->penetration);
        contact->damping_ratio = tb__contact_damping_ratio(def->restitution);
        /* a pair rings at omega sqrt(M_light / m_reduced) <= omega sqrt(2) (apply_contact) */
        contact->push_duration =
            tb__contact_push_duration_for(def->restitution) / (sqrt(2.0) * contact->omega);
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

tb_status tb_scene_contact_friction_stats(const tb_scene *scene, size_t effect,
                                          tb_contact_friction_stats *out_stats)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_scene *writable = (tb_scene *)scene; /* the detail only */
    if (out_stats == NULL) {
        return tb__scene_fail(writable, TB_STATUS_NULL_POINTER, "out_stats is NULL");
    }
    if (effect >= scene->effect_count || scene->effects[effect].ops != &contact_ops) {
        return tb__scene_fail(writable, TB_STATUS_INVALID_ARGUMENT,
                              "effect: %zu is not a contact effect (the scene has %zu effects)",
                              effect, scene->effect_count);
    }
    *out_stats = *tb__friction_stats(scene->effects[effect].params.contact.friction);
    return TB_STATUS_OK;
}

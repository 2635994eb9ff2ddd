/* Contact between bodies: the pairs of contact/contact_pairs.h (broad and narrow phase, a
 * manifold of up to 4 points, normal from A to B) turned into forces by the shared normal law
 * (contact/contact_law.h) and Coulomb friction. Each point's force acts on both bodies at one
 * world point with opposite signs: linear and angular momentum are conserved to round-off.
 * Friction: the ground's stick anchor where a point holds a slot of the friction pool
 * (effects/contact_friction.h), the memoryless law elsewhere. */
#include "effects/effect_contact.h"

#include "contact/contact_law.h"
#include "contact/contact_pairs.h"
#include "effects/contact_events.h"
#include "core/detail.h"
#include "core/validate.h"
#include "effects/effect_contact_check.h"
#include "effects/contact_friction.h"
#include "effects/contact_pass_memo.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

#define TB__CONTACT_COOKIE 0xc0c7
/* Pairs handled per batch of the pass (a stack buffer). */
#define TB__CONTACT_BATCH 16
/* Friction slots per body of the effect when the def leaves friction_points at 0. */
#define TB__FRICTION_POINTS_PER_BODY 6

/* One manifold point of pair (a, b) holding friction slot `slot` (TB__NO_SLOT: none): the force
 * on b is N n + friction, on a its opposite, both at the point's world position. */
static void point_load(const tb__effect *effect, const tb_scene *scene,
                       const tb__pair_contact *pair, const tb__pair_motion *m,
                       const tb__contact_point *point, double share, size_t slot, const double *y,
                       double *dydt)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    const double *n = pair->manifold.normal;
    double arm_a[3], arm_b[3], v_a[3], v_b[3];
    for (int k = 0; k < 3; ++k) {
        arm_a[k] = point->position[k] - m->body[0]->x[k];
        arm_b[k] = point->position[k] - m->body[1]->x[k];
    }
    tb__point_velocity(m->body[0], arm_a, v_a);
    tb__point_velocity(m->body[1], arm_b, v_b);
    const double relative[3] = {v_b[0] - v_a[0], v_b[1] - v_a[1], v_b[2] - v_a[2]};
    const double approach = tb__v3_dot(relative, n);
    /* k = M_min omega^2 share, c = 2 zeta sqrt(k m_j): point j's dashpot pushes its part of the
     * effective mass at the centre of pressure (pair_masses): an off-centre hit keeps e */
    const double part = point->depth > 0.0 ? point->depth / m->load : 0.0;
    const double N =
        tb__contact_point_force(m->light * share * contact->omega * contact->omega,
                                m->normal * part, contact->damping_ratio, point->depth, -approach);
    if (!(N > 0.0)) {
        return; /* a slot held here relaxes (tb__friction_relax_all) */
    }
    double tangent[3], friction[3];
    for (int k = 0; k < 3; ++k) {
        tangent[k] = relative[k] - approach * n[k];
    }
    /* the spring sized as the normal one, k_t = M_min g s0 share, damped at ratio 1/2 at the
     * point's part of the tangential effective mass, or at m_r share where that is lighter:
     * the damping only keeps the spring from ringing, and is never more than it was */
    const double stiffness = m->light * share * contact->gravity * contact->bristle_stiffness;
    const double damping = sqrt(stiffness * fmin(m->tangential * part, m->reduced * share));
    const size_t k = effect->state_offset + TB__FRICTION_SLOT_STATES * slot;
    const bool held = slot != TB__NO_SLOT;
    tb__friction_force(contact, stiffness, damping, N, n, tangent, m->body[0]->q,
                       held ? y + k : NULL, held ? dydt + k : NULL, friction);
    double f[3], minus[3];
    for (int i = 0; i < 3; ++i) {
        f[i] = N * n[i] + friction[i];
        minus[i] = -f[i];
    }
    tb__add_body_load(scene, dydt, pair->body_b, arm_b, f);
    tb__add_body_load(scene, dydt, pair->body_a, arm_a, minus);
}

/* The dashpots are sized where they act: the touching points' centre of pressure p (their
 * positions weighted by depth, as their spring forces are) has the effective masses
 * 1/m = 1/M_a + 1/M_b + (r_a x u) . I_a^-1 (r_a x u) + (r_b x u) . I_b^-1 (r_b x u), r = p - x,
 * along the normal u = n and (the lightest) across it, and point j's dashpots push its part
 * d_j / sum d of them. One point touching: its own effective mass, so an off-centre hit is the
 * law's oscillator and keeps the restitution; points landing together (face on face): the mass
 * of the motion the load excites. Continuous as points come and go (a point enters at d = 0). */
static void pair_masses(const tb_scene *scene, const tb__pair_contact *pair, tb__pair_motion *m)
{
    const double *n = pair->manifold.normal;
    double centre[3] = {0.0, 0.0, 0.0};
    m->load = 0.0;
    for (int j = 0; j < pair->manifold.count; ++j) {
        const tb__contact_point *point = &pair->manifold.points[j];
        if (point->depth > 0.0) {
            m->load += point->depth;
            tb__v3_axpy(centre, point->depth, point->position);
        }
    }
    m->normal = m->tangential = 0.0;
    if (!(m->load > 0.0)) {
        return;
    }
    double along = 0.0, across = 0.0, t1[3], t2[3];
    tb__tangent_basis(n, t1, t2); /* once for both bodies */
    for (int k = 0; k < 2; ++k) {
        const tb__body *body = tb__body_constants(scene, k == 0 ? pair->body_a : pair->body_b);
        if (body->inv_mass == 0.0) {
            continue; /* a body without a state (a board): its terms are 0 exactly */
        }
        double arm[3];
        for (int i = 0; i < 3; ++i) {
            arm[i] = centre[i] / m->load - m->body[k]->x[i];
        }
        along += tb__inverse_mass_along(body, m->body[k], arm, n);
        across += tb__inverse_mass_across_basis(body, m->body[k], arm, t1, t2);
    }
    m->normal = 1.0 / along;
    m->tangential = 1.0 / across;
}

void tb__contact_pair_motion(const tb_scene *scene, const tb__pair_contact *pair,
                             tb__pair_motion *m)
{
    const tb__body *a = tb__body_constants(scene, pair->body_a);
    const tb__body *b = tb__body_constants(scene, pair->body_b);
    m->body[0] = tb__derivative_motion(scene, pair->body_a);
    m->body[1] = tb__derivative_motion(scene, pair->body_b);
    m->light = fmin(a->mass, b->mass);
    m->reduced = tb__reduced_mass(a->mass, b->mass);
    pair_masses(scene, pair, m);
}

static void pair_loads(const tb__effect *effect, const tb_scene *scene, const double *y,
                       const tb__pair_contact *pair, size_t *fresh, double *dydt)
{
    tb__pair_motion m;
    tb__contact_pair_motion(scene, pair, &m);
    size_t slots[TB__MANIFOLD_POINTS];
    tb__friction_match(tb__contact_of(effect)->friction, pair, m.body[0], fresh, slots);
    const double share = 1.0 / (double)pair->manifold.count;
    for (int j = 0; j < pair->manifold.count; ++j) {
        point_load(effect, scene, pair, &m, &pair->manifold.points[j], share, slots[j], y, dydt);
    }
}

static int apply_contact(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                         double *dydt)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    tb__friction_relax_all(contact->friction, scene, y + effect->state_offset,
                           dydt + effect->state_offset);
    size_t count, fresh = 0;
    const tb__pair_contact *kept;
    if (tb__pass_memo_at(contact->memo, scene, t, y, &kept, &count)) { /* the boundary's pass */
        for (size_t k = 0; k < count; ++k) {
            pair_loads(effect, scene, y, &kept[k], &fresh, dydt);
        }
        return 0;
    }
    tb__pair_contact batch[TB__CONTACT_BATCH];
    tb__contact_pairs_begin(contact->pairs, scene, t, y);
    while ((count = tb__contact_pairs_next(contact->pairs, scene, y, batch, TB__CONTACT_BATCH)) >
           0) {
        for (size_t k = 0; k < count; ++k) {
            pair_loads(effect, scene, y, &batch[k], &fresh, dydt);
        }
    }
    return 0;
}

/* How much lighter a point of body id's surface is than the body, its lightness M w for a
 * force at the point (w its inverse mass there): at most tb__lightness_at's at the farthest
 * corner of the shape's bounds in its own frame (closed forms per type), since for each
 * direction the inverse mass is a convex function of the point. The corners are fixed in the
 * body, so the bound does not change as the body turns: the world bounds' corners did (up to
 * sqrt 3 farther for a tumbling die, so a default step chosen at the start was refused
 * mid-throw). A sphere's normal passes through its centre c, so along the normal its points
 * weigh as c does (arm x n = c x n), and across it as its surface does, |c| + radius out (not
 * the bounds' corner, sqrt 3 radii). */
double tb__contact_lightness(const tb_scene *scene, const double *y, size_t id, bool normal)
{
    const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
    const tb__body *body = tb__body_constants(scene, id);
    const double identity[TB__POSE_SIZE] = {0, 0, 0, 1, 0, 0, 0};
    double low[3], high[3], pose[TB__POSE_SIZE];
    tb__collision_shape_bounds(shape, identity, low, high); /* in the shape frame */
    tb__shape_pose(scene, scene->time, y, id, pose);
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, id, &motion);
    const double *x = motion.x, *q = motion.q;
    const bool sphere = shape->type == TB_SHAPE_SPHERE;
    double most = 1.0;
    for (int corner = 0; corner < (sphere ? 1 : 8); ++corner) {
        double local[3], world[3], principal[3];
        for (int k = 0; k < 3; ++k) {
            local[k] = sphere ? 0.0 : (corner >> k) & 1 ? high[k] : low[k];
        }
        tb__q_rotate(world, pose + 3, local);
        for (int k = 0; k < 3; ++k) {
            world[k] += pose[k] - x[k];
        }
        tb__q_rotate_inverse(principal, q, world);
        const double reach[3] = {tb__v3_norm(world) + shape->radius, 0.0, 0.0};
        most = fmax(most, sphere && !normal ? body->mass * tb__inverse_mass_at(body, reach)
                                            : tb__lightness_at(body, principal));
    }
    return most;
}

/* Bounds over the effect's bodies: the two largest lightnesses along the normal and across it
 * (a pair's sum is at most theirs), the largest of the bodies that can touch at several points
 * at once (not spheres: a sphere's manifold has one point), and their count. */
typedef struct tb__contact_bounds {
    double normal[2], tangential[2]; /* largest first */
    double several_normal, several_tangential;
    size_t several, shaped, body; /* body: the lightest along the normal, to name */
} tb__contact_bounds;

static void keep_two(double top[2], double value)
{
    if (value > top[0]) {
        top[1] = top[0];
        top[0] = value;
    } else if (value > top[1]) {
        top[1] = value;
    }
}

static void contact_bounds(const tb__contact_params *contact, const tb_scene *scene,
                           const double *y, tb__contact_bounds *out)
{
    *out = (tb__contact_bounds){{0.0, 0.0}, {0.0, 0.0}, 1.0, 1.0, 0, 0, TB_ALL_BODIES};
    for (size_t k = 0; k < contact->body_count; ++k) {
        const size_t id = contact->bodies[k];
        const tb__collision_shape *shape =
            id < scene->body_count ? tb__scene_body_collision_shape(scene, id) : NULL;
        if (shape == NULL || tb__body_fixed(scene, id)) { /* no mass: the partner's alone */
            continue;
        }
        const double normal = tb__contact_lightness(scene, y, id, true);
        const double tangential = tb__contact_lightness(scene, y, id, false);
        if (normal > out->normal[0]) {
            out->body = id;
        }
        out->shaped += 1;
        keep_two(out->normal, normal);
        keep_two(out->tangential, tangential);
        if (shape->type != TB_SHAPE_SPHERE) {
            out->several += 1;
            out->several_normal = fmax(out->several_normal, normal);
            out->several_tangential = fmax(out->several_tangential, tangential);
        }
    }
}

/* The modes of the pairs the effect can form, bounded from its bodies (docs/contact.md,
 * "Stability"). A pair's point of stiffness k = M_min omega^2 share (shares summing to 1) between
 * bodies of lightness l_a, l_b along the normal rings at up to omega a, a^2 = l_a + l_b (the
 * inverse mass at a point is at most l_a / M_a + l_b / M_b). Its dashpot pushes its part of the
 * effective mass at the centre of pressure (pair_masses): one point is the law's oscillator, at
 * damping ratio zeta; several together damp the other modes up to zeta kappa,
 * kappa^2 = max(l_a, l_b) (the real decay rates are at most 2 zeta omega a kappa, from
 * x^T C x / x^T M x over the modes). The friction spring, k_t = M_min g s0 share damped at ratio
 * 1/2 for its part of the tangential effective mass (or m_r share, whichever is lighter), rings
 * at up to sqrt(g s0) a_t, with a_t^2 the sum across the normal, at ratio min(a_t, kappa_t) / 2
 * (the first bound holds for damping at m_r share, the second for the part); the anchor's slip
 * relaxes at
 * TB__BRISTLE_MAX_RATE. A point that finds no slot has the regularised law, which decays at
 * mu_s g a_t^2 / v_reg under a load of the body's weight: counted too, since any point may find
 * the pool full, unless the pool holds every point of every pair the bodies can form (up to 4
 * bodies at the default 6 slots per body). */
static void contact_rate(const tb__effect *effect, const tb_scene *scene, const double *y,
                         tb__effect_rate *out)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    *out = (tb__effect_rate){0.0, TB_ALL_BODIES, 0.0, TB_ALL_BODIES, 0.0};
    tb__contact_bounds b;
    contact_bounds(contact, scene, y, &b);
    if (b.body == TB_ALL_BODIES) {
        return;
    }
    const size_t body = b.body;
    const double a = sqrt(b.normal[0] + b.normal[1]);
    const double a_t2 = b.tangential[0] + b.tangential[1];
    const double kappa = b.several >= 2 ? sqrt(b.several_normal) : 1.0;
    const double kappa_t = b.several >= 2 ? sqrt(b.several_tangential) : 1.0;
    tb__effect_rate_add_damped_mode(out, contact->omega * a, contact->damping_ratio * kappa, body);
    if (contact->static_friction > 0.0) {
        tb__effect_rate_add_damped_mode(out,
                                        sqrt(contact->gravity * contact->bristle_stiffness * a_t2),
                                        0.5 * fmin(sqrt(a_t2), kappa_t), body);
        tb__effect_rate_add_decay(out, TB__BRISTLE_MAX_RATE, body);
    }
    tb__effect_rate_add_decay(out, TB__BRISTLE_RELEASE_RATE, body);
    const double pairs = 0.5 * (double)b.shaped * (double)(b.shaped - 1);
    if ((double)tb__friction_pool_slots(contact->friction) < TB__MANIFOLD_POINTS * pairs) {
        tb__effect_rate_add_decay(
            out, contact->static_friction * contact->gravity * a_t2 / contact->slip_velocity, body);
    }
}

static void release_contact(tb__effect *effect)
{
    tb__contact_events_release(tb__contact_of(effect));
    tb__contact_pairs_destroy(tb__contact_of(effect)->pairs);
    tb__friction_pool_destroy(tb__contact_of(effect)->friction);
    tb__contact_of(effect)->friction = NULL;
    tb__pass_memo_destroy(tb__contact_of(effect)->memo);
    tb__contact_of(effect)->memo = NULL;
    free(tb__contact_of(effect)->bodies);
    tb__contact_of(effect)->pairs = NULL;
    tb__contact_of(effect)->bodies = NULL;
}

static const tb__effect_stepping contact_stepping = {
    .event_gaps = tb__contact_event_gaps, /* effect_contact_events.c */
    .wake_gaps = tb__contact_wake_gaps,
    .wake_links = tb__contact_wake_links,
    .adaptive_step_limit = tb__contact_step_limit, /* at least half the shortest push */
    .tunnel_step = tb__contact_tunnel_step,
    .check_impacts = tb__contact_check_impacts,
    .post_step = tb__friction_post_step,
    .step_start = tb__friction_step_start,
    .restart = tb__friction_effect_restart,
    .check_shape = tb__contact_check_shape, /* a listed body keeps a shape it can be pushed by */
    .event_pairs = tb__contact_event_pairs, /* effect_contact_event_pairs.c */
    .impact_law = tb__contact_impact_law,
};

static void contact_state_owners(const tb__effect *effect, const tb_scene *scene,
                                 tb__coupling_visit visit, void *ctx)
{
    (void)scene;
    tb__friction_state_owners(tb__contact_of(effect)->friction, effect->state_offset, visit, ctx);
}

static const tb__effect_ops contact_ops = {
    .name = "contact",
    .apply = apply_contact,
    .couples_bodies = true,
    .conserves_momentum = true,
    .rate = contact_rate,
    .release = release_contact,
    .check_start = tb__contact_check_start,
    .owns_states = true,
    .stepping = &contact_stepping,
    .state_owners = contact_state_owners,
    .jacobian = tb__contact_jacobian, /* effect_contact_jacobian.c */
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
    if (status == TB_STATUS_OK) { /* NaN and infinities: NOT_FINITE, as every other field's */
        status = tb__validate_nonnegative(detail, def->restitution, "restitution");
    }
    if (status == TB_STATUS_OK && !(def->restitution <= 1.0)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "restitution: must be in [0, 1], got %.17g", def->restitution);
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_finite(detail, def->static_friction, "static_friction");
    }
    if (status == TB_STATUS_OK && !(def->static_friction >= def->kinetic_friction)) {
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
    /* a list given with its count forgotten: an effect that touches nothing, silently */
    if (status == TB_STATUS_OK && def->bodies != NULL && def->body_count == 0) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "body_count: 0 with a list of bodies (an effect that touches "
                                "nothing); bodies NULL is every body");
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
    if (status == TB_STATUS_OK) {
        status = tb__contact_check_friction_rate(scene, def->static_friction, def->gravity,
                                                 def->presliding);
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
    tb__contact_params *contact = tb__contact_of(effect);
    /* body_count ids were allocated, so 6 body_count does not overflow */
    const size_t bodies = contact->body_count > 0 ? contact->body_count : 1;
    const size_t slots =
        def->friction_points > 0 ? def->friction_points : TB__FRICTION_POINTS_PER_BODY * bodies;
    const tb_status status = tb__contact_check_friction_points(
        scene, def->friction_points, contact->bodies, contact->body_count);
    if (status != TB_STATUS_OK) {
        return status;
    }
    size_t ids = 0; /* 1 + the largest id: the pairs' bodies */
    for (size_t k = 0; k < contact->body_count; ++k) {
        ids = contact->bodies[k] >= ids ? contact->bodies[k] + 1 : ids;
    }
    contact->friction = tb__friction_pool_create(slots, ids, def->presliding);
    contact->memo = tb__pass_memo_create(contact->body_count, scene->slot_count);
    if (contact->friction == NULL || contact->memo == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "friction_points: %zu slots", slots);
    }
    effect->fixed_states = TB__FRICTION_SLOT_STATES * slots;
    effect->state_scale = def->presliding;
    /* per unit of the weight M_min share a point carries, as the ground's (ground_params) */
    contact->bristle_stiffness = def->static_friction / def->presliding;
    /* the memoryless fallback's regularisation (contact_friction.h) */
    contact->slip_velocity =
        tb__contact_slip_velocity(def->static_friction, def->gravity, def->presliding);
    return TB_STATUS_OK;
}

/* The scene idle (before the pair finder, the set checks and the start check run under the
 * step) and def's fields. */
static tb_status check_def(tb_scene *scene, const tb_contact_def *def)
{
    tb_status status = tb__scene_check_idle(scene, "adding an effect");
    if (status == TB_STATUS_OK) {
        status = validate_contact(scene, def);
    }
    return status == TB_STATUS_OK ? validate_friction(scene, def) : status;
}

/* The listed bodies' shapes: each present (a list given) and not too large for penetration. */
static tb_status check_listed_shapes(tb_scene *scene, const tb__contact_params *contact,
                                     double penetration)
{
    tb_status status = TB_STATUS_OK;
    if (!contact->every_body) {
        status = tb__contact_check_shapes(scene, contact->bodies, contact->body_count);
    }
    if (status == TB_STATUS_OK) {
        status =
            tb__contact_check_shape_sizes(scene, contact->bodies, contact->body_count, penetration);
    }
    return status;
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
    tb_status status = check_def(scene, def);
    tb__contact_params params = {.pairs = NULL}, *contact = &params;
    tb__effect effect = {.ops = &contact_ops, .body = TB_ALL_BODIES, .params = &params};
    if (status == TB_STATUS_OK) {
        status = copy_bodies(scene, def, contact);
    }
    if (status == TB_STATUS_OK) {
        status = tb__contact_pairs_create(scene, contact->bodies, contact->body_count,
                                          TB__CONTACT_MARGIN, &contact->pairs, scene->detail);
    }
    if (status == TB_STATUS_OK) { /* after the pair finder, which checked the ids */
        status = check_listed_shapes(scene, contact, def->penetration);
    }
    if (status == TB_STATUS_OK) {
        status = tb__contact_check_shared_pairs(scene, &contact_ops, contact->bodies,
                                                contact->body_count);
    }
    if (status == TB_STATUS_OK) {
        status = tb__contact_events_create(scene, contact);
    }
    if (status == TB_STATUS_OK) { /* no narrow phase inside a sleeping island */
        tb__contact_pairs_skip_asleep(contact->pairs, true);
        tb__contact_pairs_skip_asleep(contact->lookahead, true);
    }
    if (status == TB_STATUS_OK) {
        status = make_pool(scene, def, &effect);
    }
    if (status == TB_STATUS_OK) {
        contact->omega = sqrt(def->gravity / def->penetration);
        contact->damping_ratio = tb__contact_damping_ratio(def->restitution);
        /* a centred hit rings at omega sqrt(M_light / m_reduced) <= omega sqrt(2); a point off
         * the centre, lighter (pair_masses), rings faster and pushes for less: this floor of the
         * adaptive step limit is then longer than half its push, and CVODE's error control, not
         * the limit, resolves it (test_contact_damping: e within 0.05 % under Adams) */
        contact->push_duration =
            tb__contact_push_duration_for(def->restitution) / (sqrt(2.0) * contact->omega);
        contact->static_friction = def->static_friction;
        contact->kinetic_friction = def->kinetic_friction;
        contact->stribeck_velocity = def->stribeck_velocity;
        contact->gravity = def->gravity;
        status = tb__scene_push_effect(scene, &effect, sizeof params);
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
    *out_stats = *tb__friction_stats(tb__contact_of(&scene->effects[effect])->friction);
    return TB_STATUS_OK;
}

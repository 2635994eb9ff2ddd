/* A ground plane against the shapes of bodies without contact points (ground_shapes.h): the
 * plane is body A of a pair, infinitely heavy and at rest, so a pair's law (effect_contact.c) with
 * M_min = m_r = M, the body's mass: point j of the plane's manifold pushes with stiffness
 * M omega^2 / count and a dashpot at its part d_j / sum d of the effective mass at the points'
 * centre of pressure, and its friction is the contact's (the stick anchor of a pool slot, z in
 * the plane's frame, which is the world's). At rest on its points the body sinks by
 * M g / (M omega^2) = penetration, as on contact points. */
#include "effects/ground_shapes.h"

#include "effects/ground_shapes_internal.h"

#include "contact/contact_law.h"
#include "contact/contact_pairs.h"
#include "core/detail.h"
#include "core/validate.h"
#include "effects/contact_events.h"
#include "effects/contact_friction.h"
#include "effects/effect_contact_check.h"
#include "effects/friction_jacobian.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

/* The plane as body A: at rest at the origin, unturned (friction keys and z in the world). */
static const tb__motion plane_motion = {{0, 0, 0}, {1.0, 0.0, 0.0, 0.0}, {0, 0, 0}, {0, 0, 0}};

/* The body's load on its touching points: the sum of depths and the effective masses at their
 * centre of pressure (as effect_contact.c's pair_masses with an immovable A). */
typedef struct tb__plane_load {
    const tb__motion *motion;
    double mass, load, normal, tangential; /* kg, m, kg, kg */
} tb__plane_load;

static void plane_load(const tb__ground_params *ground, const tb__body *body,
                       const tb__contact_manifold *m, tb__plane_load *out)
{
    double centre[3] = {0.0, 0.0, 0.0};
    out->mass = body->mass;
    out->load = out->normal = out->tangential = 0.0;
    for (int j = 0; j < m->count; ++j) {
        if (m->points[j].depth > 0.0) {
            out->load += m->points[j].depth;
            tb__v3_axpy(centre, m->points[j].depth, m->points[j].position);
        }
    }
    if (!(out->load > 0.0)) {
        return;
    }
    double arm[3];
    for (int k = 0; k < 3; ++k) {
        arm[k] = centre[k] / out->load - out->motion->x[k];
    }
    out->normal = 1.0 / tb__inverse_mass_along(body, out->motion, arm, ground->normal);
    out->tangential = 1.0 / tb__inverse_mass_across_basis(body, out->motion, arm,
                                                          ground->tangent[0], ground->tangent[1]);
}

/* One manifold point's force on body id (z, dz: its slot's states, NULL for none). */
static void point_force(const tb__contact_params *law, const tb__ground_params *ground,
                        const tb__plane_load *m, const tb__contact_point *point, double share,
                        const double *z, double *dz, size_t slot, double *dydt)
{
    const double *n = ground->normal;
    double arm[3], velocity[3], tangent[3], friction[3], f[3];
    for (int k = 0; k < 3; ++k) {
        arm[k] = point->position[k] - m->motion->x[k];
    }
    tb__point_velocity(m->motion, arm, velocity);
    const double away = tb__v3_dot(velocity, n);
    const double part = point->depth > 0.0 ? point->depth / m->load : 0.0;
    const double N =
        tb__contact_point_force(m->mass * share * law->omega * law->omega, m->normal * part,
                                law->damping_ratio, point->depth, -away);
    if (!(N > 0.0)) {
        return; /* a slot held here relaxes (tb__friction_relax_all) */
    }
    for (int k = 0; k < 3; ++k) {
        tangent[k] = velocity[k] - away * n[k];
    }
    const double stiffness = m->mass * share * law->gravity * law->bristle_stiffness;
    const double damping = sqrt(stiffness * fmin(m->tangential * part, m->mass * share));
    tb__friction_force(law, stiffness, damping, N, n, tangent, plane_motion.q, z, dz, friction);
    for (int k = 0; k < 3; ++k) {
        f[k] = N * n[k] + friction[k];
    }
    tb__add_load(dydt, slot, arm, f); /* by the body's slot in y */
}

/* Body id's manifold against the plane at y within margin (0 points: apart, or no shape). */
static int plane_manifold(const tb__ground_params *ground, const tb_scene *scene, double t,
                          const double *y, size_t id, double margin, tb__pair_contact *out)
{
    const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
    out->body_a = out->body_b = id;  /* the pool's key: the pair (body, body) is asleep with it */
    out->piece_a = out->piece_b = 0; /* the body meets the plane as one manifold */
    out->manifold.count = 0;
    if (shape == NULL) { /* removed since the list was made */
        return 0;
    }
    double pose[TB__POSE_SIZE];
    tb__shape_pose(scene, t, y, id, pose);
    return tb__collide_plane(ground->normal, ground->offset, shape, pose, margin, &out->manifold);
}

static size_t pool_first_state(const tb__effect *effect, const tb_scene *scene)
{
    return effect->state_offset + effect->states_per_contact * scene->contact_count;
}

void tb__ground_shapes_state_owners(const tb__effect *effect, const tb_scene *scene,
                                    tb__coupling_visit visit, void *ctx)
{
    const tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    if (shapes != NULL && shapes->law.friction != NULL) {
        tb__friction_state_owners(shapes->law.friction, pool_first_state(effect, scene), visit,
                                  ctx);
    }
}

/* Body id pressing the plane at (t, y), as the derivative and its Jacobian both read it: its
 * manifold, its load and the friction slots its points hold (matched in body order, fresh counting
 * the slots taken so far). False for a body the plane does not meet, an asleep one (its slots stay
 * frozen: relax_all) and one clear of the plane. */
typedef struct pressing {
    tb__pair_contact pair;
    tb__plane_load m;
    size_t slots[TB__MANIFOLD_POINTS];
    double share; /* each point's part of the body's contact */
} pressing;

static bool presses(const tb__ground_params *ground, const tb_scene *scene, double t,
                    const double *y, size_t id, size_t *fresh, pressing *out)
{
    const tb__ground_shapes *shapes = ground->shapes;
    if (!tb__ground_shapes_meet(shapes, scene, id) || tb__body_asleep(scene, id) ||
        plane_manifold(ground, scene, t, y, id, TB__CONTACT_MARGIN, &out->pair) == 0) {
        return false;
    }
    out->m = (tb__plane_load){.motion = tb__derivative_motion(scene, id)};
    plane_load(ground, tb__body_constants(scene, id), &out->pair.manifold, &out->m);
    for (int j = 0; j < TB__MANIFOLD_POINTS; ++j) {
        out->slots[j] = TB__NO_SLOT;
    }
    if (shapes->law.friction != NULL && id < shapes->pool_bodies) {
        tb__friction_match(shapes->law.friction, &out->pair, &plane_motion, fresh, out->slots);
    }
    out->share = 1.0 / (double)out->pair.manifold.count;
    return true;
}

void tb__ground_shapes_apply(const tb__effect *effect, const tb_scene *scene, double t,
                             const double *y, double *dydt)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    const tb__ground_shapes *shapes = ground->shapes;
    const size_t first = pool_first_state(effect, scene);
    if (shapes->law.friction != NULL) {
        tb__friction_relax_all(shapes->law.friction, scene, y + first, dydt + first);
    }
    size_t fresh = 0;
    for (size_t id = 0; id < scene->body_count; ++id) {
        pressing b;
        if (!presses(ground, scene, t, y, id, &fresh, &b)) {
            continue;
        }
        for (int j = 0; j < b.pair.manifold.count; ++j) {
            const bool held = b.slots[j] != TB__NO_SLOT;
            const size_t s = first + TB__FRICTION_SLOT_STATES * (held ? b.slots[j] : 0);
            point_force(&shapes->law, ground, &b.m, &b.pair.manifold.points[j], b.share,
                        held ? y + s : NULL, held ? dydt + s : NULL, tb__body_slot(scene, id),
                        dydt);
        }
    }
}

/* Point j's analytic rows, as point_force (the plane's z is the world's: T = 1). */
static void point_rows(const tb_scene *scene, const tb__contact_params *law,
                       const tb__ground_params *ground, const tb__plane_load *m,
                       const tb__contact_point *point, double share, size_t id, size_t state,
                       const double *y, tb__jacobian_rows *rows)
{
    const double *n = ground->normal;
    tb__point_jacobian p = {.body_a = TB_WORLD, .body_b = id, .state_first = state};
    double velocity[3], tangent[3];
    for (int k = 0; k < 3; ++k) {
        p.arm_b[k] = point->position[k] - m->motion->x[k];
    }
    tb__point_velocity(m->motion, p.arm_b, velocity);
    const double away = tb__v3_dot(velocity, n);
    const double part = point->depth > 0.0 ? point->depth / m->load : 0.0;
    const double k_n = m->mass * share * law->omega * law->omega, mass = m->normal * part;
    const double N = tb__contact_point_force(k_n, mass, law->damping_ratio, point->depth, -away);
    if (!(N > 0.0)) {
        return; /* a slot held here relaxes */
    }
    double dN[2];
    tb__contact_point_force_derivatives(k_n, mass, law->damping_ratio, point->depth, -away, dN);
    for (int k = 0; k < 3; ++k) {
        tangent[k] = velocity[k] - away * n[k];
    }
    const double stiffness = m->mass * share * law->gravity * law->bristle_stiffness;
    const double damping = sqrt(stiffness * fmin(m->tangential * part, m->mass * share));
    const tb__friction_law friction = {law->static_friction, law->kinetic_friction,
                                       law->stribeck_velocity, law->slip_velocity};
    const double T[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
    tb__friction_jacobian fr;
    const tb__friction_jacobian *use = &fr;
    size_t count = 0;
    if (state == TB__NO_SLOT) {
        tb__slip_jacobian(&friction, N, tangent, &fr);
    } else if (law->static_friction > 0.0) {
        tb__anchor_jacobian(&friction, stiffness, damping, N, n, tangent, y + state, &fr);
        count = TB__FRICTION_SLOT_STATES;
    } else {
        use = NULL;
    }
    tb__contact_point_rows(n, dN[0], dN[1], use, &T[0][0], count, &p);
    tb__jacobian_add_point(rows, scene, &p);
}

void tb__ground_shapes_jacobian(const tb__effect *effect, const tb_scene *scene, double t,
                                const double *y, tb__jacobian_rows *rows)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    const tb__ground_shapes *shapes = ground->shapes;
    const size_t first = pool_first_state(effect, scene);
    if (shapes->law.friction != NULL) {
        tb__friction_relax_jacobian(shapes->law.friction, scene, first, rows);
    }
    size_t fresh = 0;
    for (size_t id = 0; id < scene->body_count; ++id) {
        pressing b;
        if (!presses(ground, scene, t, y, id, &fresh, &b)) {
            continue;
        }
        for (int j = 0; j < b.pair.manifold.count; ++j) {
            const size_t state = b.slots[j] != TB__NO_SLOT
                                     ? first + TB__FRICTION_SLOT_STATES * b.slots[j]
                                     : TB__NO_SLOT;
            point_rows(scene, &shapes->law, ground, &b.m, &b.pair.manifold.points[j], b.share, id,
                       state, y, rows);
        }
    }
}

void tb__ground_shapes_post_step(const tb__effect *effect, const tb_scene *scene, const double *y)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    const tb__ground_shapes *shapes = ground->shapes;
    tb__friction_pool *pool = shapes->law.friction;
    if (pool == NULL) {
        return;
    }
    tb__friction_boundary_begin(pool);
    size_t fresh = 0;
    for (size_t id = 0; id < scene->body_count; ++id) {
        if (!tb__ground_shapes_meet(shapes, scene, id)) {
            continue;
        }
        tb__pair_contact pair;
        if (id < shapes->pool_bodies && !tb__body_asleep(scene, id) &&
            plane_manifold(ground, scene, scene->time, y, id, TB__CONTACT_MARGIN, &pair) > 0) {
            tb__friction_hold(pool, &pair, &plane_motion, &fresh);
        }
    }
    tb__friction_boundary_end(pool, scene, y + pool_first_state(effect, scene), fresh);
}

void tb__ground_shapes_step_start(const tb__effect *effect, const tb_scene *scene, const double *y)
{
    const tb__friction_pool *pool = tb__ground_of(effect)->shapes->law.friction;
    if (pool != NULL && tb__friction_boundary_due(pool, scene->time)) {
        tb__ground_shapes_post_step(effect, scene, y); /* it links no islands */
    }
}

void tb__ground_shapes_restart(const tb__effect *effect, const tb_scene *scene, double t,
                               const double *y)
{
    tb__friction_pool *pool = tb__ground_of(effect)->shapes->law.friction;
    if (pool != NULL) {
        tb__friction_restart(pool, t, y + pool_first_state(effect, scene));
    }
}

/* The modes of a body on the plane, contact_rate's (effect_contact.c) for a pair whose A weighs
 * nothing in the bounds (lightness 0): the normal points ring at omega sqrt(l), l the body's
 * lightness along the normal, damped at zeta kappa with kappa = sqrt(l) for a shape that touches
 * at several points at once (every shape but a sphere); the friction spring rings at
 * sqrt(g s0 l_t) damped at min(sqrt(l_t), kappa_t) / 2; the anchors relax at the slip and release
 * rates; a point without a slot has the memoryless law's decay mu_s g l_t / v_reg. */
void tb__ground_shapes_rate(const tb__effect *effect, const tb_scene *scene, const double *y,
                            tb__effect_rate *out)
{
    const tb__ground_shapes *shapes = tb__ground_of(effect)->shapes;
    const tb__contact_params *law = &shapes->law;
    for (size_t id = 0; id < scene->body_count; ++id) {
        if (!tb__ground_shapes_meet(shapes, scene, id)) {
            continue;
        }
        const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
        const double l = tb__contact_lightness(scene, y, id, true);
        const double l_t = tb__contact_lightness(scene, y, id, false);
        const bool several = shape->type != TB_SHAPE_SPHERE;
        const double kappa = several ? sqrt(l) : 1.0, kappa_t = several ? sqrt(l_t) : 1.0;
        tb__effect_rate_add_damped_mode(out, law->omega * sqrt(l), law->damping_ratio * kappa, id);
        if (law->static_friction > 0.0) {
            tb__effect_rate_add_damped_mode(out, sqrt(law->gravity * law->bristle_stiffness * l_t),
                                            0.5 * fmin(sqrt(l_t), kappa_t), id);
            tb__effect_rate_add_decay(out, TB__BRISTLE_MAX_RATE, id);
        }
        tb__effect_rate_add_decay(out, TB__BRISTLE_RELEASE_RATE, id);
        if (law->friction == NULL || id >= shapes->pool_bodies ||
            tb__friction_pool_slots(law->friction) < shapes->slots_wanted) {
            tb__effect_rate_add_decay(
                out, law->static_friction * law->gravity * l_t / law->slip_velocity, id);
        }
    }
}

/* Whether the ground meets body id through its shape; if so the deepest of its manifold's
 * points at y within margin (m, -INFINITY for none) and how many touch (depth > 0). */
static bool deepest(const tb__ground_params *ground, const tb_scene *scene, const double *y,
                    size_t id, double margin, double *depth, int *touching)
{
    if (!tb__ground_shapes_meet(ground->shapes, scene, id)) {
        return false;
    }
    tb__pair_contact pair;
    plane_manifold(ground, scene, scene->time, y, id, margin, &pair);
    *depth = -INFINITY;
    *touching = 0;
    for (int j = 0; j < pair.manifold.count; ++j) {
        *depth = fmax(*depth, pair.manifold.points[j].depth);
        *touching += pair.manifold.points[j].depth > 0.0;
    }
    return true;
}

void tb__ground_shapes_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                                  double *gap)
{
    for (size_t id = 0; id < scene->body_count; ++id) {
        double depth;
        int touching;
        if (deepest(tb__ground_of(effect), scene, y, id, TB__EVENT_LOOKAHEAD, &depth, &touching)) {
            gap[id] = fmin(gap[id], -depth); /* the gap of the deepest point, continuous in y */
        }
    }
}

bool tb__ground_shape_touch(const tb__effect *effect, const tb_scene *scene, const double *y,
                            size_t id, double *depth, int *points)
{
    return deepest(tb__ground_of(effect), scene, y, id, 0.0, depth, points);
}

bool tb__ground_meets_shape(const tb__effect *effect, const tb_scene *scene, size_t id)
{
    return tb__ground_shapes_meet(tb__ground_of(effect)->shapes, scene, id);
}

size_t tb__ground_shapes_event_pairs(const tb__effect *effect, const tb_scene *scene,
                                     const double *y, tb__event_pair *out, size_t capacity,
                                     size_t total)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    for (size_t id = 0; id < scene->body_count; ++id) {
        tb__pair_contact pair;
        if (!tb__ground_shapes_meet(ground->shapes, scene, id) ||
            plane_manifold(ground, scene, scene->time, y, id, TB__EVENT_LOOKAHEAD, &pair) == 0) {
            continue;
        }
        const tb__contact_point *deepest = tb__manifold_deepest(&pair.manifold);
        tb__motion motion;
        tb__body_motion_at(scene, scene->time, y, id, &motion);
        double arm[3], velocity[3];
        for (int k = 0; k < 3; ++k) {
            arm[k] = deepest->position[k] - motion.x[k];
        }
        tb__point_velocity(&motion, arm, velocity);
        tb__event_pair found = {.body_a = id,
                                .body_b = TB_WORLD,
                                .gap = -deepest->depth,
                                .gap_rate = tb__v3_dot(velocity, ground->normal),
                                .share = tb__manifold_landing_share(&pair.manifold),
                                .gravity = ground->gravity};
        for (int k = 0; k < 3; ++k) {
            found.point[k] = deepest->position[k];
            found.normal[k] = -ground->normal[k]; /* from the body into the ground */
        }
        found.inverse_mass =
            tb__inverse_mass_along(tb__body_constants(scene, id), &motion, arm, ground->normal);
        if (total < capacity) {
            out[total] = found;
        }
        ++total;
    }
    return total;
}

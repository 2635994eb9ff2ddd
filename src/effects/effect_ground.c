/* Contact with a ground plane: the compliant normal law (contact/contact_law.h) and stick-anchor
 * friction at the bodies' contact points. Each point keeps a tangential deflection z, two
 * components in the plane, in the state after the bodies' (bristles() and docs/effects.md). */
#include "effects/effect_ground.h"

#include "contact/contact_law.h"
#include "core/detail.h"
#include "core/validate.h"
#include "effects/contact_events.h"
#include "effects/effect_contact_check.h"
#include "effects/ground_shapes.h"
#include "math/tb_math.h"

#include <string.h>

#define TB__GROUND_COOKIE 0x960d

/* Whether hypot(z[0], z[1]) <= cone surely, from the squares: |z|^2 rounds within 3 ulps and
 * hypot within a few (glibc: 1), so a square below cone^2 (1 - 1e-14) leaves the deflection at
 * most the cone, where bristles() needs no more of it (an anchor at rest, most of them). A cone
 * below 1e-140 (its square near underflow), or anything not finite, asks hypot. */
static bool inside_cone(const double z[2], double cone)
{
    return cone > 1e-140 && cone < 1e140 &&
           z[0] * z[0] + z[1] * z[1] <= cone * cone * (1.0 - 1e-14);
}

/* Friction at one point: writes dz and returns the friction force (N, tangent basis). A stick
 * anchor with plastic slip (docs/effects.md, "Friction"): z is the elastic deflection of a
 * tangential spring of stiffness k = m g s0 for the mass m the point carries and a dashpot
 * sqrt(k m_t), damping ratio 1/2 for the tangential effective mass m_t its dashpot pushes
 * (masses_at), whose force is capped at mu N. z grows with the tangential velocity until it
 * passes the static cone z_s = mu_s N / k; the excess relaxes at TB__BRISTLE_MAX_RATE r, so in a
 * slide at v it settles at v / r and r excess estimates the slip speed. mu falls from mu_s to
 * mu_k with that slip speed (Stribeck), not with the velocity: a presliding transient, however
 * fast, does not lower the cap, so a load below mu_s N is held whatever the release. At rest
 * dz = 0 exactly and the spring holds the load: no creep. */
static void bristles(const tb__ground_params *ground, double mass, double damping_mass, double N,
                     const double v_t[2], const double z[2], double dz[2], double friction[2])
{
    if (!(ground->static_friction > 0.0)) { /* frictionless */
        for (int k = 0; k < 2; ++k) {
            dz[k] = -TB__BRISTLE_RELEASE_RATE * z[k];
            friction[k] = 0.0;
        }
        return;
    }
    const double stiffness = mass * ground->gravity * ground->bristle_stiffness;
    const double damping = sqrt(stiffness * damping_mass);
    const double cone = ground->static_friction * N / stiffness;
    const double deflection = inside_cone(z, cone) ? 0.0 : hypot(z[0], z[1]);
    const double excess = deflection > cone ? deflection - cone : 0.0;
    const double slip = TB__BRISTLE_MAX_RATE * excess / ground->stribeck_velocity;
    /* exp(-0) is 1 exactly: a point inside its cone (at rest, most of them) skips the call */
    const double stribeck = slip == 0.0 ? 1.0 : exp(-slip * slip);
    const double mu =
        ground->kinetic_friction + (ground->static_friction - ground->kinetic_friction) * stribeck;
    double trial[2], magnitude = 0.0;
    for (int k = 0; k < 2; ++k) {
        trial[k] = -(stiffness * z[k] + damping * v_t[k]);
        magnitude += trial[k] * trial[k];
        dz[k] = v_t[k] - (excess > 0.0 ? TB__BRISTLE_MAX_RATE * excess * z[k] / deflection : 0.0);
    }
    magnitude = sqrt(magnitude);
    const double scale = magnitude > mu * N ? mu * N / magnitude : 1.0;
    friction[0] = scale * trial[0];
    friction[1] = scale * trial[1];
}

/* How far contact point c's sphere dips below the plane (m, negative above it); its lever
 * arm from the centre of mass goes into arm. */
double tb__ground_point_depth(const tb__ground_params *ground, const tb__contact *c,
                              const tb__motion *motion, double arm[3])
{
    tb__point_arm(motion, c->r, arm);
    const double height =
        tb__v3_dot(ground->normal, motion->x) + tb__v3_dot(ground->normal, arm) - ground->offset;
    return c->radius - height;
}

/* Points per body whose depth and arm the first pass keeps for the second (a stack buffer); a
 * body with more has them computed again. */
#define TB__GROUND_KEPT_POINTS 16

/* The load of body's points [first, end) at motion. The dashpots are sized where they act: point
 * j's pushes m_j = m_cp w_j / sum w, the effective mass at the centre of pressure shared by load.
 * One point touching: its own effective mass, so an end or corner landing keeps the restitution;
 * points landing together (a flat face, the two corners of a rod's end): the mass of the motion
 * the load excites, which for a face under the centre of mass is M share_j as before. m_j is
 * kept below max(M share_j, the point's own effective mass): unequal loads near the centre of
 * mass (a box rocking onto an edge) would otherwise load a point with more than either, and
 * overdamp its rocking. The friction dashpot's mass is kept below M share_j, as before. */
void tb__ground_body_load(const tb__ground_params *ground, const tb_scene *scene, size_t first,
                          size_t end, const tb__motion *motion, tb__point_place *kept,
                          tb__body_load *out)
{
    double moment[3] = {0.0, 0.0, 0.0}, arm[3];
    *out = (tb__body_load){0.0, 0.0, 0.0};
    for (size_t j = first; j < end; ++j) {
        const tb__contact *c = &scene->contacts[j];
        const double depth = tb__ground_point_depth(ground, c, motion, arm);
        if (kept != NULL) {
            kept[j - first] = (tb__point_place){depth, {arm[0], arm[1], arm[2]}};
        }
        if (depth > 0.0) {
            tb__v3_axpy(arm, -c->radius, ground->normal);
            out->total += c->share * depth;
            tb__v3_axpy(moment, c->share * depth, arm);
        }
    }
    if (!(out->total > 0.0)) {
        return;
    }
    const double centre[3] = {moment[0] / out->total, moment[1] / out->total,
                              moment[2] / out->total};
    const tb__body *body = tb__body_constants(scene, scene->contacts[first].body);
    out->normal = 1.0 / tb__inverse_mass_along(body, motion, centre, ground->normal);
    out->tangential = 1.0 / tb__inverse_mass_across_basis(body, motion, centre, ground->tangent[0],
                                                          ground->tangent[1]);
}

/* place: the point's depth and arm from body_load, or NULL to compute them */
static void contact(const tb__ground_params *ground, const tb_scene *scene, const tb__contact *c,
                    const tb__motion *motion, const tb__body_load *load,
                    const tb__point_place *place, const double *z, double *dz, double *dydt)
{
    const double *n = ground->normal, *t1 = ground->tangent[0], *t2 = ground->tangent[1];
    double arm[3];
    const double depth =
        place != NULL ? place->depth : tb__ground_point_depth(ground, c, motion, arm);
    if (place != NULL) {
        tb__v3_copy(arm, place->arm);
    }
    if (depth <= 0.0) {
        dz[0] = -TB__BRISTLE_RELEASE_RATE * z[0];
        dz[1] = -TB__BRISTLE_RELEASE_RATE * z[1];
        return;
    }
    tb__v3_axpy(arm, -c->radius, n); /* the sphere's lowest point touches */
    double velocity[3];
    tb__point_velocity(motion, arm, velocity);
    const tb__body *body = tb__body_constants(scene, c->body);
    const double mass = body->mass * c->share;
    const double part = c->share * depth / load->total; /* of the load, in (0, 1] */
    /* never heavier than M share, the mass the law had before, unless the point alone is */
    double dashpot = load->normal * part;
    if (dashpot > mass) {
        dashpot = fmin(dashpot, fmax(mass, 1.0 / tb__inverse_mass_along(body, motion, arm, n)));
    }
    const double N =
        tb__contact_point_force(mass * ground->omega * ground->omega, dashpot,
                                ground->damping_ratio, depth, -tb__v3_dot(n, velocity));
    const double v_t[2] = {tb__v3_dot(t1, velocity), tb__v3_dot(t2, velocity)};
    double friction[2];
    bristles(ground, mass, fmin(load->tangential * part, mass), N, v_t, z, dz, friction);
    double f[3];
    for (int k = 0; k < 3; ++k) {
        f[k] = N * n[k] + friction[0] * t1[k] + friction[1] * t2[k];
    }
    tb__add_body_load(scene, dydt, c->body, arm, f);
}

/* True when every point of the body's [first, end) is surely above the plane at motion, with
 * room for the rounding of point_depth: each point's centre is |r| from the centre of mass
 * whichever way the body is turned, so the depths need no rotation to be known negative (a
 * tumbling body above the floor, a die lying on a table). Their point_depth would be < 0: the
 * answer is contact()'s for depth <= 0 to the bit. */
bool tb__ground_body_clear(const tb__ground_params *ground, const tb_scene *scene, size_t first,
                           size_t end, const tb__motion *motion)
{
    const double centre = tb__v3_dot(ground->normal, motion->x);
    const double height = centre - ground->offset;
    for (size_t j = first; j < end; ++j) {
        const tb__contact *c = &scene->contacts[j];
        const double r2 = tb__v3_dot(c->r, c->r);
        const double room = height - c->radius -
                            1e-12 * (fabs(centre) + fabs(ground->offset) + c->radius + sqrt(r2));
        if (!(room > 0.0 && room * room > r2 * (1.0 + 1e-12))) {
            return false;
        }
    }
    return true;
}

static int apply_ground(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                        double *dydt)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    size_t first = 0;
    while (first < scene->contact_count) {
        const size_t body = scene->contacts[first].body, end = tb__ground_run_end(scene, first);
        if (tb__body_asleep(scene, body)) { /* its anchors stay frozen */
            memset(dydt + effect->state_offset + effect->states_per_contact * first, 0,
                   (end - first) * effect->states_per_contact * sizeof(double));
            first = end;
            continue;
        }
        const tb__motion *motion = tb__derivative_motion(scene, body);
        if (tb__ground_body_clear(ground, scene, first, end,
                                  motion)) { /* every z relaxes (contact()) */
            for (size_t k = effect->state_offset + effect->states_per_contact * first;
                 k < effect->state_offset + effect->states_per_contact * end; ++k) {
                dydt[k] = -TB__BRISTLE_RELEASE_RATE * y[k];
            }
            first = end;
            continue;
        }
        tb__body_load load;
        tb__point_place kept[TB__GROUND_KEPT_POINTS];
        const bool keep = end - first <= TB__GROUND_KEPT_POINTS;
        tb__ground_body_load(ground, scene, first, end, motion, keep ? kept : NULL, &load);
        for (size_t j = first; j < end; ++j) {
            const size_t k = effect->state_offset + effect->states_per_contact * j;
            contact(ground, scene, &scene->contacts[j], motion, &load,
                    keep ? &kept[j - first] : NULL, y + k, dydt + k, dydt);
        }
        first = end;
    }
    tb__ground_shapes_apply(effect, scene, t, y, dydt); /* bodies without points, by their shapes */
    return 0;
}

/* a^2: how much faster than bouncing the body rocks on its contact points. Rotating the body
 * by theta moves point j by theta x r_j, so the rotational stiffness is at most
 * sum k_j [r_j x]^T [r_j x] = sum k_j (|r_j|^2 1 - r_j r_j^T), the inertia tensor of point
 * masses k_j at the arms; against I_body its largest generalised eigenvalue, bounded by the
 * largest row sum of |I^-1/2 A I^-1/2| (Gershgorin), is a^2 omega0^2 with
 * A = M sum share_j (|r_j|^2 1 - r_j r_j^T) / sum share_j (the points carrying the body share
 * 1). Across the plane (normal false: friction) each arm reaches the point's sphere,
 * |r_j| + radius; along the normal the sphere's radius lies along n and turns nothing
 * (arm x n = r_j x n), so the arm is r_j. A box on its corners gives 3, a light body on wide
 * points ~1e2; bouncing alone gives 1. The body's points are contacts[first, end). *kappa2:
 * the largest lightness of a point (tb__lightness_at; with a sphere's radius across the normal
 * M (1/M + (|r_j| + radius)^2 / I_min)), 1 for a body with one point (ground_rate). */
static double rocking_factor(const tb_scene *scene, size_t first, size_t end, bool normal,
                             double *kappa2)
{
    double A[3][3] = {{0}}, shares = 0.0;
    for (size_t j = first; j < end; ++j) {
        const tb__contact *c = &scene->contacts[j];
        const double length = tb__v3_norm(c->r), reach = normal ? length : length + c->radius;
        const double scale = length > 0.0 ? reach / length : 0.0;
        const double r[3] = {c->r[0] * scale, c->r[1] * scale, c->r[2] * scale};
        for (int k = 0; k < 3; ++k) {
            for (int l = 0; l < 3; ++l) {
                A[k][l] += c->share * ((k == l ? reach * reach : 0.0) - r[k] * r[l]);
            }
        }
        shares += c->share;
    }
    const tb__body *b = tb__body_constants(scene, scene->contacts[first].body);
    double a2 = 1.0;
    for (int k = 0; k < 3; ++k) {
        double row = 0.0;
        for (int l = 0; l < 3; ++l) {
            row += fabs(A[k][l]) * sqrt(b->inv_moments[k] * b->inv_moments[l]);
        }
        a2 = fmax(a2, b->mass * row / shares);
    }
    *kappa2 = 1.0;
    for (size_t j = first; j < end && end - first > 1; ++j) {
        const tb__contact *c = &scene->contacts[j];
        const double arm[3] = {tb__v3_norm(c->r) + c->radius, 0.0, 0.0};
        *kappa2 = fmax(*kappa2, normal || c->radius == 0.0 ? tb__lightness_at(b, c->r)
                                                           : b->mass * tb__inverse_mass_at(b, arm));
    }
    return a2;
}

/* The modes of a body on its points (docs/contact.md, "Stability"): a point's stiffness is its
 * share of M g / penetration, so bouncing has omega0 = sqrt(g / penetration) and rocking
 * omega0 a. The dashpots push their parts of the effective mass at the centre of pressure
 * (body_load): one point is the law's oscillator at damping ratio zeta; several together damp
 * the other modes at up to zeta kappa, kappa^2 the largest lightness of a point (the real decay
 * rates are at most 2 zeta omega0 a kappa, from x^T C x / x^T M x). The friction spring of a
 * point, stiffness m g s0 damped at ratio 1/2 for its part of the tangential effective mass,
 * rings at sqrt(g s0) a_t with ratio kappa_t / 2 (a_t, kappa_t with the arms reaching the
 * points' spheres). The relaxation of a deflection beyond the cone (TB__BRISTLE_MAX_RATE) and a
 * lifted point's release are decaying modes of their own. */
static void ground_rate(const tb__effect *effect, const tb_scene *scene, const double *y,
                        tb__effect_rate *out)
{
    (void)y;
    const tb__ground_params *ground = tb__ground_of(effect);
    *out = (tb__effect_rate){0.0, TB_ALL_BODIES, 0.0, TB_ALL_BODIES, 0.0};
    const double omega0 = ground->omega;
    const double bristles = sqrt(ground->gravity * ground->bristle_stiffness);
    size_t first = 0;
    for (size_t j = 1; j <= scene->contact_count; ++j) {
        if (j < scene->contact_count && scene->contacts[j].body == scene->contacts[first].body) {
            continue;
        }
        const size_t body = scene->contacts[first].body;
        double kappa2, kappa2_t;
        const double a = sqrt(rocking_factor(scene, first, j, true, &kappa2));
        const double a_t = sqrt(rocking_factor(scene, first, j, false, &kappa2_t));
        (void)kappa2; /* the normal dashpots are capped at M share_j or one point's (body_load) */
        tb__effect_rate_add_damped_mode(out, omega0 * a, ground->damping_ratio * a, body);
        tb__effect_rate_add_damped_mode(out, bristles * a_t, 0.5 * fmin(a_t, sqrt(kappa2_t)), body);
        const double relaxation =
            ground->static_friction > 0.0 ? TB__BRISTLE_MAX_RATE : TB__BRISTLE_RELEASE_RATE;
        if (relaxation > out->decay) {
            out->decay = relaxation;
            out->decay_body = body;
        }
        first = j;
    }
    tb__ground_shapes_rate(effect, scene, y, out);
}

/* The gaps of the bodies' points (effect_contact_events.c), then of the shapes of the bodies
 * without points. */
static void ground_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                              double *gap, bool signs)
{
    tb__ground_event_gaps(effect, scene, y, gap, signs);
    tb__ground_shapes_event_gaps(effect, scene, y, gap);
}

static const tb__effect_stepping ground_stepping = {
    .event_gaps = ground_event_gaps,
    /* the shapes of bodies without points (effect_ground_shapes.c): their friction slots' map */
    .post_step = tb__ground_shapes_post_step,
    .step_start = tb__ground_shapes_step_start,
    .restart = tb__ground_shapes_restart,
    .check_shape = tb__ground_check_shape,
    .check_points = tb__ground_check_points,
    .uncheck_points = tb__ground_shapes_unnote,
    .shapes_changed = tb__ground_shapes_changed,
    .shapes_settled = tb__ground_shapes_settled,
    .event_pairs = tb__ground_event_pairs, /* effect_contact_event_pairs.c */
    .impact_law = tb__ground_impact_law,
};

/* Each point's deflection belongs to its body; then the shapes' friction slots. */
static void ground_state_owners(const tb__effect *effect, const tb_scene *scene,
                                tb__coupling_visit visit, void *ctx)
{
    for (size_t j = 0; j < scene->contact_count; ++j) {
        const size_t body = scene->contacts[j].body;
        visit(ctx, effect->state_offset + effect->states_per_contact * j,
              effect->states_per_contact, body, body);
    }
    tb__ground_shapes_state_owners(effect, scene, visit, ctx);
}

static const tb__effect_ops ground_ops = {
    .name = "ground",
    .apply = apply_ground,
    .couples_bodies = false,
    .owns_states = true,
    .rate = ground_rate,
    .check_start = tb__ground_check_start, /* effect_ground_check.c */
    .stepping = &ground_stepping,
    /* the list and pool of the shapes of bodies without points (effect_ground_shapes.c) */
    .release = tb__ground_shapes_release,
    .state_owners = ground_state_owners,
    .jacobian = tb__ground_jacobian, /* effect_ground_jacobian.c */
};

tb_ground_def tb_ground_def_default(void)
{
    tb_ground_def def;
    memset(&def, 0, sizeof def);
    def.normal[2] = 1.0;
    def.gravity = 9.81;
    def.penetration = 8e-7;
    def.restitution = 0.3;
    def.static_friction = 0.6;
    def.kinetic_friction = 0.5;
    def.stribeck_velocity = 0.01;
    def.presliding = 5e-7;
    def.internal_cookie = TB__GROUND_COOKIE;
    return def;
}

/* The contact's rates are numbers (F18: presliding 1e-310 m made the bristle stiffness
 * static_friction / presliding infinite, and the guard's largest stable step 0 s): bouncing
 * g / penetration, the bristles' stiffness and their g s0 and s0 / g (see ground_params); both
 * rates at most TB__CONTACT_RATE_MAX (F98, F107). */
static tb_status validate_ground_rates(tb_scene *scene, const tb_ground_def *def)
{
    if (!isfinite(def->gravity / def->penetration)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "penetration: %g m under gravity %g m/s^2 makes the contact's rate "
                              "g / penetration overflow",
                              def->penetration, def->gravity);
    }
    /* F98: the contact effect's bounds (F22), which the plane lacked: gravity 1e300 m/s^2 gave
     * omega 1e153 rad/s and a default step of 2e-154 s; 1e-300 over 1e300 m gave omega 0 */
    const double omega = sqrt(def->gravity / def->penetration);
    if (!(omega > 0.0 && omega <= TB__CONTACT_RATE_MAX)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "%s: penetration %g m with gravity %g m/s^2 makes the contact's "
                              "rate sqrt(gravity / penetration) %g rad/s (above 0 and at most "
                              "%g: an impact of pi / rate no shorter than 3 ns)",
                              fabs(log(def->gravity / 9.81)) >= fabs(log(def->penetration / 8e-7))
                                  ? "gravity"
                                  : "penetration",
                              def->penetration, def->gravity, omega, TB__CONTACT_RATE_MAX);
    }
    return tb__contact_check_friction_rate(scene, def->static_friction, def->gravity,
                                           def->presliding);
}

static tb_status validate_ground(tb_scene *scene, const tb_ground_def *def)
{
    if (def->internal_cookie != TB__GROUND_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_ground_def_default()");
    }
    char *detail = scene->detail;
    tb_status status = tb__validate_vector(detail, def->normal, "normal");
    double direction[3];
    if (status == TB_STATUS_OK && !tb__v3_direction(def->normal, direction)) {
        status =
            tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                           "normal: must be a direction (any nonzero length), got (%g, %g, %g)",
                           def->normal[0], def->normal[1], def->normal[2]);
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_finite(detail, def->offset, "offset");
    }
    const struct {
        double value;
        const char *name;
    } positive[] = {{def->gravity, "gravity"},
                    {def->penetration, "penetration"},
                    {def->stribeck_velocity, "stribeck_velocity"},
                    {def->presliding, "presliding"}},
      nonnegative[] = {{def->kinetic_friction, "kinetic_friction"}};
    for (size_t k = 0; k < 4 && status == TB_STATUS_OK; ++k) {
        status = tb__validate_positive(detail, positive[k].value, positive[k].name);
    }
    for (size_t k = 0; k < 1 && status == TB_STATUS_OK; ++k) {
        status = tb__validate_nonnegative(detail, nonnegative[k].value, nonnegative[k].name);
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
    return status == TB_STATUS_OK ? validate_ground_rates(scene, def) : status;
}

/* The typed parameters of a validated def. */
static void ground_params(const tb_ground_def *def, tb__ground_params *ground)
{
    tb__v3_direction(def->normal, ground->normal); /* validated: nonzero */
    /* an orthonormal basis of the plane, right-handed with n: tb__inverse_mass_across's */
    tb__tangent_basis(ground->normal, ground->tangent[0], ground->tangent[1]);
    ground->offset = def->offset;
    ground->gravity = def->gravity;
    ground->penetration = def->penetration;
    ground->omega = sqrt(def->gravity / def->penetration);
    ground->damping_ratio = tb__contact_damping_ratio(def->restitution);
    ground->push_units = tb__contact_push_duration_for(def->restitution);
    ground->static_friction = def->static_friction;
    ground->kinetic_friction = def->kinetic_friction;
    ground->stribeck_velocity = def->stribeck_velocity;
    /* Per unit of the mass m a point carries, times g: the spring k = m g s0 (the breakaway
     * deflection under the weight is presliding); its damper sqrt(k m_t) is sized at the
     * tangential effective mass m_t (body_load), a damping ratio of 1/2. Not 1: a flat body's
     * yaw mode on its corners is stiffer and more damped than one point, and overdamped its
     * fast eigenvalue would cost explicit methods a shorter step. */
    ground->bristle_stiffness = def->static_friction / def->presliding;
}

/* A second plane facing the same way (normals within 1e-6 rad) as an earlier one is either the
 * same plane again or buried in the other's ground: coincident, both push every point (twice the
 * stiffness, a restitution neither asked for, each event twice); buried, it pushes only what is
 * already deep in the other. */
static tb_status check_parallel(tb_scene *scene, const tb__ground_params *ground)
{
    for (size_t e = 0; e < scene->effect_count; ++e) {
        if (scene->effects[e].ops != &ground_ops) {
            continue;
        }
        const tb__ground_params *other = tb__ground_of(&scene->effects[e]);
        if (tb__v3_dot(other->normal, ground->normal) >= 1.0 - 5e-13) {
            return tb__scene_fail(
                scene, TB_STATUS_INVALID_ARGUMENT,
                "normal: (%g, %g, %g) faces the way effect %zu (a ground plane "
                "with normal (%g, %g, %g), offset %g m) faces: the two would push "
                "the same points twice (or one lies buried in the other's "
                "ground); give each direction one plane",
                ground->normal[0], ground->normal[1], ground->normal[2], e, other->normal[0],
                other->normal[1], other->normal[2], other->offset);
        }
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_add_ground(tb_scene *scene, const tb_ground_def *def)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (def == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "def is NULL");
    }
    /* before the checks that read the state under the step (the start depth) */
    tb_status status = tb__scene_check_idle(scene, "adding an effect");
    if (status == TB_STATUS_OK) {
        status = validate_ground(scene, def);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__ground_params ground;
    tb__effect effect = {.ops = &ground_ops,
                         .body = TB_ALL_BODIES,
                         .states_per_contact = 2,
                         .state_scale = def->presliding,
                         .params = &ground};
    ground_params(def, &ground);
    status = check_parallel(scene, &ground);
    if (status != TB_STATUS_OK) {
        return status;
    }
    status = tb__ground_shapes_create(scene, def, &effect);
    if (status == TB_STATUS_OK) {
        status = tb__ground_check_start(&effect, scene, scene->states, scene->detail);
    }
    if (status == TB_STATUS_OK) {
        status = tb__ground_shapes_check_sizes(&effect, scene);
    }
    if (status == TB_STATUS_OK) {
        status = tb__scene_push_effect(scene, &effect, sizeof ground);
    }
    if (status != TB_STATUS_OK) {
        tb__ground_shapes_release(&effect);
    }
    return status;
}

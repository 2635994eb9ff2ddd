/* Hooke springs with damping between two body points, or a body point and a world anchor. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <string.h>

#define TB__SPRING_COOKIE 0x5921

/* Points fixed in a body are offsets from its centre of mass in its principal frame (m). */
typedef struct tb__spring_params {
    size_t other;       /* the second body, or TB_WORLD */
    double point[3];    /* on the first body, principal frame */
    double anchor[3];   /* on the second body (principal frame) or in the world */
    double stiffness;   /* N/m */
    double damping;     /* N s/m */
    double rest_length; /* m */
} tb__spring_params;

static const tb__spring_params *spring_of(const tb__effect *effect)
{
    return effect->params;
}

/* An end of a spring: the point's lever arm from the centre of mass, its position and its
 * velocity (world). */
typedef struct spring_end {
    double arm[3], p[3], v[3];
} spring_end;

static void motion_end(const tb__motion *motion, const double r[3], spring_end *end)
{
    tb__point_arm(motion, r, end->arm);
    tb__point_velocity(motion, end->arm, end->v);
    for (int k = 0; k < 3; ++k) {
        end->p[k] = motion->x[k] + end->arm[k];
    }
}

/* The end at body point r of the dynamic body whose state is s (a per-body range's form). */
static void body_end(const tb__body *body, const double *s, const double r[3], spring_end *end)
{
    tb__motion motion;
    tb__body_motion(body, s, &motion);
    tb__point_arm(&motion, r, end->arm);
    tb__point_velocity(&motion, end->arm, end->v);
    for (int k = 0; k < 3; ++k) {
        end->p[k] = motion.x[k] + end->arm[k];
    }
}

/* The force on end a, f = -(k (l - l0) + c (v_a - v_b) . u) u along u = (p_a - p_b) / l; false
 * when the ends meet (no direction). */
static bool spring_force(const tb__spring_params *spring, const spring_end *a, const spring_end *b,
                         double f[3])
{
    const double d[3] = {a->p[0] - b->p[0], a->p[1] - b->p[1], a->p[2] - b->p[2]};
    const double length = tb__v3_norm(d);
    if (length == 0.0) {
        return false;
    }
    const double u[3] = {d[0] / length, d[1] / length, d[2] / length};
    const double relative[3] = {a->v[0] - b->v[0], a->v[1] - b->v[1], a->v[2] - b->v[2]};
    const double magnitude = -spring->stiffness * (length - spring->rest_length) -
                             spring->damping * tb__v3_dot(relative, u);
    tb__v3_set(f, magnitude * u[0], magnitude * u[1], magnitude * u[2]);
    return true;
}

/* A spring between a body point and a world anchor. */
static int apply_anchored_spring(const tb__effect *effect, const tb_scene *scene, double t,
                                 const double *y, double *dydt, size_t first, size_t count)
{
    (void)t;
    const tb__spring_params *spring = spring_of(effect);
    size_t i;
    if (!tb__local_body(effect->slot, first, count, &i)) {
        return 0;
    }
    spring_end a, anchor = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    body_end(&scene->bodies[effect->slot], y + TB_STATE_SIZE * i, spring->point, &a);
    tb__v3_copy(anchor.p, spring->anchor);
    double f[3];
    if (spring_force(spring, &a, &anchor, f)) {
        tb__add_load(dydt, i, a.arm, f);
    }
    return 0;
}

/* A spring between two body points (point on body, anchor on other). */
static int apply_spring(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                        double *dydt)
{
    const tb__spring_params *spring = spring_of(effect);
    spring_end a, b;
    tb__motion motion;
    tb__body_motion_at(scene, t, y, effect->body, &motion);
    motion_end(&motion, spring->point, &a);
    tb__body_motion_at(scene, t, y, spring->other, &motion);
    motion_end(&motion, spring->anchor, &b);
    double f[3];
    if (spring_force(spring, &a, &b, f)) {
        tb__add_body_load(scene, dydt, effect->body, a.arm, f);
        tb__v3_set(f, -f[0], -f[1], -f[2]);
        tb__add_body_load(scene, dydt, spring->other, b.arm, f);
    }
    return 0;
}

/* World position of a spring end: a body point (principal frame offset) or a world anchor. */
static void end_position(const tb_scene *scene, const double *y, size_t body, const double r[3],
                         double p[3])
{
    if (body == TB_WORLD) {
        tb__v3_copy(p, r);
        return;
    }
    tb__motion motion;
    double arm[3];
    tb__body_motion_at(scene, scene->time, y, body, &motion);
    tb__q_rotate(arm, motion.q, r);
    tb__v3_set(p, motion.x[0] + arm[0], motion.x[1] + arm[1], motion.x[2] + arm[2]);
}

/* k (|d| - rest)^2 / 2 (J). */
static double spring_potential_energy(const tb__effect *effect, const tb_scene *scene,
                                      const double *y)
{
    const tb__spring_params *spring = spring_of(effect);
    double a[3], b[3];
    end_position(scene, y, effect->body, spring->point, a);
    end_position(scene, y, spring->other, spring->anchor, b);
    const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    const double stretch = tb__v3_norm(d) - spring->rest_length;
    return 0.5 * spring->stiffness * stretch * stretch;
}

static bool spring_conserves_energy(const tb__effect *effect)
{
    return spring_of(effect)->damping == 0.0;
}

/* Along the spring the ends move as one mass of inverse w (the sum of the inverse masses at the
 * ends, rotation included): eigenvalues -c w / 2 +- sqrt((c w / 2)^2 - k w), so
 * |Im lambda| <= sqrt(k w) and the overdamped fast root is at most c w. */
static void spring_rate(const tb__effect *effect, const tb_scene *scene, const double *y,
                        tb__effect_rate *out)
{
    (void)y;
    const tb__spring_params *spring = spring_of(effect);
    double w = tb__inverse_mass_at(tb__body_constants(scene, effect->body), spring->point);
    if (spring->other != TB_WORLD) {
        w += tb__inverse_mass_at(tb__body_constants(scene, spring->other), spring->anchor);
    }
    *out = (tb__effect_rate){.oscillation = sqrt(spring->stiffness * w),
                             .oscillation_body = effect->body,
                             .decay = spring->damping > 0.0 ? spring->damping * w : 0.0,
                             .decay_body = effect->body};
}

static const tb__effect_ops anchored_spring_ops = {
    .name = "spring",
    .apply_bodies = apply_anchored_spring,
    .potential_energy = spring_potential_energy,
    .conserves_energy = spring_conserves_energy,
    .rate = spring_rate,
};

/* Two bodies joined by a spring sleep and wake together. */
static size_t spring_partner(const tb__effect *effect)
{
    return spring_of(effect)->other == TB_WORLD ? TB_ALL_BODIES : spring_of(effect)->other;
}

static const tb__effect_ops spring_ops = {
    .name = "spring",
    .apply = apply_spring,
    .couples_bodies = true,
    .conserves_momentum = true, /* equal and opposite forces along the line of their points */
    .potential_energy = spring_potential_energy,
    .conserves_energy = spring_conserves_energy,
    .rate = spring_rate,
    .sleep_partner = spring_partner,
};

tb_spring_def tb_spring_def_default(void)
{
    tb_spring_def def;
    memset(&def, 0, sizeof def);
    def.body_b = TB_WORLD;
    def.internal_cookie = TB__SPRING_COOKIE;
    return def;
}

static tb_status validate(tb_scene *scene, const tb_spring_def *def)
{
    if (def->internal_cookie != TB__SPRING_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_spring_def_default()");
    }
    tb_status status = tb__scene_check_id(scene, def->body_a, "body_a");
    if (status == TB_STATUS_OK && def->body_b != TB_WORLD) {
        status = tb__scene_check_id(scene, def->body_b, "body_b");
    }
    if (status == TB_STATUS_OK && def->body_b == def->body_a) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "body_b: a spring needs two different bodies, got %zu twice",
                                def->body_a);
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_vector(scene->detail, def->point_a, "point_a");
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_vector(scene->detail, def->point_b, "point_b");
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_nonnegative(scene->detail, def->stiffness, "stiffness");
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_nonnegative(scene->detail, def->damping, "damping");
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_nonnegative(scene->detail, def->rest_length, "rest_length");
    }
    return status;
}

/* A point so far from its body's centre of mass (6e246 m) that the inverse mass at it, and so
 * the spring's rate, overflow: no step could be judged stable. Refused, naming the point. */
static tb_status check_rate(tb_scene *scene, const tb__effect *effect, const tb_spring_def *def)
{
    tb__effect_rate rate;
    spring_rate(effect, scene, scene->states, &rate);
    if (isfinite(rate.oscillation) && isfinite(rate.decay)) {
        return TB_STATUS_OK;
    }
    const tb__spring_params *spring = spring_of(effect);
    const bool a_far =
        !isfinite(tb__inverse_mass_at(tb__body_constants(scene, effect->body), spring->point));
    const bool b_far =
        spring->other != TB_WORLD &&
        !isfinite(tb__inverse_mass_at(tb__body_constants(scene, spring->other), spring->anchor));
    if (!a_far && !b_far) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "stiffness: %g N/m with damping %g N s/m makes the spring's rate "
                              "overflow",
                              spring->stiffness, spring->damping);
    }
    const double *p = a_far ? def->point_a : def->point_b;
    return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                          "%s: (%g, %g, %g) m is so far from the body's centre of mass that the "
                          "inverse mass there, and the spring's rate, overflow",
                          a_far ? "point_a" : "point_b", p[0], p[1], p[2]);
}

tb_status tb_scene_add_spring(tb_scene *scene, const tb_spring_def *def)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (def == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "def is NULL");
    }
    tb_status status = validate(scene, def);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const bool anchored = def->body_b == TB_WORLD;
    tb__spring_params params;
    const tb__effect effect = {.ops = anchored ? &anchored_spring_ops : &spring_ops,
                               .body = def->body_a,
                               .params = &params};
    tb__spring_params *spring = &params;
    spring->other = def->body_b;
    tb__shape_point_to_principal(&scene->mass_props[def->body_a], def->point_a, spring->point);
    if (anchored) {
        tb__v3_copy(spring->anchor, def->point_b);
    } else {
        tb__shape_point_to_principal(&scene->mass_props[def->body_b], def->point_b, spring->anchor);
    }
    spring->stiffness = def->stiffness;
    spring->damping = def->damping;
    spring->rest_length = def->rest_length;
    status = check_rate(scene, &effect, def);
    if (status != TB_STATUS_OK) {
        return status;
    }
    return tb__scene_push_effect(scene, &effect, sizeof params);
}

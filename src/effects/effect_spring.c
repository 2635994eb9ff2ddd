/* Hooke springs with damping between two body points, or a body point and a world anchor. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <string.h>

#define TB__SPRING_COOKIE 0x5921

/* An end of a spring: the point's lever arm from the centre of mass, its position and its
 * velocity (world). */
typedef struct spring_end {
    double arm[3], p[3], v[3];
} spring_end;

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

/* param[0..2]: stiffness, damping, rest length. The force on end a, f = -(k (l - l0) + c
 * (v_a - v_b) . u) u along u = (p_a - p_b) / l; false when the ends meet (no direction). */
static bool spring_force(const tb__effect *effect, const spring_end *a, const spring_end *b,
                         double f[3])
{
    const double d[3] = {a->p[0] - b->p[0], a->p[1] - b->p[1], a->p[2] - b->p[2]};
    const double length = tb__v3_norm(d);
    if (length == 0.0) {
        return false;
    }
    const double u[3] = {d[0] / length, d[1] / length, d[2] / length};
    const double relative[3] = {a->v[0] - b->v[0], a->v[1] - b->v[1], a->v[2] - b->v[2]};
    const double magnitude = -effect->param[0] * (length - effect->param[2]) -
                             effect->param[1] * tb__v3_dot(relative, u);
    tb__v3_set(f, magnitude * u[0], magnitude * u[1], magnitude * u[2]);
    return true;
}

/* A spring between a body point (point, principal frame) and a world anchor (other_point). */
static int apply_anchored_spring(const tb__effect *effect, const tb_scene *scene, double t,
                                 const double *y, double *dydt, size_t first, size_t count)
{
    (void)t;
    size_t i;
    if (!tb__local_body(effect->body, first, count, &i)) {
        return 0;
    }
    spring_end a, anchor = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    body_end(&scene->bodies[effect->body], y + TB_STATE_SIZE * i, effect->point, &a);
    tb__v3_copy(anchor.p, effect->other_point);
    double f[3];
    if (spring_force(effect, &a, &anchor, f)) {
        tb__add_load(dydt, i, a.arm, f);
    }
    return 0;
}

/* A spring between two body points (point on body, other_point on other). */
static int apply_spring(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                        double *dydt)
{
    (void)t;
    spring_end a, b;
    body_end(&scene->bodies[effect->body], y + TB_STATE_SIZE * effect->body, effect->point, &a);
    body_end(&scene->bodies[effect->other], y + TB_STATE_SIZE * effect->other, effect->other_point,
             &b);
    double f[3];
    if (spring_force(effect, &a, &b, f)) {
        tb__add_load(dydt, effect->body, a.arm, f);
        tb__v3_set(f, -f[0], -f[1], -f[2]);
        tb__add_load(dydt, effect->other, b.arm, f);
    }
    return 0;
}

tb_spring_def tb_spring_def_default(void)
{
    tb_spring_def def;
    memset(&def, 0, sizeof def);
    def.body_b = TB_WORLD;
    def.internal_cookie = TB__SPRING_COOKIE;
    return def;
}

static tb_status check_point(tb_scene *scene, const double p[3], const char *what)
{
    if (!tb__all_finite(p, 3)) {
        return tb__scene_fail(scene, TB_STATUS_NOT_FINITE, "%s: contains NaN or infinity", what);
    }
    return TB_STATUS_OK;
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
        status = check_point(scene, def->point_a, "point_a");
    }
    if (status == TB_STATUS_OK) {
        status = check_point(scene, def->point_b, "point_b");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_coefficient(scene, def->stiffness, "stiffness");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_coefficient(scene, def->damping, "damping");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_coefficient(scene, def->rest_length, "rest_length");
    }
    return status;
}

tb_status tb_scene_add_spring(tb_scene *scene, const tb_spring_def *def)
{
    if (scene == NULL || def == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    tb_status status = validate(scene, def);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__effect effect = {.kind = TB__SPRING, .body = def->body_a, .other = def->body_b};
    if (def->body_b == TB_WORLD) {
        effect.apply_bodies = apply_anchored_spring;
    } else {
        effect.apply = apply_spring;
    }
    tb__shape_point_to_principal(&scene->mass_props[def->body_a], def->point_a, effect.point);
    if (def->body_b == TB_WORLD) {
        tb__v3_copy(effect.other_point, def->point_b);
    } else {
        tb__shape_point_to_principal(&scene->mass_props[def->body_b], def->point_b,
                                     effect.other_point);
    }
    effect.param[0] = def->stiffness;
    effect.param[1] = def->damping;
    effect.param[2] = def->rest_length;
    return tb__scene_push_effect(scene, &effect);
}

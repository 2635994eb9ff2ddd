/* Hooke springs with damping between two body points, or a body point and a world anchor. */
#include "scene_internal.h"

#include "detail.h"
#include "tb_math.h"

#include <string.h>

#define TB__SPRING_COOKIE 0x5921

/* param[0..2]: stiffness, damping, rest length. point / other_point: principal-frame offsets
 * of the ends (other_point is the world anchor when other == TB_WORLD). */
static int apply_spring(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                        double *dydt)
{
    (void)t;
    tb__motion a, b;
    double arm_a[3], arm_b[3] = {0, 0, 0}, p_a[3], p_b[3], v_a[3], v_b[3] = {0, 0, 0};
    tb__body_motion(scene, y, effect->body, &a);
    tb__point_arm(&a, effect->point, arm_a);
    tb__point_velocity(&a, arm_a, v_a);
    for (int k = 0; k < 3; ++k) {
        p_a[k] = a.x[k] + arm_a[k];
    }
    if (effect->other == TB_WORLD) {
        tb__v3_copy(p_b, effect->other_point);
    } else {
        tb__body_motion(scene, y, effect->other, &b);
        tb__point_arm(&b, effect->other_point, arm_b);
        tb__point_velocity(&b, arm_b, v_b);
        for (int k = 0; k < 3; ++k) {
            p_b[k] = b.x[k] + arm_b[k];
        }
    }
    const double d[3] = {p_a[0] - p_b[0], p_a[1] - p_b[1], p_a[2] - p_b[2]};
    const double length = tb__v3_norm(d);
    if (length == 0.0) {
        return 0; /* no direction: no force */
    }
    const double u[3] = {d[0] / length, d[1] / length, d[2] / length};
    const double relative[3] = {v_a[0] - v_b[0], v_a[1] - v_b[1], v_a[2] - v_b[2]};
    const double magnitude = -effect->param[0] * (length - effect->param[2]) -
                             effect->param[1] * tb__v3_dot(relative, u);
    double f[3] = {magnitude * u[0], magnitude * u[1], magnitude * u[2]};
    tb__add_load(dydt, effect->body, arm_a, f);
    if (effect->other != TB_WORLD) {
        tb__v3_set(f, -f[0], -f[1], -f[2]);
        tb__add_load(dydt, effect->other, arm_b, f);
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
    tb__effect effect = {
        .apply = apply_spring, .kind = TB__SPRING, .body = def->body_a, .other = def->body_b};
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

/* Drag: F = -(b + c |v|) v on the centre-of-mass velocity, tau = -(b_w + c_w |omega|) omega. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <string.h>

#define TB__DRAG_COOKIE 0xd7a6

/* param[0..3]: linear, quadratic, angular, angular_quadratic. s and d: the body's states and
 * their derivatives. */
static void drag_body(const tb__effect *effect, const tb__body *body, const double *s, double *d)
{
    const double v[3] = {s[7] * body->inv_mass, s[8] * body->inv_mass, s[9] * body->inv_mass};
    tb__v3_axpy(d + 7, -(effect->param[0] + effect->param[1] * tb__v3_norm(v)), v);
    if (effect->param[2] != 0.0 || effect->param[3] != 0.0) {
        double omega[3];
        tb__angular_velocity(body, s, omega);
        tb__v3_axpy(d + 10, -(effect->param[2] + effect->param[3] * tb__v3_norm(omega)), omega);
    }
}

static int apply_drag(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                      double *dydt, size_t first, size_t count)
{
    (void)t;
    const tb__body *bodies = scene->bodies + first;
    size_t i;
    if (effect->body != TB_ALL_BODIES) {
        if (tb__local_body(effect->body, first, count, &i)) {
            drag_body(effect, &bodies[i], y + TB_STATE_SIZE * i, dydt + TB_STATE_SIZE * i);
        }
        return 0;
    }
    for (i = 0; i < count; ++i) {
        drag_body(effect, &bodies[i], y + TB_STATE_SIZE * i, dydt + TB_STATE_SIZE * i);
    }
    return 0;
}

tb_drag_def tb_drag_def_default(void)
{
    tb_drag_def def;
    memset(&def, 0, sizeof def);
    def.body = TB_ALL_BODIES;
    def.internal_cookie = TB__DRAG_COOKIE;
    return def;
}

tb_status tb__check_coefficient(tb_scene *scene, double value, const char *what)
{
    if (!(value >= 0) || !isfinite(value)) {
        return tb__scene_fail(scene,
                              isfinite(value) ? TB_STATUS_INVALID_ARGUMENT : TB_STATUS_NOT_FINITE,
                              "%s: must be finite and >= 0, got %g", what, value);
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_add_drag(tb_scene *scene, const tb_drag_def *def)
{
    if (scene == NULL || def == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    if (def->internal_cookie != TB__DRAG_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_drag_def_default()");
    }
    tb_status status =
        def->body == TB_ALL_BODIES ? TB_STATUS_OK : tb__scene_check_id(scene, def->body, "body");
    const double values[4] = {def->linear, def->quadratic, def->angular, def->angular_quadratic};
    static const char *const names[4] = {"linear", "quadratic", "angular", "angular_quadratic"};
    for (int k = 0; k < 4 && status == TB_STATUS_OK; ++k) {
        status = tb__check_coefficient(scene, values[k], names[k]);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__effect effect = {.apply_bodies = apply_drag, .kind = TB__DRAG, .body = def->body};
    memcpy(effect.param, values, sizeof values);
    return tb__scene_push_effect(scene, &effect);
}

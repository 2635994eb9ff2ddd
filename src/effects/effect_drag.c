/* Drag: F = -(b + c |v|) v on the centre-of-mass velocity, tau = -(b_w + c_w |omega|) omega. */
#include "effects/effect_drag.h"

#include "core/detail.h"
#include "core/validate.h"
#include "effects/effect_lanes.h"
#include "math/tb_math.h"

#include <string.h>

#define TB__DRAG_COOKIE 0xd7a6

/* s and d: the body's states and their derivatives. */
static void drag_body(const tb__drag_params *drag, const tb__body *body, const double *s, double *d)
{
    const double *P = s + TB_STATE_P;
    const double v[3] = {P[0] * body->inv_mass, P[1] * body->inv_mass, P[2] * body->inv_mass};
    tb__v3_axpy(d + TB_STATE_P, -(drag->linear + drag->quadratic * tb__v3_norm(v)), v);
    if (drag->angular != 0.0 || drag->angular_quadratic != 0.0) {
        double omega[3];
        tb__angular_velocity(body, s, omega);
        tb__v3_axpy(d + TB_STATE_L, -(drag->angular + drag->angular_quadratic * tb__v3_norm(omega)),
                    omega);
    }
}

static int apply_drag(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                      double *dydt, size_t first, size_t count)
{
    (void)t;
    const tb__drag_params *drag = effect->params;
    const tb__body *bodies = scene->bodies + first;
    size_t i;
    if (effect->body != TB_ALL_BODIES) {
        if (tb__local_body(effect->slot, first, count, &i)) {
            drag_body(drag, &bodies[i], y + TB_STATE_SIZE * i, dydt + TB_STATE_SIZE * i);
        }
        return 0;
    }
    for (i = 0; i < count; ++i) {
        drag_body(drag, &bodies[i], y + TB_STATE_SIZE * i, dydt + TB_STATE_SIZE * i);
    }
    return 0;
}

/* Drag decays velocities: F = -(b + c |v|) v has the rate (b + 2 c |v|) / m along v (the
 * derivative of the force's magnitude by the speed, over the mass), the torque's twin
 * (b_w + 2 c_w |omega|) / I_min; the quadratic parts grow with the state. The larger of the
 * two, for the body where it is largest. */
static double drag_body_rate(const tb__drag_params *drag, const tb__body *body, const double *s)
{
    const double speed = tb__v3_hypot(s + TB_STATE_P) * body->inv_mass;
    double rate = (drag->linear + 2.0 * drag->quadratic * speed) * body->inv_mass;
    if (drag->angular != 0.0 || drag->angular_quadratic != 0.0) {
        double omega[3];
        tb__angular_velocity(body, s, omega);
        const double *inverse = body->inv_moments;
        const double largest_inverse = fmax(inverse[0], fmax(inverse[1], inverse[2]));
        rate = fmax(rate, (drag->angular + 2.0 * drag->angular_quadratic * tb__v3_hypot(omega)) *
                              largest_inverse);
    }
    return rate;
}

static void drag_rate(const tb__effect *effect, const tb_scene *scene, const double *y,
                      tb__effect_rate *out)
{
    *out = (tb__effect_rate){0.0, TB_ALL_BODIES, 0.0, TB_ALL_BODIES, 0.0};
    const bool all = effect->body == TB_ALL_BODIES;
    for (size_t i = all ? 0 : effect->slot; i < (all ? scene->slot_count : effect->slot + 1); ++i) {
        const double rate =
            drag_body_rate(effect->params, &scene->bodies[i], y + TB_STATE_SIZE * i);
        if (rate > out->decay) {
            out->decay = rate;
            out->decay_body = scene->slot_ids[i];
        }
    }
}

static const tb__effect_lanes drag_lanes = {TB__EFFECT_LANES(tb__drag_lanes)}; /* effect_lanes.c */

static const tb__effect_ops drag_ops = {
    .name = "drag",
    .lanes = &drag_lanes, /* for drag on every body */
    .apply_bodies = apply_drag,
    .rate = drag_rate,
};

tb_drag_def tb_drag_def_default(void)
{
    tb_drag_def def;
    memset(&def, 0, sizeof def);
    def.body = TB_ALL_BODIES;
    def.internal_cookie = TB__DRAG_COOKIE;
    return def;
}

tb_status tb_scene_add_drag(tb_scene *scene, const tb_drag_def *def)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (def == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "def is NULL");
    }
    if (def->internal_cookie != TB__DRAG_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_drag_def_default()");
    }
    tb_status status =
        def->body == TB_ALL_BODIES ? TB_STATUS_OK : tb__scene_check_id(scene, def->body, "body");
    const double values[4] = {def->linear, def->quadratic, def->angular, def->angular_quadratic};
    static const char *const names[4] = {"linear", "quadratic", "angular", "angular_quadratic"};
    for (int k = 0; k < 4 && status == TB_STATUS_OK; ++k) {
        status = tb__validate_nonnegative(scene->detail, values[k], names[k]);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__drag_params drag = {def->linear, def->quadratic, def->angular, def->angular_quadratic};
    const tb__effect effect = {.ops = &drag_ops, .body = def->body, .params = &drag};
    return tb__scene_push_effect(scene, &effect, sizeof drag);
}

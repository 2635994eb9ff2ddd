/* User effects: a callback adds loads through tb_effect_add_force / tb_effect_add_torque. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"

static int apply_user(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                      double *dydt)
{
    return effect->params.user.fn(t, scene, y, dydt, effect->params.user.ctx);
}

/* A callback may couple bodies, and its modes and energy are its own: the guard and the
 * read-outs assume nothing of it. */
static const tb__effect_ops user_ops = {
    .name = "user effect",
    .apply = apply_user,
    .couples_bodies = true,
};

tb_status tb_scene_add_user_effect(tb_scene *scene, tb_user_effect_fn fn, void *ctx)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    scene->detail[0] = '\0';
    if (fn == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "fn is NULL");
    }
    tb__effect effect = {.ops = &user_ops, .body = TB_ALL_BODIES};
    effect.params.user.fn = fn;
    effect.params.user.ctx = ctx;
    return tb__scene_push_effect(scene, &effect);
}

void tb_effect_add_force(const tb_scene *scene, const double *y, double *dydt, size_t id,
                         const double force[3], const double point[3])
{
    (void)scene;
    const double *x = y + TB_STATE_SIZE * id + TB_STATE_X;
    const double arm[3] = {point[0] - x[0], point[1] - x[1], point[2] - x[2]};
    tb__add_load(dydt, id, arm, force);
}

void tb_effect_add_torque(const tb_scene *scene, double *dydt, size_t id, const double torque[3])
{
    (void)scene;
    tb__v3_axpy(dydt + TB_STATE_SIZE * id + TB_STATE_L, 1.0, torque);
}

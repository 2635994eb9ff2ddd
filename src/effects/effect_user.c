/* User effects: a callback adds loads through tb_effect_add_force / tb_effect_add_torque. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

typedef struct tb__user_params {
    tb_user_effect_fn fn;
    void *ctx;
} tb__user_params;

static int apply_user(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                      double *dydt)
{
    tb_scene *writable = (tb_scene *)scene; /* the load status, like the detail, is writable */
    writable->user_load_status = TB_STATUS_OK;
    const tb__user_params *user = effect->params;
    /* The read-outs the callback asks with y (a keyframed body's pose) and its loads' arms read
     * bodies without a state at the scene's time: it is the callback's t while the callback
     * runs, and back as it was after, so the derivative leaves the scene as it found it. */
    const double time = scene->time;
    writable->time = t;
    const int rc = user->fn(t, scene, y, dydt, user->ctx);
    writable->time = time;
    /* A refused load the callback did not act on would be a silently missing force: fail. */
    return rc == 0 && scene->user_load_status != TB_STATUS_OK ? -1 : rc;
}

/* A callback may couple bodies, and its modes and energy are its own: the guard and the
 * read-outs assume nothing of it. */
static const tb__effect_ops user_ops = {
    .name = "user effect",
    .apply = apply_user,
    .couples_bodies = true,
    .keeps_awake = true, /* its loads may change with t while the bodies rest */
};

tb_status tb_scene_add_user_effect(tb_scene *scene, tb_user_effect_fn fn, void *ctx)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (fn == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "fn is NULL");
    }
    tb__user_params user = {.fn = fn, .ctx = ctx};
    const tb__effect effect = {.ops = &user_ops, .body = TB_ALL_BODIES, .params = &user};
    return tb__scene_push_effect(scene, &effect, sizeof user);
}

/* The checks of both load functions; the failure is kept for apply_user. */
static tb_status check_load(const tb_scene *scene, const double *dydt, size_t id,
                            const double *load, const char *load_name)
{
    char *detail = ((tb_scene *)scene)->detail;
    tb_status status = tb__validate_pointer(detail, dydt, "dydt");
    if (status == TB_STATUS_OK) {
        status = tb__validate_index(detail, id, scene->body_count, "id", "bodies");
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_vector(detail, load, load_name);
    }
    return status;
}

static tb_status refuse(const tb_scene *scene, tb_status status)
{
    if (scene->user_load_status == TB_STATUS_OK) {
        ((tb_scene *)scene)->user_load_status = status;
    }
    return status;
}

/* The common case, checked inline (these run once per load per derivative): every pointer
 * set, id in range, the vectors finite. The checks above then only write the detail. */
static inline bool load_is_good(const tb_scene *scene, const double *dydt, size_t id,
                                const double *load, const double *point)
{
    return dydt != NULL && id < scene->body_count && load != NULL && point != NULL &&
           tb__all_finite(load, 3) && tb__all_finite(point, 3);
}

tb_status tb_effect_add_force(const tb_scene *scene, const double *y, double *dydt, size_t id,
                              const double force[3], const double point[3])
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    char *detail = ((tb_scene *)scene)->detail;
    detail[0] = '\0';
    if (y == NULL || !load_is_good(scene, dydt, id, force, point)) {
        tb_status status = tb__validate_pointer(detail, y, "y");
        if (status == TB_STATUS_OK) {
            status = check_load(scene, dydt, id, force, "force");
        }
        if (status == TB_STATUS_OK) {
            status = tb__validate_vector(detail, point, "point");
        }
        return refuse(scene, status);
    }
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, id, &motion);
    const double *x = motion.x;
    const double arm[3] = {point[0] - x[0], point[1] - x[1], point[2] - x[2]};
    tb__add_body_load(scene, dydt, id, arm, force);
    return TB_STATUS_OK;
}

tb_status tb_effect_add_torque(const tb_scene *scene, double *dydt, size_t id,
                               const double torque[3])
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    ((tb_scene *)scene)->detail[0] = '\0';
    if (!load_is_good(scene, dydt, id, torque, torque)) {
        return refuse(scene, check_load(scene, dydt, id, torque, "torque"));
    }
    double *d = tb__body_state_mut(scene, dydt, id);
    if (d != NULL) {
        tb__v3_axpy(d + TB_STATE_L, 1.0, torque);
    }
    return TB_STATUS_OK;
}

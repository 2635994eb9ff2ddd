/* Scene files: the "integrator" and "output" sections, into the tb_run_def the loader
 * returns. */
#include "io/scene_file_internal.h"

#include "core/detail.h"

#include <stdio.h>
#include <string.h>

static tb_status load_linear_solver(tb__loader *ld, const json_t *object, tb_integrator_def *def)
{
    const char *name = NULL;
    tb_status status = tb__json_string(ld, object, "integrator", "linear_solver", false, &name);
    if (status != TB_STATUS_OK || name == NULL) {
        return status;
    }
    static const char *const names[] = {"auto", "dense", "krylov", "sparse"};
    for (int k = 0; k < 4; ++k) {
        if (strcmp(name, names[k]) == 0) {
            def->linear_solver = (tb_linear_solver)k;
            return TB_STATUS_OK;
        }
    }
    return tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.linear_solver",
                         "must be one of auto, dense, krylov, sparse, got \"%s\"", name);
}

/* A setting the method does not read (the method table's rule, tb_method_check_setting) is
 * refused rather than ignored: a "dt" next to "cvode-bdf" is a mistake the user should hear
 * about. */
static tb_status check_settings_fit(tb__loader *ld, const json_t *object, tb_method method)
{
    const char *key;
    const json_t *value;
    json_object_foreach((json_t *)object, key, value)
    {
        tb_error error;
        if (strcmp(key, "method") != 0 &&
            tb_method_check_setting(method, key, &error) == TB_STATUS_UNSUPPORTED) {
            char where[64];
            snprintf(where, sizeof where, "integrator.%s", key);
            return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "%s", error.message);
        }
    }
    return TB_STATUS_OK;
}

/* dt, rtol, atol. */
static tb_status load_step_settings(tb__loader *ld, const json_t *object, tb_integrator_def *def)
{
    tb_status status = tb__json_number(ld, object, "integrator", "dt", false, &def->dt);
    if (status == TB_STATUS_OK) {
        status = tb__check_positive_at(ld, "integrator", "dt", def->dt);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "integrator", "rtol", false, &def->rtol);
    }
    if (status == TB_STATUS_OK && !(def->rtol >= 1e-15 && def->rtol < 1)) {
        char typed[32]; /* 1e-320 as written, not 9.99989e-321 (F119) */
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.rtol",
                               "must be in [1e-15, 1), got %s", tb__shortest(def->rtol, typed));
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "integrator", "atol", false, &def->atol);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_non_negative_at(ld, "integrator", "atol", def->atol);
    }
    return status;
}

/* max_steps, max_order. */
static tb_status load_limits(tb__loader *ld, const json_t *object, tb_integrator_def *def)
{
    long max_order = def->max_order;
    tb_status status =
        tb__json_count(ld, object, "integrator", "max_steps", false, &def->max_steps);
    if (status == TB_STATUS_OK) {
        status = tb__check_positive_at(ld, "integrator", "max_steps", (double)def->max_steps);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_count(ld, object, "integrator", "max_order", false, &max_order);
    }
    if (status == TB_STATUS_OK && max_order > tb_method_order(def->method)) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.max_order",
                               "must be at most %d for %s, got %ld", tb_method_order(def->method),
                               tb_method_name(def->method), max_order);
    }
    if (status == TB_STATUS_OK) {
        def->max_order = (int)max_order;
    }
    return status;
}

tb_status tb__load_integrator(tb__loader *ld, const json_t *object)
{
    static const char *const keys[] = {"method",    "dt",        "rtol",          "atol",
                                       "max_steps", "max_order", "linear_solver", "allow_unstable",
                                       NULL};
    tb_status status = tb__json_object(ld, object, "integrator", keys);
    tb_integrator_def *def = &ld->run.integrator;
    const char *method = NULL;
    if (status == TB_STATUS_OK) {
        status = tb__json_string(ld, object, "integrator", "method", false, &method);
    }
    if (status == TB_STATUS_OK && method != NULL &&
        tb_method_from_name(method, &def->method) != TB_STATUS_OK) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.method",
                               "must be one of euler, midpoint, rk4, cvode-adams, cvode-bdf, "
                               "rosenbrock, ark-imex, got \"%s\"",
                               method);
    }
    if (status == TB_STATUS_OK) {
        status = check_settings_fit(ld, object, def->method);
    }
    if (status == TB_STATUS_OK) {
        status = load_step_settings(ld, object, def);
    }
    if (status == TB_STATUS_OK) {
        status = load_limits(ld, object, def);
    }
    const json_t *unstable = json_object_get(object, "allow_unstable");
    if (status == TB_STATUS_OK && unstable != NULL && !json_is_boolean(unstable)) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.allow_unstable",
                               "must be true or false, got %s", tb__json_kind(unstable));
    }
    tb_scene_set_allow_unstable(ld->scene, unstable != NULL && json_is_true(unstable));
    return status == TB_STATUS_OK ? load_linear_solver(ld, object, def) : status;
}

tb_status tb__load_output(tb__loader *ld, const json_t *object)
{
    static const char *const keys[] = {"fps", "duration", NULL};
    tb_status status = tb__json_object(ld, object, "output", keys);
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "output", "fps", false, &ld->run.fps);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_positive_at(ld, "output", "fps", ld->run.fps);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "output", "duration", false, &ld->run.duration);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_non_negative_at(ld, "output", "duration", ld->run.duration);
    }
    /* the library's frame count (tb_scene_run refuses what it refuses): checking a scene
     * refuses what running it would */
    size_t frames = 0;
    tb_error error;
    if (status == TB_STATUS_OK &&
        tb_run_frame_count(ld->run.duration, ld->run.fps, &frames, &error) != TB_STATUS_OK) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "output", "%s", error.message);
    }
    return status;
}

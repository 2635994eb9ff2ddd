/* Runs: frames at a fixed rate over a duration, each handed to a callback. */
#include "tumble/run.h"

#include "core/detail.h"

#include <math.h>
#include <string.h>

#define TB__RUN_COOKIE 0x2a11
/* A duration within this fraction of a frame past a whole number of frames still ends on
 * that frame (5 s at 60 fps is 300 frames, not 300 plus a sliver). */
#define TB__FRAME_SLACK 1e-9

tb_run_def tb_run_def_default(void)
{
    tb_run_def def;
    memset(&def, 0, sizeof def);
    def.integrator = tb_integrator_def_default();
    def.fps = 60.0;
    def.duration = 5.0;
    def.internal_cookie = TB__RUN_COOKIE;
    return def;
}

static tb_status validate(const tb_scene *scene, const tb_run_def *def, tb_error *error)
{
    if (scene == NULL || def == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             scene == NULL ? "scene" : "def");
    }
    if (def->internal_cookie != TB__RUN_COOKIE) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def: not initialised by tb_run_def_default()");
    }
    if (!(def->fps > 0) || !isfinite(def->fps)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "fps: must be finite and > 0, got %g", def->fps);
    }
    if (!(def->duration >= 0) || !isfinite(def->duration) || def->duration * def->fps > 1e9) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "duration: must be finite, >= 0 and at most 1e9 frames, got %g",
                             def->duration);
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_run(tb_scene *scene, const tb_run_def *def, tb_frame_fn on_frame, void *ctx,
                       tb_integrator_stats *out_stats, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (out_stats != NULL) {
        memset(out_stats, 0, sizeof *out_stats);
    }
    tb_status status = validate(scene, def, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb_integrator *integrator = NULL;
    status = tb_scene_integrator_create(scene, &def->integrator, 0.0, &integrator);
    if (status != TB_STATUS_OK) {
        return tb__set_error(out_error, status, "%s", tb_scene_detail(scene));
    }
    const size_t frames = (size_t)floor(def->duration * def->fps + TB__FRAME_SLACK);
    for (size_t k = 0; k <= frames && status == TB_STATUS_OK; ++k) {
        const double t = (double)k / def->fps;
        status = tb_integrator_advance(integrator, t);
        if (status != TB_STATUS_OK) {
            tb__set_error(out_error, status, "%s", tb_integrator_detail(integrator));
        } else if (on_frame != NULL && on_frame(k, t, scene, ctx) != 0) {
            status = tb__set_error(out_error, TB_STATUS_CANCELLED,
                                   "the frame callback stopped the run at t = %g", t);
        }
    }
    if (out_stats != NULL) {
        tb_integrator_get_stats(integrator, out_stats);
    }
    tb_integrator_destroy(integrator);
    return status;
}

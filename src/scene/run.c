/* Runs: frames at a fixed rate over a duration, each handed to a callback. */
#include "tumble/run.h"

#include "core/detail.h"
#include "scene/scene_internal.h"

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

/* A fixed step takes (1 / fps) / dt steps from frame to frame; more than the integrator's
 * max_steps is known before the run, so it is refused before the first frame (the advance
 * would refuse it at the second), and checking a scene refuses it too. One step of slack: the
 * advance decides at the boundary. */
static tb_status check_frame_budget(const tb_scene *scene, const tb_run_def *def, tb_error *error)
{
    const tb_integrator_def *integrator = &def->integrator;
    /* dt 0: the scene's default step, which the integrator will take */
    const double dt = integrator->dt == 0.0 && !tb_method_is_adaptive(integrator->method)
                          ? tb__scene_default_step(scene, scene->states, integrator->method)
                          : integrator->dt;
    if (tb_method_is_adaptive(integrator->method) || !(dt > 0) || !isfinite(dt) ||
        integrator->max_steps <= 0) {
        return TB_STATUS_OK; /* tb_integrator_create names what is wrong */
    }
    const double steps = 1.0 / def->fps / dt;
    if (!(steps > (double)integrator->max_steps + 1.0)) {
        return TB_STATUS_OK;
    }
    return tb__set_error(error, TB_STATUS_TOO_MANY_STEPS,
                         "integrator.dt: frames %g s apart (%g fps) are %.3g steps of dt = %g s%s, "
                         "more than max_steps = %ld: use a larger dt (a softer contact or spring "
                         "allows one), a larger max_steps, or more frames a second",
                         1.0 / def->fps, def->fps, steps, dt,
                         integrator->dt == 0.0 ? " (the scene's default step)" : "",
                         integrator->max_steps);
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
    size_t frames;
    const tb_status status = tb_run_frame_count(def->duration, def->fps, &frames, error);
    return status != TB_STATUS_OK || frames == 0 ? status : check_frame_budget(scene, def, error);
}

tb_status tb_run_frame_count(double duration, double fps, size_t *out_frames, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (out_frames == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "out_frames is NULL");
    }
    if (!isfinite(fps) || !isfinite(duration)) {
        return tb__set_error(out_error, TB_STATUS_NOT_FINITE, "%s: must be finite, got %g",
                             isfinite(fps) ? "duration" : "fps", isfinite(fps) ? duration : fps);
    }
    if (!(fps > 0)) {
        return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT, "fps: must be > 0, got %g",
                             fps);
    }
    /* compared before the product is converted, so no value overflows the conversion */
    const double frames = floor(duration * fps + TB__FRAME_SLACK);
    if (!(duration >= 0) || !(frames <= TB_RUN_MAX_FRAMES)) {
        return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT,
                             "duration: must be >= 0 and at most 1e9 frames (TB_RUN_MAX_FRAMES) "
                             "at %g fps (%g s), got %g s",
                             fps, TB_RUN_MAX_FRAMES / fps, duration);
    }
    *out_frames = (size_t)frames;
    return TB_STATUS_OK;
}

tb_status tb_run_output_frames(size_t body_count, double duration, double fps, size_t *out_frames,
                               tb_error *out_error)
{
    size_t last = 0;
    const tb_status status =
        tb_run_frame_count(duration, fps, out_frames != NULL ? &last : NULL, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    /* in doubles: last + 1 <= 1e9 + 1 and any body count give no overflow */
    const double body_frames = ((double)last + 1.0) * (double)body_count;
    if (body_frames > TB_RUN_MAX_BODY_FRAMES) {
        return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT,
                             "duration: %g s at %g fps is %zu frames of %zu bodies, %.3g "
                             "body-frames, more than the %g an output holds "
                             "(TB_RUN_MAX_BODY_FRAMES): shorten the run or lower fps",
                             duration, fps, last + 1, body_count, body_frames,
                             TB_RUN_MAX_BODY_FRAMES);
    }
    *out_frames = last + 1;
    return TB_STATUS_OK;
}

/* After a frame: a fixed step that the state has outgrown (a spin or speed that rose) stops the
 * run before the frame is handed on. */
static tb_status check_frame(tb_scene *scene, const tb_run_def *def, double t, tb_error *error)
{
    if (tb_method_is_adaptive(def->integrator.method)) {
        return TB_STATUS_OK;
    }
    char detail[TB_DETAIL_SIZE];
    const tb_status status = tb__scene_check_step(
        scene, tb_scene_states_const(scene), def->integrator.method, def->integrator.dt, detail);
    return status == TB_STATUS_OK ? status
                                  : tb__set_error(error, status, "at t = %g s: %s", t, detail);
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
    tb_run_def stepped = *def; /* dt 0: the scene's default step, also for check_frame */
    if (!tb_method_is_adaptive(def->integrator.method) && def->integrator.dt == 0.0) {
        stepped.integrator.dt =
            tb__scene_default_step(scene, scene->states, def->integrator.method);
    }
    def = &stepped;
    tb_integrator *integrator = NULL;
    status = tb_scene_integrator_create(scene, &def->integrator, 0.0, &integrator);
    if (status != TB_STATUS_OK) {
        return tb__set_error(out_error, status, "%s", tb_scene_detail(scene));
    }
    size_t frames = 0;
    tb_run_frame_count(def->duration, def->fps, &frames, NULL);
    for (size_t k = 0; k <= frames && status == TB_STATUS_OK; ++k) {
        const double t = (double)k / def->fps;
        status = tb_integrator_advance(integrator, t);
        if (status != TB_STATUS_OK) {
            tb__set_error(out_error, status, "%s", tb_integrator_detail(integrator));
        } else if ((status = check_frame(scene, def, t, out_error)) != TB_STATUS_OK) {
            break;
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

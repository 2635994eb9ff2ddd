/* Runs: advancing a scene frame by frame and handing each frame to a callback (a sink: a CSV
 * writer, a renderer, a binding that copies states into arrays). */
#ifndef TUMBLE_RUN_H
#define TUMBLE_RUN_H

#include "tumble/export.h"

#include "tumble/ode.h"
#include "tumble/scene.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tb_run_def {
    tb_integrator_def integrator; /* how to integrate; default RK4 at 1/240 s */
    double fps;                   /* frames per second, > 0; default 60 */
    double duration;              /* s, >= 0; default 5 */
    int internal_cookie;
} tb_run_def;

TB_API tb_run_def tb_run_def_default(void);

/* Most frames a run makes (a frame past the first at t = 0). */
#define TB_RUN_MAX_FRAMES 1e9

/* The number of the last frame of a run: floor(duration * fps), a duration within 1e-9 of a
 * frame past a whole number of frames ending on that frame (5 s at 60 fps: 300, so 301 frames
 * with t = 0). Refuses what tb_scene_run refuses: NaN/inf (NOT_FINITE), fps <= 0, duration < 0
 * or more than TB_RUN_MAX_FRAMES frames (INVALID_ARGUMENT), naming the argument; out_error may
 * be NULL. Front ends ask it so that checking a scene refuses what running it would. */
TB_API tb_status tb_run_frame_count(double duration, double fps, size_t *out_frames,
                                    tb_error *out_error);

/* Most body-frames (frames, t = 0 included, times bodies) a run's kept or written output may
 * hold: 1e8, that is 10.4 GB of frame values (13 doubles a body-frame) in memory and tens of GB
 * of CSV. */
#define TB_RUN_MAX_BODY_FRAMES 1e8

/* The frames a run hands on, t = 0 included (tb_run_frame_count + 1), for a front end that keeps
 * or writes every one of body_count bodies' frames: refuses what tb_run_frame_count refuses, and
 * more than TB_RUN_MAX_BODY_FRAMES body-frames (TB_STATUS_INVALID_ARGUMENT naming duration, fps,
 * the bodies and the bound), so that nothing is allocated or written for a run that could not be
 * kept. The CLI (run and check) and the Python bindings ask it before they allocate or open a
 * file (tests/test_frame_values.c, bindings/python/tests/test_front_end_contracts.py). out_error
 * may be NULL. */
TB_API tb_status tb_run_output_frames(size_t body_count, double duration, double fps,
                                      size_t *out_frames, tb_error *out_error);

/* Called at t = 0 and at every frame time k / fps up to the duration (frame k), with the scene
 * holding the states at that time (quaternions normalised). Return 0 to go on, non-zero to
 * stop the run (tb_scene_run then returns TB_STATUS_CANCELLED). */
typedef int (*tb_frame_fn)(size_t frame, double t, const tb_scene *scene, void *ctx);

/* Runs the scene from its current state at t = 0 for def->duration seconds. A fixed step that
 * needs more than def->integrator.max_steps steps from one frame to the next is refused before
 * the first frame (TB_STATUS_TOO_MANY_STEPS, nothing done). A fixed step the
 * state outgrows during the run (spin or speed rising past tb_scene_max_stable_step) stops it
 * after the frame where that is found, before that frame is handed on, with
 * TB_STATUS_UNSTABLE_STEP. Adaptive methods
 * take their steps as their error control decides and frames come from their interpolant,
 * so the frame rate does not change the solution. out_stats (may be NULL) receives what the
 * integrator did, also on failure. On failure the scene holds the last good state and
 * out_error (may be NULL) says what happened and when. */
TB_API tb_status tb_scene_run(tb_scene *scene, const tb_run_def *def, tb_frame_fn on_frame,
                              void *ctx, tb_integrator_stats *out_stats, tb_error *out_error);

#ifdef __cplusplus
}
#endif

#endif

/* The accuracy sweep: a scene run with each integrator across a sweep of its setting, every
 * run compared with a tight reference run of the same scene. What `tumble accuracy` prints
 * and Python's Scene.accuracy returns, computed once, here. */
#ifndef TUMBLE_ACCURACY_H
#define TUMBLE_ACCURACY_H

#include "tumble/export.h"

#include "tumble/ode.h"
#include "tumble/run.h"
#include "tumble/scene.h"
#include "tumble/status.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tb_accuracy_setting {
    tb_method method;
    double setting; /* fixed-step methods: steps per second (dt = 1 / setting); CVODE: rtol */
} tb_accuracy_setting;

/* The default sweep: Euler at 240, 1000, 4000 steps/s; midpoint at 60, 240, 1000; RK4 at 60,
 * 240, 1000, 4000; CVODE Adams and BDF and ark-imex at rtol 1e-3, 1e-5, 1e-7, 1e-9. A constant
 * array of
 * *out_count settings. */
TB_API const tb_accuracy_setting *tb_accuracy_default_sweep(size_t *out_count);

/* The default sweep fitted to a scene: as tb_accuracy_default_sweep, except that a fixed-step
 * method whose default step on the scene (tb_scene_default_step: stiff contact or springs) is
 * shorter than 1/240 s runs at 1, 2 and 4 times the rate of that step instead of the table's
 * rates, which would all be refused as unstable. Writes at most capacity settings to out (the
 * default sweep's count is always enough) and their number to *out_count. */
TB_API tb_status tb_accuracy_scene_sweep(const tb_scene *scene, tb_accuracy_setting *out,
                                         size_t capacity, size_t *out_count);

/* Which run is the reference. */
typedef enum tb_accuracy_reference_kind {
    /* CVODE BDF; if it fails (stiff contact whose manifold jumps defeats BDF's error test at
     * tight tolerances: 12 dice fail near the first impacts), RK4 instead */
    TB_ACCURACY_REFERENCE_AUTO = 0,
    TB_ACCURACY_REFERENCE_CVODE, /* CVODE BDF at reference_rtol, checked at check_rtol */
    /* RK4 at reference_step_fraction of the scene's default RK4 step, checked at twice it */
    TB_ACCURACY_REFERENCE_RK4,
} tb_accuracy_reference_kind;

/* Which run of the sweep a progress report is about. */
typedef enum tb_accuracy_run_kind {
    TB_ACCURACY_RUN_REFERENCE = 0, /* the reference run (under AUTO: BDF, then RK4 if it failed) */
    TB_ACCURACY_RUN_CHECK,         /* the check run that bounds the reference's own error */
    TB_ACCURACY_RUN_SETTING        /* a setting of the sweep */
} tb_accuracy_run_kind;

/* How far the sweep has got: reported at the start of every run (t = 0), at each of its frames
 * and, inside a frame, every 256 evaluations of the scene's derivative (t is then that
 * evaluation's time, which may step back a little where a solver retries a step), so that a
 * front end can show progress on a long sweep (`tumble accuracy`) even where a run crawls
 * through one frame. */
typedef struct tb_accuracy_progress {
    tb_accuracy_run_kind kind;
    size_t index;     /* the setting's index (TB_ACCURACY_RUN_SETTING), else 0 */
    size_t count;     /* the settings in the sweep */
    tb_method method; /* the run's method and its setting, as tb_accuracy_setting */
    double setting;
    double t;        /* s: the frame the run has reached */
    double duration; /* s: where the run ends */
} tb_accuracy_progress;

/* Called with the sweep's progress (see tb_accuracy_progress); it must not change the scene. */
typedef void (*tb_accuracy_progress_fn)(const tb_accuracy_progress *progress, void *ctx);

typedef struct tb_accuracy_def {
    const tb_accuracy_setting *settings; /* NULL: the default sweep */
    size_t setting_count;                /* settings' length (ignored for the default) */
    /* The reference is CVODE BDF (it copes with stiff contact and springs) at reference_rtol;
     * a second run at check_rtol bounds the reference's own error (about a tenth of the
     * difference where the runs converge). Defaults 1e-11 and 1e-10. */
    double reference_rtol;
    double check_rtol;
    long max_steps;                       /* each run's step budget per frame; default 1000000 */
    tb_accuracy_reference_kind reference; /* default TB_ACCURACY_REFERENCE_AUTO */
    double reference_step_fraction;       /* RK4 reference: in (0, 0.5]; default 0.125 (finer
                                             than the sweep's finest, a quarter) */
    /* Chaos: where a small difference decides how a body falls, no two runs agree for long, and
     * an error taken over every frame measures the chaos, not the integrator. Frames are compared
     * up to the horizon: the last frame before the check run strays farther than
     * horizon_tolerance (m, the error's measure) from the reference, where the reference is still
     * known to that tolerance. 0 or INFINITY: every frame. Default 1e-4 m. */
    double horizon_tolerance;
    tb_accuracy_progress_fn progress; /* NULL (the default): no progress reports */
    void *progress_ctx;               /* passed to progress */
    int internal_cookie;
} tb_accuracy_def;

TB_API tb_accuracy_def tb_accuracy_def_default(void);

/* One setting's outcome. Errors are the largest over all frames and bodies: the position of
 * each body's centre of mass (m), the angle between orientations (rad), and what an animator
 * sees, the displacement |dx| + l * angle of the body's points at its radius of gyration l
 * about its largest principal axis (m). */
typedef struct tb_accuracy_result {
    tb_method method;
    double setting;
    tb_status status;            /* OK, or why this setting gave no result (the run's status:
                                    TB_STATUS_UNSTABLE_STEP when the step is refused as
                                    unstable, TB_STATUS_TOO_MANY_STEPS, ...) */
    char detail[TB_DETAIL_SIZE]; /* the run's detail when status is not OK, else "" */
    double error;                /* m */
    double position_error;       /* m */
    double angle_error;          /* rad */
    double cpu_seconds;          /* processor time of the run */
    long steps;
    long derivative_evals;
    /* |E - E_ref| at the last frame, J (E kinetic plus potential): a statistic that stays
     * meaningful past the horizon (12 dice come to rest at the same height wherever they land) */
    double energy_error;
} tb_accuracy_result;

/* The reference used and its own uncertainty: the errors of the check run against it, up to
 * the horizon. Errors below these are not resolved. */
typedef struct tb_accuracy_reference {
    double error, position_error, angle_error; /* m, m, rad */
    tb_method method;                          /* TB_METHOD_CVODE_BDF or TB_METHOD_RK4 */
    double setting;        /* its rtol, or steps per second; as tb_accuracy_setting */
    double check_setting;  /* the check run's, of the same method */
    double horizon;        /* s: the time of the last frame compared (see horizon_tolerance) */
    size_t horizon_frames; /* frames compared (from the first); all the run's when it agrees */
    size_t frames;         /* frames in the run */
    double energy_error;   /* the check run's |E - E_ref| at the last frame, J */
    /* Why CVODE was set aside for RK4 (its run's detail), "" when it was not */
    char cvode_detail[TB_DETAIL_SIZE];
} tb_accuracy_reference;

/* Called after each setting has run (index into the sweep); non-zero stops the sweep
 * (TB_STATUS_CANCELLED). */
typedef int (*tb_accuracy_fn)(size_t index, const tb_accuracy_result *result, void *ctx);

/* Runs the sweep on scene from its current state with run's frames (fps, duration; run's
 * integrator is not used: each setting runs with tb_integrator_def_default() changed to its
 * method, its dt or rtol (atol 0: per body), and def's max_steps), each compared with the
 * reference over the frames up to the reference's horizon (see horizon_tolerance). def may be
 * NULL for tb_accuracy_def_default(). out_results holds one result per setting. The scene's
 * states are as they were on return, success or not. Fails (with out_error naming the cause) on
 * bad arguments, or when the reference or check run fails (under AUTO: when RK4 fails too): then
 * the status and detail are the run's, prefixed with which run it was. A setting whose run
 * fails is not a failure of the sweep: its result says why. Budgets that keep a sweep on
 * contact short: on a scene with events an adaptive setting may take at most 4 times the RK4
 * reference's steps a frame (more would cost more derivatives than the reference), and where
 * the reference is RK4 a setting stops at the first frame past 1.5 times the reference run's
 * CPU time (it would cost more than the more accurate reference; which rows finish can then
 * depend on the machine's load); both fail the row with TB_STATUS_TOO_MANY_STEPS. No printing. */
TB_API tb_status tb_scene_accuracy_sweep(tb_scene *scene, const tb_run_def *run,
                                         const tb_accuracy_def *def, tb_accuracy_fn on_result,
                                         void *ctx, tb_accuracy_result *out_results,
                                         tb_accuracy_reference *out_reference, tb_error *out_error);

/* The index of the cheapest result (least CPU time) that ran and has error <= target_error
 * (m); count when none has. */
TB_API size_t tb_accuracy_cheapest(const tb_accuracy_result *results, size_t count,
                                   double target_error);

#ifdef __cplusplus
}
#endif

#endif

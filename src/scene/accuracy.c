/* The accuracy sweep. The reference run's poses (centre of mass and orientation of each body
 * at each frame) are kept; every other run is compared with them frame by frame as it goes,
 * so only one trajectory is stored. */
#include "tumble/accuracy.h"

#include "core/detail.h"
#include "core/validate.h"
#include "scene/run_watch.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define TB__ACCURACY_COOKIE 0x5ac1
#define TB__POSE 7 /* x[3], q[4] */
/* A setting's CPU budget in RK4 reference runs (see sweep) */
#define TB__REFERENCE_CPU_FACTOR 1.5

static const tb_accuracy_setting default_sweep[] = {
    {TB_METHOD_EULER, 240},        {TB_METHOD_EULER, 1000},       {TB_METHOD_EULER, 4000},
    {TB_METHOD_MIDPOINT, 60},      {TB_METHOD_MIDPOINT, 240},     {TB_METHOD_MIDPOINT, 1000},
    {TB_METHOD_RK4, 60},           {TB_METHOD_RK4, 240},          {TB_METHOD_RK4, 1000},
    {TB_METHOD_RK4, 4000},         {TB_METHOD_CVODE_ADAMS, 1e-3}, {TB_METHOD_CVODE_ADAMS, 1e-5},
    {TB_METHOD_CVODE_ADAMS, 1e-7}, {TB_METHOD_CVODE_ADAMS, 1e-9}, {TB_METHOD_CVODE_BDF, 1e-3},
    {TB_METHOD_CVODE_BDF, 1e-5},   {TB_METHOD_CVODE_BDF, 1e-7},   {TB_METHOD_CVODE_BDF, 1e-9},
    {TB_METHOD_ARK_IMEX, 1e-3},    {TB_METHOD_ARK_IMEX, 1e-5},    {TB_METHOD_ARK_IMEX, 1e-7},
    {TB_METHOD_ARK_IMEX, 1e-9},    {TB_METHOD_ROSENBROCK, 240},   {TB_METHOD_ROSENBROCK, 1000},
};

const tb_accuracy_setting *tb_accuracy_default_sweep(size_t *out_count)
{
    if (out_count != NULL) {
        *out_count = sizeof default_sweep / sizeof default_sweep[0];
    }
    return default_sweep;
}

/* Whether method's stability region has no bound (the method table's limits: rosenbrock). */
static bool unbounded_stability(tb_method method)
{
    tb_method_info info;
    return tb_method_get_info(method, &info) == TB_STATUS_OK && isinf(info.real_limit) &&
           isinf(info.imaginary_limit);
}

/* The fixed-step rates the scene's default step of method asks for, written after *count; false
 * when the table's rates are stable (the default step is the table's 1/240 s). A method with no
 * stability limit keeps the table's rates: a user's step, where what it costs and how far it
 * lands is the question (its default step resolves the fastest oscillation instead). */
static bool stiff_rates(const tb_scene *scene, tb_method method, tb_accuracy_setting *out,
                        size_t capacity, size_t *count)
{
    double dt = 0.0;
    if (unbounded_stability(method) || tb_scene_default_step(scene, method, &dt) != TB_STATUS_OK ||
        !(dt < 1.0 / 240.0)) {
        return false;
    }
    for (int k = 0; k < 3 && *count < capacity; ++k) {
        out[(*count)++] = (tb_accuracy_setting){method, (double)(1 << k) / dt};
    }
    return true;
}

tb_status tb_accuracy_scene_sweep(const tb_scene *scene, tb_accuracy_setting *out, size_t capacity,
                                  size_t *out_count)
{
    if (scene == NULL || out == NULL || out_count == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    size_t count = 0, table = sizeof default_sweep / sizeof default_sweep[0];
    for (size_t k = 0; k < table && count < capacity; ++k) {
        const tb_method method = default_sweep[k].method;
        const bool first = k == 0 || default_sweep[k - 1].method != method;
        if (tb_method_is_adaptive(method)) {
            out[count++] = default_sweep[k];
        } else if (first && !stiff_rates(scene, method, out, capacity, &count)) {
            for (size_t j = k; j < table && default_sweep[j].method == method && count < capacity;
                 ++j) {
                out[count++] = default_sweep[j];
            }
        }
    }
    *out_count = count;
    return TB_STATUS_OK;
}

tb_accuracy_def tb_accuracy_def_default(void)
{
    tb_accuracy_def def;
    memset(&def, 0, sizeof def);
    def.reference_rtol = 1e-11;
    def.check_rtol = 1e-10;
    def.max_steps = 1000000;
    def.reference = TB_ACCURACY_REFERENCE_AUTO;
    def.reference_step_fraction = 0.125;
    def.horizon_tolerance = 1e-4;
    def.internal_cookie = TB__ACCURACY_COOKIE;
    return def;
}

/* What one run is compared with, and what the comparison found so far. */
typedef struct comparison {
    size_t bodies;        /* the dynamic bodies, by slot */
    const double *length; /* bodies: radius of gyration about the largest axis, m */
    double *reference;    /* frames x bodies x TB__POSE, grown while recording */
    size_t frames, capacity;
    int recording; /* 1: store the poses (the reference run); 0: compare with them */
    /* The check run looks for the horizon: the first frame farther than tolerance from the
     * reference ends the frames compared (limit), for it and every later run. */
    int checking;
    double tolerance; /* m */
    size_t limit;     /* frames compared */
    double horizon;   /* s: the last frame compared */
    double position, angle, displacement;
    double energy, reference_energy; /* J, at the latest frame of the run and of the reference */
    tb_accuracy_progress_fn progress_fn; /* the def's, NULL for none */
    void *progress_ctx;
    tb_accuracy_progress progress; /* the run under way: kind and index set before run_one */
    /* A setting's run stops at the frame past cpu_limit s of CPU (0: none; see sweep) */
    double cpu_limit, reference_cpu; /* s; the reference run's CPU time */
    clock_t started;
    int over; /* the run under way passed cpu_limit */
} comparison;

static void report(comparison *c, double t)
{
    if (c->progress_fn != NULL) {
        c->progress.t = t;
        c->progress_fn(&c->progress, c->progress_ctx);
    }
}

static int record(comparison *c, const double *y)
{
    if (c->frames == c->capacity) {
        const size_t per_frame = c->bodies * TB__POSE;
        const size_t capacity = c->capacity == 0 ? 64 : 2 * c->capacity;
        size_t doubles;
        if (!tb__size_product(capacity, per_frame, &doubles)) {
            return 1;
        }
        double *grown = tb__realloc_array(c->reference, doubles, sizeof(double));
        if (grown == NULL) {
            return 1;
        }
        c->reference = grown;
        c->capacity = capacity;
    }
    for (size_t i = 0; i < c->bodies; ++i) {
        memcpy(c->reference + TB__POSE * (c->frames * c->bodies + i), y + TB_STATE_SIZE * i,
               TB__POSE * sizeof(double));
    }
    c->frames += 1;
    return 0;
}

/* The angle between orientations p and r, from the relative rotation r* p, whose vector part
 * has length sin(angle / 2): atan2 keeps full precision near zero, unlike acos of the dot. */
static double angle_between(const double *p, const double *r)
{
    const double w = r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3] * p[3];
    const double v[3] = {r[0] * p[1] - r[1] * p[0] - r[2] * p[3] + r[3] * p[2],
                         r[0] * p[2] + r[1] * p[3] - r[2] * p[0] - r[3] * p[1],
                         r[0] * p[3] - r[1] * p[2] + r[2] * p[1] - r[3] * p[0]};
    return 2.0 * atan2(sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), fabs(w));
}

static void compare(comparison *c, size_t frame, double t, const double *y)
{
    double position = 0.0, angle = 0.0, displacement = 0.0;
    for (size_t i = 0; i < c->bodies; ++i) {
        const double *p = y + TB_STATE_SIZE * i;
        const double *r = c->reference + TB__POSE * (frame * c->bodies + i);
        const double d[3] = {p[TB_STATE_X] - r[0], p[TB_STATE_X + 1] - r[1],
                             p[TB_STATE_X + 2] - r[2]};
        const double shift = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double turn = angle_between(p + TB_STATE_Q, r + 3);
        position = fmax(position, shift);
        angle = fmax(angle, turn);
        displacement = fmax(displacement, shift + c->length[i] * turn);
    }
    if (c->checking && !(displacement <= c->tolerance)) {
        c->limit = frame; /* the horizon: this frame and later ones are not compared */
        return;
    }
    c->position = fmax(c->position, position);
    c->angle = fmax(c->angle, angle);
    c->displacement = fmax(c->displacement, displacement);
    c->horizon = t;
}

static double energy(const tb_scene *scene, const double *y)
{
    double kinetic = 0.0, potential = 0.0;
    tb_scene_kinetic_energy(scene, y, &kinetic);
    tb_scene_potential_energy(scene, y, &potential);
    return kinetic + potential;
}

/* Whether the run under way has passed its CPU budget (cpu_limit > 0), which then ends it. */
static int over_budget(comparison *c)
{
    c->over = c->cpu_limit > 0.0 && (double)(clock() - c->started) / CLOCKS_PER_SEC > c->cpu_limit;
    return c->over;
}

static int on_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    comparison *c = ctx;
    const double *y = tb_scene_states_const(scene);
    report(c, t);
    if (c->recording) {
        c->reference_energy = energy(scene, y);
        return record(c, y);
    }
    c->energy = energy(scene, y);
    if (frame < c->frames && frame < c->limit) {
        compare(c, frame, t, y);
    }
    return over_budget(c); /* the run stops here: CANCELLED, turned into the budget's status */
}

/* The run's watch inside its frames (run_watch.h): progress, and the CPU budget if set. */
static int watch_run(double t, void *ctx)
{
    report(ctx, t);
    return over_budget(ctx);
}

/* One run from the saved start; its status, with the result's counts, time and detail. */
static tb_status run_one(tb_scene *scene, const tb_run_def *base, const double *start,
                         const tb_accuracy_def *def, const tb_accuracy_setting *setting,
                         comparison *c, tb_accuracy_result *out)
{
    /* The method's defaults, not the scene's integrator: a field one method reads means
     * nothing to another. atol 0: per body, from its own size (tb_scene_absolute_tolerances). */
    tb_run_def run = *base;
    run.integrator = tb_integrator_def_default();
    run.integrator.method = setting->method;
    run.integrator.max_steps = def->max_steps;
    if (tb_method_is_adaptive(setting->method)) {
        run.integrator.rtol = setting->setting;
    } else {
        run.integrator.dt = 1.0 / setting->setting;
    }
    memcpy(tb_scene_states(scene), start, tb_scene_state_size(scene) * sizeof(double));
    c->position = c->angle = c->displacement = 0.0;
    c->progress.method = setting->method;
    c->progress.setting = setting->setting;
    c->progress.duration = run.duration; /* reported from on_frame, t = 0 first */
    tb_integrator_stats stats;
    tb_error error;
    const clock_t started = clock();
    c->started = started;
    c->over = 0;
    tb__run_watch watch = {watch_run, c, TB__RUN_WATCH_EVERY};
    scene->watch = &watch;
    const tb_status status = tb_scene_run(scene, &run, on_frame, c, &stats, &error);
    scene->watch = NULL;
    memset(out, 0, sizeof *out);
    out->method = setting->method;
    out->setting = setting->setting;
    out->status = status;
    out->cpu_seconds = (double)(clock() - started) / CLOCKS_PER_SEC;
    out->steps = stats.steps;
    out->derivative_evals = stats.derivative_evals;
    if (status != TB_STATUS_OK) {
        memcpy(out->detail, error.message, sizeof out->detail);
        if (status == TB_STATUS_CANCELLED && c->recording) {
            out->status = TB_STATUS_OUT_OF_MEMORY;
            tb__set_detail(out->detail, out->status, "no memory for the reference's %zu frames",
                           c->frames);
        } else if (c->over) { /* at a frame (CANCELLED) or inside one (the derivative's) */
            out->status = TB_STATUS_TOO_MANY_STEPS;
            tb__set_detail(out->detail, out->status,
                           "stopped at t = %g s: more than %g s of CPU, %g times the reference's",
                           c->progress.t, c->cpu_limit, TB__REFERENCE_CPU_FACTOR);
        }
    }
    out->error = c->displacement;
    out->position_error = c->position;
    out->angle_error = c->angle;
    out->energy_error = fabs(c->energy - c->reference_energy);
    return out->status;
}

static tb_status validate(const tb_scene *scene, const tb_run_def *run, const tb_accuracy_def *def,
                          const tb_accuracy_result *out_results, tb_error *error)
{
    if (scene == NULL || run == NULL || out_results == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             scene == NULL ? "scene"
                             : run == NULL ? "run"
                                           : "out_results");
    }
    if (def->internal_cookie != TB__ACCURACY_COOKIE) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def: not initialised by tb_accuracy_def_default()");
    }
    const double rtols[2] = {def->reference_rtol, def->check_rtol};
    for (int k = 0; k < 2; ++k) {
        if (!isfinite(rtols[k])) {
            return tb__set_error(error, TB_STATUS_NOT_FINITE, "def.%s: got %g",
                                 k == 0 ? "reference_rtol" : "check_rtol", rtols[k]);
        }
    }
    if ((unsigned)def->reference > (unsigned)TB_ACCURACY_REFERENCE_RK4) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.reference: no such reference, got %d", (int)def->reference);
    }
    if (!(def->reference_step_fraction > 0.0 && def->reference_step_fraction <= 0.5)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.reference_step_fraction: must be in (0, 0.5], got %g",
                             def->reference_step_fraction);
    }
    if (!(def->horizon_tolerance >= 0.0)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.horizon_tolerance: must be >= 0 (0: no horizon), got %g",
                             def->horizon_tolerance);
    }
    if (def->settings == NULL && def->setting_count != 0) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER, "def.settings is NULL");
    }
    for (size_t k = 0; k < def->setting_count; ++k) {
        const tb_accuracy_setting *s = &def->settings[k];
        if ((unsigned)s->method >= (unsigned)TB_METHOD_COUNT) {
            return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                                 "def.settings[%zu].method: no such method, got %d", k,
                                 (int)s->method);
        }
        if (!isfinite(s->setting)) {
            return tb__set_error(error, TB_STATUS_NOT_FINITE, "def.settings[%zu].setting: got %g",
                                 k, s->setting);
        }
        if (!(s->setting > 0)) {
            return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                                 "def.settings[%zu].setting: must be > 0, got %g", k, s->setting);
        }
    }
    return TB_STATUS_OK;
}

static void describe(char *out, size_t size, const tb_accuracy_setting *setting)
{
    if (tb_method_is_adaptive(setting->method)) {
        snprintf(out, size, "%s at rtol %g", tb_method_name(setting->method), setting->setting);
    } else {
        snprintf(out, size, "%s at dt %.3g s", tb_method_name(setting->method),
                 1.0 / setting->setting);
    }
}

/* The reference run of pair[0] (recorded) and the check run of pair[1] (compared with it, which
 * sets the horizon). */
static tb_status reference_pair(tb_scene *scene, const tb_run_def *run, const double *start,
                                const tb_accuracy_def *def, const tb_accuracy_setting pair[2],
                                comparison *c, tb_accuracy_result *result, tb_error *error)
{
    const double tolerance = def->horizon_tolerance;
    c->frames = 0;
    c->limit = SIZE_MAX;
    c->tolerance = tolerance > 0.0 ? tolerance : INFINITY;
    for (int k = 0; k < 2; ++k) {
        c->recording = k == 0;
        c->checking = k == 1;
        c->progress.kind = k == 0 ? TB_ACCURACY_RUN_REFERENCE : TB_ACCURACY_RUN_CHECK;
        c->progress.index = 0;
        const tb_status status = run_one(scene, run, start, def, &pair[k], c, result);
        if (k == 0) {
            c->reference_cpu = result->cpu_seconds;
        }
        if (status != TB_STATUS_OK) {
            char what[80];
            describe(what, sizeof what, &pair[k]);
            c->recording = c->checking = 0;
            return tb__set_error(error, status, "%s run (%s) failed: %s",
                                 k == 0 ? "reference" : "check", what, result->detail);
        }
    }
    c->recording = c->checking = 0;
    c->limit = c->limit < c->frames ? c->limit : c->frames;
    return TB_STATUS_OK;
}

/* RK4 at fraction and twice fraction of the scene's default RK4 step at the start. */
static tb_status rk4_pair(tb_scene *scene, const double *start, const tb_accuracy_def *def,
                          tb_accuracy_setting pair[2], tb_error *error)
{
    memcpy(tb_scene_states(scene), start, tb_scene_state_size(scene) * sizeof(double));
    double dt = 0.0;
    const tb_status status = tb_scene_default_step(scene, TB_METHOD_RK4, &dt);
    if (status != TB_STATUS_OK || !(dt > 0.0 && isfinite(dt))) {
        return tb__set_error(error, status != TB_STATUS_OK ? status : TB_STATUS_INVALID_ARGUMENT,
                             "reference: no RK4 step for this scene (%s)", tb_scene_detail(scene));
    }
    const double rate = 1.0 / (def->reference_step_fraction * dt);
    pair[0] = (tb_accuracy_setting){TB_METHOD_RK4, rate};
    pair[1] = (tb_accuracy_setting){TB_METHOD_RK4, 0.5 * rate};
    return TB_STATUS_OK;
}

/* What the reference and check runs found (c after reference_pair). */
static void describe_reference(const comparison *c, const tb_accuracy_result *check,
                               const tb_accuracy_setting pair[2], tb_accuracy_reference *out)
{
    out->error = check->error;
    out->position_error = check->position_error;
    out->angle_error = check->angle_error;
    out->method = pair[0].method;
    out->setting = pair[0].setting;
    out->check_setting = pair[1].setting;
    out->horizon = c->horizon;
    out->horizon_frames = c->limit;
    out->frames = c->frames;
    out->energy_error = check->energy_error;
}

/* def for the BDF reference tried first (reference AUTO): its step budget per frame no larger
 * than the steps per frame of the RK4 reference that replaces it on failure, on a scene with
 * events (contact, ground: a right-hand side with kinks), where without the cap BDF crept
 * towards the million steps a frame allows (three dice: 100 000 steps, 64 s of CPU, before it
 * gave up at t = 0.32 s). On a smooth scene TB__SMOOTH_BDF_BUDGET times that: BDF's steps at
 * rtol 1e-11 vary within a run far more than their mean (the jointed double pendulum: 21 a
 * frame on average, 32 within its first frame, where BDF starts at order 1, and 110 were too
 * few for the frame at t = 8.68 s), so RK4's 32 ended it at t = 0.003 s (CV_TOO_MUCH_WORK) and
 * the reference fell back to RK4 (the cli test accuracy_double_pendulum). */
#define TB__SMOOTH_BDF_BUDGET 4.0
static tb_accuracy_def bdf_budget(tb_scene *scene, const tb_run_def *run, const double *start,
                                  const tb_accuracy_def *def)
{
    tb_accuracy_def capped = *def;
    tb_accuracy_setting rk4[2];
    tb_error ignored;
    if (def->reference == TB_ACCURACY_REFERENCE_AUTO && run->fps > 0.0 &&
        rk4_pair(scene, start, def, rk4, &ignored) == TB_STATUS_OK) {
        const double factor = tb__scene_has_events(scene) ? 1.0 : TB__SMOOTH_BDF_BUDGET;
        const double steps = factor * ceil(rk4[0].setting / run->fps);
        if (steps < (double)capped.max_steps) {
            capped.max_steps = (long)steps;
        }
    }
    return capped;
}

/* The reference and check runs the def asks for: CVODE BDF, RK4, or RK4 after BDF failed. */
static tb_status reference_runs(tb_scene *scene, const tb_run_def *run, const double *start,
                                const tb_accuracy_def *def, comparison *c,
                                tb_accuracy_reference *out, tb_error *out_error)
{
    tb_accuracy_setting pair[2] = {{TB_METHOD_CVODE_BDF, def->reference_rtol},
                                   {TB_METHOD_CVODE_BDF, def->check_rtol}};
    tb_accuracy_result check;
    tb_error error;
    memset(out, 0, sizeof *out);
    tb_status status = TB_STATUS_OK;
    if (def->reference != TB_ACCURACY_REFERENCE_RK4) {
        const tb_accuracy_def budget = bdf_budget(scene, run, start, def);
        status = reference_pair(scene, run, start, &budget, pair, c, &check, &error);
        if (status != TB_STATUS_OK && def->reference == TB_ACCURACY_REFERENCE_AUTO) {
            snprintf(out->cvode_detail, sizeof out->cvode_detail, "%s", error.message);
        }
    }
    if (def->reference == TB_ACCURACY_REFERENCE_RK4 || out->cvode_detail[0] != '\0') {
        status = rk4_pair(scene, start, def, pair, &error);
        if (status == TB_STATUS_OK) {
            status = reference_pair(scene, run, start, def, pair, c, &check, &error);
        }
    }
    if (status == TB_STATUS_OK) {
        describe_reference(c, &check, pair, out);
    } else if (out->cvode_detail[0] != '\0') {
        return tb__set_error(out_error, status, "%s; and RK4 instead: %s", out->cvode_detail,
                             error.message);
    } else {
        tb__set_error(out_error, status, "%s", error.message);
    }
    return status;
}

/* def for the sweep's adaptive settings on a scene with events (contact, ground): their step
 * budget per frame no larger than TB__DERIVATIVES_PER_RK4_STEP times the RK4 reference's steps
 * per frame. A CVODE step costs at least one derivative and an RK4 step four, so a setting past
 * that budget spends more derivatives on the frame than the reference itself; it fails
 * (TB_STATUS_TOO_MANY_STEPS, in its row) instead of creeping: on the twelve example dice over
 * 0.5 s BDF at rtol 1e-5 crept at the first landings for more than 16 minutes of one core with
 * the million steps a frame allows (docs/accuracy.md has the sweep's cost now). Elsewhere def's
 * budget. */
#define TB__DERIVATIVES_PER_RK4_STEP 4.0
static tb_accuracy_def adaptive_budget(tb_scene *scene, const tb_run_def *run, const double *start,
                                       const tb_accuracy_def *def)
{
    tb_accuracy_def capped = *def;
    tb_accuracy_setting rk4[2];
    tb_error ignored;
    if (tb__scene_has_events(scene) && run->fps > 0.0 &&
        rk4_pair(scene, start, def, rk4, &ignored) == TB_STATUS_OK) {
        const double steps = TB__DERIVATIVES_PER_RK4_STEP * ceil(rk4[0].setting / run->fps);
        if (steps < (double)capped.max_steps) {
            capped.max_steps = (long)steps;
        }
    }
    return capped;
}

static tb_status sweep(tb_scene *scene, const tb_run_def *run, const tb_accuracy_def *def,
                       tb_accuracy_fn on_result, void *ctx, comparison *c, const double *start,
                       tb_accuracy_result *out_results, tb_accuracy_reference *out_reference,
                       tb_error *error)
{
    tb_accuracy_reference reference;
    tb_status status = reference_runs(scene, run, start, def, c, &reference, error);
    if (out_reference != NULL) {
        *out_reference = reference;
    }
    const tb_accuracy_def adaptive = adaptive_budget(scene, run, start, def);
    /* Where the reference is RK4 (BDF could not be one: kinks, chaos), a setting that has spent
     * more CPU than the reference run costs more than the reference, the more accurate by
     * construction: past TB__REFERENCE_CPU_FACTOR times it (a margin for the machine's noise:
     * Adams at rtol 1e-9 on the dice costs 1.25 times the reference) it stops, at the next frame
     * or inside the frame (watch_run), its row failed (TB_STATUS_TOO_MANY_STEPS).
     * Without it ark-imex took 110 s on the dice (the reference 9 s); checked at frames only,
     * over 7 minutes inside the stack's first frame. */
    c->cpu_limit = status == TB_STATUS_OK && reference.method == TB_METHOD_RK4
                       ? TB__REFERENCE_CPU_FACTOR * c->reference_cpu
                       : 0.0;
    for (size_t k = 0; k < def->setting_count && status == TB_STATUS_OK; ++k) {
        c->progress.kind = TB_ACCURACY_RUN_SETTING;
        c->progress.index = k;
        const bool capped = tb_method_is_adaptive(def->settings[k].method);
        run_one(scene, run, start, capped ? &adaptive : def, &def->settings[k], c, &out_results[k]);
        if (on_result != NULL && on_result(k, &out_results[k], ctx) != 0) {
            status = tb__set_error(error, TB_STATUS_CANCELLED,
                                   "the result callback stopped the sweep after setting %zu", k);
        }
    }
    return status;
}

tb_status tb_scene_accuracy_sweep(tb_scene *scene, const tb_run_def *run,
                                  const tb_accuracy_def *def, tb_accuracy_fn on_result, void *ctx,
                                  tb_accuracy_result *out_results,
                                  tb_accuracy_reference *out_reference, tb_error *out_error)
{
    tb__clear_error(out_error);
    tb_accuracy_def chosen = def != NULL ? *def : tb_accuracy_def_default();
    if (chosen.settings == NULL && chosen.setting_count == 0) {
        chosen.settings = tb_accuracy_default_sweep(&chosen.setting_count);
    }
    tb_status status = validate(scene, run, &chosen, out_results, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    /* the bodies compared are those with a state (slots): the others move the same in both */
    const size_t bodies = scene->slot_count, size = tb_scene_state_size(scene);
    double *start = tb__malloc_array(size > 0 ? size : 1, sizeof(double));
    double *length = tb__malloc_array(bodies > 0 ? bodies : 1, sizeof(double));
    if (start == NULL || length == NULL) {
        free(start);
        free(length);
        return tb__set_error(out_error, TB_STATUS_OUT_OF_MEMORY, "no memory for %zu bodies",
                             bodies);
    }
    memcpy(start, tb_scene_states_const(scene), size * sizeof(double));
    for (size_t i = 0; i < bodies; ++i) {
        tb_mass_properties mass;
        tb_scene_get_mass(scene, scene->slot_ids[i], &mass);
        const double largest = fmax(mass.moments[0], fmax(mass.moments[1], mass.moments[2]));
        length[i] = sqrt(largest / mass.mass);
    }
    comparison c = {.bodies = bodies,
                    .length = length,
                    .progress_fn = chosen.progress,
                    .progress_ctx = chosen.progress_ctx,
                    .progress = {.count = chosen.setting_count}};
    status = sweep(scene, run, &chosen, on_result, ctx, &c, start, out_results, out_reference,
                   out_error);
    memcpy(tb_scene_states(scene), start, size * sizeof(double));
    free(c.reference);
    free(length);
    free(start);
    return status;
}

size_t tb_accuracy_cheapest(const tb_accuracy_result *results, size_t count, double target_error)
{
    size_t best = count;
    for (size_t k = 0; results != NULL && k < count; ++k) {
        if (results[k].status == TB_STATUS_OK && results[k].error <= target_error &&
            (best == count || results[k].cpu_seconds < results[best].cpu_seconds)) {
            best = k;
        }
    }
    return best;
}

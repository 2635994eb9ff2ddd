/* The accuracy sweep. The reference run's poses (centre of mass and orientation of each body
 * at each frame) are kept; every other run is compared with them frame by frame as it goes,
 * so only one trajectory is stored. */
#include "tumble/accuracy.h"

#include "core/detail.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define TB__ACCURACY_COOKIE 0x5ac1
#define TB__POSE 7 /* x[3], q[4] */

static const tb_accuracy_setting default_sweep[] = {
    {TB_METHOD_EULER, 240},        {TB_METHOD_EULER, 1000},       {TB_METHOD_EULER, 4000},
    {TB_METHOD_MIDPOINT, 60},      {TB_METHOD_MIDPOINT, 240},     {TB_METHOD_MIDPOINT, 1000},
    {TB_METHOD_RK4, 60},           {TB_METHOD_RK4, 240},          {TB_METHOD_RK4, 1000},
    {TB_METHOD_RK4, 4000},         {TB_METHOD_CVODE_ADAMS, 1e-3}, {TB_METHOD_CVODE_ADAMS, 1e-5},
    {TB_METHOD_CVODE_ADAMS, 1e-7}, {TB_METHOD_CVODE_ADAMS, 1e-9}, {TB_METHOD_CVODE_BDF, 1e-3},
    {TB_METHOD_CVODE_BDF, 1e-5},   {TB_METHOD_CVODE_BDF, 1e-7},   {TB_METHOD_CVODE_BDF, 1e-9},
};

const tb_accuracy_setting *tb_accuracy_default_sweep(size_t *out_count)
{
    if (out_count != NULL) {
        *out_count = sizeof default_sweep / sizeof default_sweep[0];
    }
    return default_sweep;
}

tb_accuracy_def tb_accuracy_def_default(void)
{
    tb_accuracy_def def;
    memset(&def, 0, sizeof def);
    def.reference_rtol = 1e-11;
    def.check_rtol = 1e-10;
    def.max_steps = 1000000;
    def.internal_cookie = TB__ACCURACY_COOKIE;
    return def;
}

/* What one run is compared with, and what the comparison found so far. */
typedef struct comparison {
    size_t bodies;
    const double *length; /* bodies: radius of gyration about the largest axis, m */
    double *reference;    /* frames x bodies x TB__POSE, grown while recording */
    size_t frames, capacity;
    int recording; /* 1: store the poses (the reference run); 0: compare with them */
    double position, angle, displacement;
} comparison;

static int record(comparison *c, const double *y)
{
    if (c->frames == c->capacity) {
        const size_t per_frame = c->bodies * TB__POSE;
        const size_t capacity = c->capacity == 0 ? 64 : 2 * c->capacity;
        if (per_frame != 0 && capacity > SIZE_MAX / sizeof(double) / per_frame) {
            return 1;
        }
        double *grown = realloc(c->reference, capacity * per_frame * sizeof(double));
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

static void compare(comparison *c, size_t frame, const double *y)
{
    for (size_t i = 0; i < c->bodies; ++i) {
        const double *p = y + TB_STATE_SIZE * i;
        const double *r = c->reference + TB__POSE * (frame * c->bodies + i);
        const double d[3] = {p[TB_STATE_X] - r[0], p[TB_STATE_X + 1] - r[1],
                             p[TB_STATE_X + 2] - r[2]};
        const double shift = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double turn = angle_between(p + TB_STATE_Q, r + 3);
        c->position = fmax(c->position, shift);
        c->angle = fmax(c->angle, turn);
        c->displacement = fmax(c->displacement, shift + c->length[i] * turn);
    }
}

static int on_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    (void)t;
    comparison *c = ctx;
    const double *y = tb_scene_states_const(scene);
    if (c->recording) {
        return record(c, y);
    }
    if (frame < c->frames) {
        compare(c, frame, y);
    }
    return 0;
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
    tb_integrator_stats stats;
    tb_error error;
    const clock_t started = clock();
    const tb_status status = tb_scene_run(scene, &run, on_frame, c, &stats, &error);
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
        }
    }
    out->error = c->displacement;
    out->position_error = c->position;
    out->angle_error = c->angle;
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

/* The reference run (recorded) and the check run (compared with it). */
static tb_status reference_runs(tb_scene *scene, const tb_run_def *run, const double *start,
                                const tb_accuracy_def *def, comparison *c,
                                tb_accuracy_reference *out_reference, tb_error *error)
{
    const tb_accuracy_setting settings[2] = {{TB_METHOD_CVODE_BDF, def->reference_rtol},
                                             {TB_METHOD_CVODE_BDF, def->check_rtol}};
    tb_accuracy_result result;
    for (int k = 0; k < 2; ++k) {
        c->recording = k == 0;
        const tb_status status = run_one(scene, run, start, def, &settings[k], c, &result);
        if (status != TB_STATUS_OK) {
            return tb__set_error(error, status, "%s run (cvode-bdf at rtol %g) failed: %s",
                                 k == 0 ? "reference" : "check", settings[k].setting,
                                 result.detail);
        }
    }
    c->recording = 0;
    if (out_reference != NULL) {
        *out_reference =
            (tb_accuracy_reference){result.error, result.position_error, result.angle_error};
    }
    return TB_STATUS_OK;
}

static tb_status sweep(tb_scene *scene, const tb_run_def *run, const tb_accuracy_def *def,
                       tb_accuracy_fn on_result, void *ctx, comparison *c, const double *start,
                       tb_accuracy_result *out_results, tb_accuracy_reference *out_reference,
                       tb_error *error)
{
    tb_status status = reference_runs(scene, run, start, def, c, out_reference, error);
    for (size_t k = 0; k < def->setting_count && status == TB_STATUS_OK; ++k) {
        run_one(scene, run, start, def, &def->settings[k], c, &out_results[k]);
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
    const size_t bodies = tb_scene_body_count(scene), size = tb_scene_state_size(scene);
    double *start = malloc(size * sizeof(double) + 1);
    double *length = malloc(bodies * sizeof(double) + 1);
    if (start == NULL || length == NULL) {
        free(start);
        free(length);
        return tb__set_error(out_error, TB_STATUS_OUT_OF_MEMORY, "no memory for %zu bodies",
                             bodies);
    }
    memcpy(start, tb_scene_states_const(scene), size * sizeof(double));
    for (size_t i = 0; i < bodies; ++i) {
        tb_mass_properties mass;
        tb_scene_get_mass(scene, i, &mass);
        const double largest = fmax(mass.moments[0], fmax(mass.moments[1], mass.moments[2]));
        length[i] = sqrt(largest / mass.mass);
    }
    comparison c = {.bodies = bodies, .length = length};
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

/* tumble accuracy: error against cost for the user's scene. The reference is CVODE BDF at
 * rtol 1e-11 (it copes with stiff contact and springs); the difference from rtol 1e-10 bounds
 * its own error (about ten times it where the runs converge). Errors are the largest over all
 * frames and bodies: position of each body's centre (m), the angle between orientations (rad),
 * and what an animator sees, the displacement |dx| + l * angle of the body's points at its
 * radius of gyration l (m). */
#define _POSIX_C_SOURCE 200809L
#include "accuracy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct trajectory {
    size_t frames, bodies;
    double *pose;   /* frames x bodies x 7: x, q */
    double *length; /* bodies: radius of gyration about the largest axis, m */
} trajectory;

typedef struct result {
    tb_method method;
    double setting, position_error, angle_error, error, cpu_ms;
    long derivatives;
    const char *note; /* "refused: unstable", "failed", or NULL */
} result;

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int record(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    (void)t;
    trajectory *out = ctx;
    if (frame >= out->frames) {
        return 0;
    }
    const double *y = tb_scene_states_const(scene);
    for (size_t i = 0; i < out->bodies; ++i) {
        memcpy(out->pose + 7 * (frame * out->bodies + i), y + TB_STATE_SIZE * i,
               7 * sizeof(double));
    }
    return 0;
}

/* Runs the scene file with the given method and setting into out; NULL note on success. */
static const char *simulate(const cli_options *o, tb_method method, double setting, trajectory *out,
                            double *cpu_ms, long *derivatives)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    if (tb_scene_load_file(o->scene, &scene, &run, &error) != TB_STATUS_OK) {
        return "failed to load";
    }
    cli_apply(o, &run, error.message, sizeof error.message); /* fps, duration */
    run.integrator.method = method;
    run.integrator.max_steps = 1000000;
    if (tb_method_is_adaptive(method)) {
        run.integrator.rtol = setting;
        run.integrator.atol = 0.0;
    } else {
        run.integrator.dt = 1.0 / setting;
    }
    tb_integrator_stats stats;
    const double start = cpu_seconds();
    const tb_status status = tb_scene_run(scene, &run, record, out, &stats, &error);
    *cpu_ms = 1e3 * (cpu_seconds() - start);
    *derivatives = stats.derivative_evals;
    tb_scene_destroy(scene);
    if (status == TB_STATUS_INVALID_ARGUMENT && strstr(error.message, "stability limit")) {
        return "refused: unstable";
    }
    return status == TB_STATUS_OK ? NULL : "failed";
}

/* Largest position error, angle error (from the relative rotation r* p, whose vector part
 * has length sin(angle / 2): atan2 keeps full precision near zero, unlike acos), and
 * displacement |dx| + l * angle. */
static void compare(const trajectory *a, const trajectory *b, double *position, double *angle,
                    double *displacement)
{
    *position = *angle = *displacement = 0.0;
    for (size_t k = 0; k < a->frames * a->bodies; ++k) {
        const double *p = a->pose + 7 * k, *r = b->pose + 7 * k;
        const double d[3] = {p[0] - r[0], p[1] - r[1], p[2] - r[2]};
        const double *pq = p + 3, *rq = r + 3;
        const double w = rq[0] * pq[0] + rq[1] * pq[1] + rq[2] * pq[2] + rq[3] * pq[3];
        const double v[3] = {rq[0] * pq[1] - rq[1] * pq[0] - rq[2] * pq[3] + rq[3] * pq[2],
                             rq[0] * pq[2] + rq[1] * pq[3] - rq[2] * pq[0] - rq[3] * pq[1],
                             rq[0] * pq[3] - rq[1] * pq[2] + rq[2] * pq[1] - rq[3] * pq[0]};
        const double turn = 2.0 * atan2(sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), fabs(w));
        const double shift = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        *position = fmax(*position, shift);
        *angle = fmax(*angle, turn);
        *displacement = fmax(*displacement, shift + a->length[k % a->bodies] * turn);
    }
}

static void svg_chart(const char *path, const result *results, size_t count, double target)
{
    FILE *out = fopen(path, "w");
    if (out == NULL) {
        fprintf(stderr, "tumble: --chart %s: cannot write\n", path);
        return;
    }
    double lo_t = INFINITY, hi_t = 0, lo_e = INFINITY, hi_e = 0;
    for (size_t k = 0; k < count; ++k) {
        if (results[k].note == NULL && results[k].error > 0) {
            lo_t = fmin(lo_t, results[k].cpu_ms), hi_t = fmax(hi_t, results[k].cpu_ms);
            lo_e = fmin(lo_e, results[k].error);
            hi_e = fmax(hi_e, results[k].error);
        }
    }
    const double x0 = floor(log10(lo_t)), x1 = ceil(log10(hi_t)) + (hi_t == lo_t);
    const double y0 = floor(log10(fmin(lo_e, target))), y1 = ceil(log10(fmax(hi_e, target)));
#define SX(v) (60.0 + 520.0 * (log10(v) - x0) / (x1 - x0))
#define SY(v) (360.0 - 320.0 * (log10(v) - y0) / (y1 - y0))
    fprintf(out, "<svg xmlns='http://www.w3.org/2000/svg' width='760' height='420' "
                 "font-family='sans-serif' font-size='12'>\n<rect width='760' height='420' "
                 "fill='white'/>\n<rect x='60' y='40' width='520' height='320' fill='none' "
                 "stroke='black'/>\n");
    for (double e = x0; e <= x1; ++e) {
        fprintf(out, "<text x='%.0f' y='378' text-anchor='middle'>1e%.0f</text>\n", SX(pow(10, e)),
                e);
    }
    for (double e = y0; e <= y1; ++e) {
        fprintf(out, "<text x='55' y='%.0f' text-anchor='end'>1e%.0f</text>\n", SY(pow(10, e)) + 4,
                e);
    }
    fprintf(out,
            "<text x='320' y='400' text-anchor='middle'>CPU time (ms)</text>\n"
            "<text x='15' y='200' transform='rotate(-90 15 200)' text-anchor='middle'>"
            "largest error (m)</text>\n<line x1='60' x2='580' y1='%.1f' "
            "y2='%.1f' stroke='gray' stroke-dasharray='4'/>\n",
            SY(target), SY(target));
    static const char *const colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd"};
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        fprintf(out, "<polyline fill='none' stroke='%s' stroke-width='2' points='", colours[m]);
        for (size_t k = 0; k < count; ++k) {
            const result *r = &results[k];
            if ((int)r->method == m && r->note == NULL && r->error > 0) {
                fprintf(out, "%.1f,%.1f ", SX(r->cpu_ms), SY(r->error));
            }
        }
        fprintf(out, "'/>\n<text x='595' y='%d' fill='%s'>%s</text>\n", 60 + 20 * m, colours[m],
                tb_method_name((tb_method)m));
    }
    fprintf(out, "</svg>\n");
#undef SX
#undef SY
    fclose(out);
}

/* The sweep: steps per second for fixed-step methods, rtol for CVODE. */
static const struct {
    tb_method method;
    double setting;
} sweep[] = {
    {TB_METHOD_EULER, 240},        {TB_METHOD_EULER, 1000},       {TB_METHOD_EULER, 4000},
    {TB_METHOD_MIDPOINT, 60},      {TB_METHOD_MIDPOINT, 240},     {TB_METHOD_MIDPOINT, 1000},
    {TB_METHOD_RK4, 60},           {TB_METHOD_RK4, 240},          {TB_METHOD_RK4, 1000},
    {TB_METHOD_RK4, 4000},         {TB_METHOD_CVODE_ADAMS, 1e-3}, {TB_METHOD_CVODE_ADAMS, 1e-5},
    {TB_METHOD_CVODE_ADAMS, 1e-7}, {TB_METHOD_CVODE_ADAMS, 1e-9}, {TB_METHOD_CVODE_BDF, 1e-3},
    {TB_METHOD_CVODE_BDF, 1e-5},   {TB_METHOD_CVODE_BDF, 1e-7},   {TB_METHOD_CVODE_BDF, 1e-9},
};
#define SWEEP (sizeof sweep / sizeof sweep[0])

static int allocate(trajectory *t, const cli_options *o)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    if (tb_scene_load_file(o->scene, &scene, &run, &error) != TB_STATUS_OK) {
        fprintf(stderr, "tumble: %s\n", error.message);
        return 0;
    }
    cli_apply(o, &run, error.message, sizeof error.message);
    t->bodies = tb_scene_body_count(scene);
    t->frames = (size_t)floor(run.duration * run.fps + 1e-9) + 1;
    t->pose = calloc(t->frames * t->bodies * 7, sizeof(double));
    t->length = calloc(t->bodies, sizeof(double));
    for (size_t i = 0; t->length != NULL && i < t->bodies; ++i) {
        tb_mass_properties mass;
        tb_scene_get_mass(scene, i, &mass);
        const double largest = fmax(mass.moments[0], fmax(mass.moments[1], mass.moments[2]));
        t->length[i] = sqrt(largest / mass.mass);
    }
    tb_scene_destroy(scene);
    return t->pose != NULL && t->length != NULL;
}

static void print_setting(char *out, size_t size, tb_method method, double setting)
{
    if (tb_method_is_adaptive(method)) {
        snprintf(out, size, "rtol %.0e", setting);
    } else {
        snprintf(out, size, "dt 1/%.0f", setting);
    }
}

int accuracy_command(const cli_options *o)
{
    trajectory reference, check, trial;
    if (!allocate(&reference, o) || !allocate(&check, o) || !allocate(&trial, o)) {
        return 2;
    }
    double ms;
    long derivatives;
    fprintf(stderr, "tumble accuracy: %s: reference runs (cvode-bdf at rtol 1e-11 and 1e-10)\n",
            o->scene);
    if (simulate(o, TB_METHOD_CVODE_BDF, 1e-11, &reference, &ms, &derivatives) != NULL ||
        simulate(o, TB_METHOD_CVODE_BDF, 1e-10, &check, &ms, &derivatives) != NULL) {
        fprintf(stderr, "tumble: the reference run failed\n");
        return 1;
    }
    double floor_position, floor_angle, floor_displacement;
    compare(&check, &reference, &floor_position, &floor_angle, &floor_displacement);
    const double target = o->has_target ? o->target_error : 1e-3;
    result results[SWEEP];
    printf("method       setting       error (m)  position (m)  angle (rad)  CPU (ms)  "
           "derivatives\n");
    for (size_t k = 0; k < SWEEP; ++k) {
        result *r = &results[k];
        r->method = sweep[k].method;
        r->setting = sweep[k].setting;
        char setting[32];
        print_setting(setting, sizeof setting, r->method, r->setting);
        fprintf(stderr, "  [%2zu/%zu] %s %s\n", k + 1, SWEEP, tb_method_name(r->method), setting);
        r->note = simulate(o, r->method, r->setting, &trial, &r->cpu_ms, &r->derivatives);
        if (r->note == NULL) {
            compare(&trial, &reference, &r->position_error, &r->angle_error, &r->error);
            printf("%-12s %-12s %10.3e  %12.3e  %11.3e  %8.2f  %11ld\n", tb_method_name(r->method),
                   setting, r->error, r->position_error, r->angle_error, r->cpu_ms, r->derivatives);
        } else {
            printf("%-12s %-12s %s\n", tb_method_name(r->method), setting, r->note);
        }
    }
    printf("\nerror: the largest displacement of a body's points at its radius of gyration,\n"
           "|dx| + l angle, over all frames and bodies, against cvode-bdf at rtol 1e-11.\n"
           "reference uncertainty (vs rtol 1e-10): %.1e m (%.1e m, %.1e rad); smaller errors are "
           "not resolved\n",
           floor_displacement, floor_position, floor_angle);
    const result *best = NULL;
    for (size_t k = 0; k < SWEEP; ++k) {
        if (results[k].note == NULL && results[k].error <= target &&
            (best == NULL || results[k].cpu_ms < best->cpu_ms)) {
            best = &results[k];
        }
    }
    if (best != NULL) {
        char setting[32];
        print_setting(setting, sizeof setting, best->method, best->setting);
        printf("cheapest setting with error <= %g m: %s, %s (%.3g m in %.2f ms)\n", target,
               tb_method_name(best->method), setting, best->error, best->cpu_ms);
    } else {
        printf("no setting in the sweep reaches an error of %g m\n", target);
    }
    if (o->chart != NULL) {
        svg_chart(o->chart, results, SWEEP, target);
    }
    trajectory *all[3] = {&reference, &check, &trial};
    for (int k = 0; k < 3; ++k) {
        free(all[k]->pose);
        free(all[k]->length);
    }
    return 0;
}

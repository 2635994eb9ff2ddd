/* Work against precision: for each reference problem, every integrator over a sweep of its
 * setting (steps per second for euler, midpoint, rk4; rtol 1e-3 .. 1e-12 for cvode-adams and
 * cvode-bdf). Error is the largest over all output frames against the reference, in the
 * quantity the problem defines (the quantity column). CPU time is the median of repeated runs.
 * Prints CSV; bench/plot_work_precision.py draws the charts in docs/.
 *
 *   top         torque-free asymmetric top, body angular velocity vs Jacobi (rad/s)
 *   separatrix  the same near the intermediate-axis separatrix (k^2 = 1 - 1e-4) (rad/s)
 *   spring      ball on a spring, position vs 1 + 0.1 cos(10 t) (m)
 *   drag        projectile with linear drag, position vs the exponential solution (m)
 *   chain       three balls on springs under gravity, position vs CVODE at rtol 1e-12,
 *               itself checked against rtol 1e-13 (m)
 *
 * usage: bench_work_precision [--quick] */
#define _POSIX_C_SOURCE 200809L
#include "bench_common.h"
#include "torque_free_top.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define MAX_FRAMES 2048

typedef struct problem {
    const char *name, *quantity, *json;
    torque_free_top top; /* for the tops */
    double (*error)(const struct problem *p, double t, const tb_scene *scene, size_t frame);
} problem;

static double reference[MAX_FRAMES][3 * 3]; /* the chain's reference positions */

static double top_error(const problem *p, double t, const tb_scene *scene, size_t frame)
{
    (void)frame;
    double R[9], w[3], exact[3], worst = 0.0;
    const double *y = tb_scene_states_const(scene);
    tb_scene_body_rotation(scene, y, 0, R);
    tb_scene_body_angular_velocity(scene, y, 0, w);
    torque_free_top_omega(&p->top, t, exact);
    for (int i = 0; i < 3; ++i) {
        const double body = R[i] * w[0] + R[3 + i] * w[1] + R[6 + i] * w[2];
        worst = fmax(worst, fabs(body - exact[i]));
    }
    return worst;
}

static double spring_error(const problem *p, double t, const tb_scene *scene, size_t frame)
{
    (void)p, (void)frame;
    return fabs(tb_scene_states_const(scene)[0] - (1.0 + 0.1 * cos(10.0 * t)));
}

static double drag_error(const problem *p, double t, const tb_scene *scene, size_t frame)
{
    (void)p, (void)frame;
    /* m = 1, b = 0.5: x = x0 + v_inf t + (v0 - v_inf) (m / b) (1 - exp(-b t / m)) */
    const double v0[3] = {4, 0, 8}, v_inf[3] = {0, 0, -9.81 / 0.5}, decay = 1 - exp(-0.5 * t);
    const double *y = tb_scene_states_const(scene);
    double worst = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double exact = v_inf[i] * t + (v0[i] - v_inf[i]) * 2.0 * decay;
        worst = fmax(worst, fabs(y[i] - exact));
    }
    return worst;
}

static double chain_error(const problem *p, double t, const tb_scene *scene, size_t frame)
{
    (void)p, (void)t;
    const double *y = tb_scene_states_const(scene);
    double worst = 0.0;
    for (int body = 0; body < 3; ++body) {
        for (int i = 0; i < 3; ++i) {
            worst = fmax(worst, fabs(y[TB_STATE_SIZE * body + i] - reference[frame][3 * body + i]));
        }
    }
    return worst;
}

typedef struct run_context {
    const problem *p;
    double worst;
    int record;
} run_context;

static int on_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    run_context *c = ctx;
    if (c->record) {
        const double *y = tb_scene_states_const(scene);
        for (int body = 0; body < 3; ++body) {
            memcpy(&reference[frame][3 * body], y + TB_STATE_SIZE * body, 3 * sizeof(double));
        }
    } else {
        c->worst = fmax(c->worst, c->p->error(c->p, t, scene, frame));
    }
    return 0;
}

/* One run; returns CPU seconds (negative on failure). */
static double run(const problem *p, tb_method method, double setting, int record, double *error,
                  tb_integrator_stats *stats)
{
    tb_scene *scene = NULL;
    tb_run_def def;
    tb_error failure;
    if (tb_scene_load_string(p->json, p->name, NULL, &scene, &def, &failure) != TB_STATUS_OK) {
        fprintf(stderr, "%s\n", failure.message);
        return -1;
    }
    tb_integrator_def_set_method(&def.integrator, method);
    def.integrator.max_steps = 1000000;
    if (tb_method_is_adaptive(method)) {
        def.integrator.rtol = setting;
    } else {
        def.integrator.dt = 1.0 / setting;
        tb_scene_set_allow_unstable(scene, true); /* the sweep shows what an unstable step gives */
    }
    run_context c = {p, 0.0, record};
    const double start = bench_cpu_seconds();
    const tb_status status = tb_scene_run(scene, &def, on_frame, &c, stats, &failure);
    const double seconds = bench_cpu_seconds() - start;
    tb_scene_destroy(scene);
    *error = status == TB_STATUS_OK ? c.worst : INFINITY;
    return seconds;
}

static const char top_json[] =
    "{\"bodies\": [{\"name\": \"top\", \"mass\": 1, \"inertia\": [1, 2, 3], "
    "\"angular_velocity_body\": [1.5, 0, 1]}], \"output\": {\"fps\": 24, \"duration\": 10}}";
static char separatrix_json[512];
static const char spring_json[] =
    "{\"bodies\": [{\"name\": \"ball\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, "
    "\"mass\": 1, \"position\": [1.1, 0, 0]}], \"effects\": [{\"type\": \"spring\", \"body_a\": "
    "\"ball\", \"point_b\": [0, 0, 0], \"stiffness\": 100, \"rest_length\": 1}], "
    "\"output\": {\"fps\": 30, \"duration\": 5}}";
static const char drag_json[] =
    "{\"bodies\": [{\"name\": \"ball\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, "
    "\"mass\": 1, \"velocity\": [4, 0, 8]}], \"effects\": [{\"type\": \"gravity\"}, "
    "{\"type\": \"drag\", \"linear\": 0.5}], \"output\": {\"fps\": 30, \"duration\": 3}}";
static const char chain_json[] =
    "{\"bodies\": ["
    "{\"name\": \"a\", \"shape\": {\"type\": \"box\", \"size\": [0.1, 0.2, 0.3]}, \"mass\": 1, "
    "\"position\": [0.1, 0, -0.3], \"angular_velocity\": [0, 0, 2]},"
    "{\"name\": \"b\", \"shape\": {\"type\": \"box\", \"size\": [0.1, 0.2, 0.3]}, \"mass\": 1, "
    "\"position\": [0.2, 0.1, -0.6]},"
    "{\"name\": \"c\", \"shape\": {\"type\": \"box\", \"size\": [0.1, 0.2, 0.3]}, \"mass\": 1, "
    "\"position\": [0.1, 0.2, -0.9]}],"
    "\"effects\": [{\"type\": \"gravity\"},"
    "{\"type\": \"spring\", \"body_a\": \"a\", \"point_a\": [0, 0, 0.15], \"point_b\": [0, 0, 0], "
    "\"stiffness\": 200, \"rest_length\": 0.1},"
    "{\"type\": \"spring\", \"body_a\": \"b\", \"point_a\": [0, 0, 0.15], \"body_b\": \"a\", "
    "\"point_b\": [0, 0, -0.15], \"stiffness\": 200, \"rest_length\": 0.05},"
    "{\"type\": \"spring\", \"body_a\": \"c\", \"point_a\": [0, 0, 0.15], \"body_b\": \"b\", "
    "\"point_b\": [0, 0, -0.15], \"stiffness\": 200, \"rest_length\": 0.05}],"
    "\"output\": {\"fps\": 30, \"duration\": 5}}";

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    const int repeats = quick ? 1 : 5;
    const double moments[3] = {1, 2, 3}, k2 = 1.0 - 1e-4, c = sqrt(1.0 / (3.0 * k2));
    snprintf(separatrix_json, sizeof separatrix_json,
             "{\"bodies\": [{\"name\": \"top\", \"mass\": 1, \"inertia\": [1, 2, 3], "
             "\"angular_velocity_body\": [1, 0, %.17g]}], \"output\": {\"fps\": 24, "
             "\"duration\": 25}}",
             c);
    problem problems[5] = {
        {"top", "angular velocity (rad/s)", top_json, {{0}, 0, 0, 0}, top_error},
        {"separatrix", "angular velocity (rad/s)", separatrix_json, {{0}, 0, 0, 0}, top_error},
        {"spring", "position (m)", spring_json, {{0}, 0, 0, 0}, spring_error},
        {"drag", "position (m)", drag_json, {{0}, 0, 0, 0}, drag_error},
        {"chain", "position (m)", chain_json, {{0}, 0, 0, 0}, chain_error},
    };
    torque_free_top_init(&problems[0].top, moments, 1.5, 1.0);
    torque_free_top_init(&problems[1].top, moments, 1.0, c);

    /* The chain's reference, and how far it is from a tighter one. */
    double unused;
    tb_integrator_stats stats;
    run(&problems[4], TB_METHOD_CVODE_ADAMS, 1e-13, 1, &unused, &stats);
    double reference_error;
    run(&problems[4], TB_METHOD_CVODE_ADAMS, 1e-12, 0, &reference_error, &stats);
    if (!quick) { /* the smoke test checks the output is nothing but CSV */
        fprintf(stderr, "chain reference (rtol 1e-12) differs from rtol 1e-13 by %.2e m\n",
                reference_error);
    }
    run(&problems[4], TB_METHOD_CVODE_ADAMS, 1e-12, 1, &unused, &stats);

    /* steps per second swept for each fixed-step method (0 ends a row) */
    static const double fixed[TB_METHOD_COUNT][5] = {
        [TB_METHOD_EULER] = {240, 1000, 4000, 16000, 0},
        [TB_METHOD_MIDPOINT] = {60, 240, 1000, 4000, 0},
        [TB_METHOD_RK4] = {24, 60, 240, 1000, 4000},
        [TB_METHOD_ROSENBROCK] = {60, 240, 1000, 4000, 16000},
    };
    printf("problem,quantity,method,setting,error,cpu_us,steps,derivatives\n");
    for (int k = 0; k < 5; ++k) {
        for (int m = 0; m < TB_METHOD_COUNT; ++m) {
            for (int s = 0; s < 10; ++s) {
                double setting;
                if (tb_method_is_adaptive((tb_method)m)) {
                    setting = pow(10.0, -3.0 - s);
                } else if (s < 5 && fixed[m][s] > 0) {
                    setting = fixed[m][s];
                } else {
                    continue;
                }
                if (quick && s > 0) {
                    continue;
                }
                double times[5], error = 0;
                for (int r = 0; r < repeats; ++r) {
                    times[r] = run(&problems[k], (tb_method)m, setting, 0, &error, &stats);
                }
                printf("%s,%s,%s,%g,%.3e,%.1f,%ld,%ld\n", problems[k].name, problems[k].quantity,
                       tb_method_name((tb_method)m), setting, error,
                       1e6 * bench_median(times, (size_t)repeats), stats.steps,
                       stats.derivative_evals);
                fflush(stdout);
            }
        }
    }
    return 0;
}

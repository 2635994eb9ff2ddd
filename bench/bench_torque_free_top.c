/* What accuracy costs, on the torque-free asymmetric top whose exact motion is known (Jacobi
 * elliptic functions): I = (1, 2, 3) kg m^2, omega_body(0) = (1.5, 0, 1) rad/s, one period
 * of its body-frame motion (8.63 s), frames at 24 fps. For each integrator and setting:
 * the largest error of the body-frame angular velocity over the frames, steps, derivative
 * evaluations, and the median CPU time of repeated runs. Prints CSV.
 *
 * usage: bench_torque_free_top [--quick] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "torque_free_top.h"
#include "bench_common.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const double moments[3] = {1.0, 2.0, 3.0};
static const double omega0[3] = {1.5, 0.0, 1.0};

typedef struct result {
    double error, seconds;
    tb_integrator_stats stats;
} result;

/* Body-frame angular velocity R^T omega of body 0. */
static void body_omega(const tb_scene *scene, double w[3])
{
    double R[9], omega[3];
    const double *y = tb_scene_states_const(scene);
    tb_scene_body_rotation(scene, y, 0, R);
    tb_scene_body_angular_velocity(scene, y, 0, omega);
    for (int i = 0; i < 3; ++i) {
        w[i] = R[i] * omega[0] + R[3 + i] * omega[1] + R[6 + i] * omega[2];
    }
}

static int run(const tb_integrator_def *def, const torque_free_top *exact, double T, result *out)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    tb_body_def body = tb_body_def_default();
    const double I[9] = {moments[0], 0, 0, 0, moments[1], 0, 0, 0, moments[2]};
    tb_mass_from_tensor(1.0, (double[]){0, 0, 0}, I, &body.mass, NULL);
    memcpy(body.angular_velocity, omega0, sizeof omega0);
    tb_integrator *integrator = NULL;
    if (tb_scene_create(&scene_def, &scene, NULL) != TB_STATUS_OK ||
        tb_scene_add_body(scene, &body, NULL) != TB_STATUS_OK ||
        tb_scene_integrator_create(scene, def, 0.0, &integrator) != TB_STATUS_OK) {
        tb_scene_destroy(scene);
        return 0;
    }
    const int frames = (int)ceil(24.0 * T);
    double elapsed = 0.0, worst = 0.0;
    int ok = 1;
    for (int f = 1; f <= frames && ok; ++f) {
        const double t = T * f / frames, start = bench_cpu_seconds();
        ok = tb_integrator_advance(integrator, t) == TB_STATUS_OK;
        elapsed += bench_cpu_seconds() - start;
        double w[3], w_exact[3];
        body_omega(scene, w);
        torque_free_top_omega(exact, t, w_exact);
        for (int i = 0; i < 3; ++i) {
            worst = fmax(worst, fabs(w[i] - w_exact[i]));
        }
    }
    out->error = worst;
    out->seconds = elapsed;
    tb_integrator_get_stats(integrator, &out->stats);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return ok;
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    const int repeats = quick ? 1 : 9;
    torque_free_top exact;
    torque_free_top_init(&exact, moments, omega0[0], omega0[2]);
    const double T = torque_free_top_period(&exact);
    static const struct {
        tb_method method;
        double setting; /* steps per second, or rtol */
        int max_order;  /* 0 for the method's own */
    } runs[] = {
        {TB_METHOD_EULER, 240, 0},
        {TB_METHOD_EULER, 2400, 0},
        {TB_METHOD_MIDPOINT, 60, 0},
        {TB_METHOD_MIDPOINT, 240, 0},
        {TB_METHOD_MIDPOINT, 1000, 0},
        {TB_METHOD_RK4, 24, 0},
        {TB_METHOD_RK4, 60, 0},
        {TB_METHOD_RK4, 240, 0},
        {TB_METHOD_RK4, 1000, 0},
        {TB_METHOD_CVODE_ADAMS, 1e-4, 0},
        {TB_METHOD_CVODE_ADAMS, 1e-6, 0},
        {TB_METHOD_CVODE_ADAMS, 1e-8, 0},
        {TB_METHOD_CVODE_ADAMS, 1e-10, 0},
        /* Adams capped at order 5 (7 history vectors fewer, docs/performance.md) */
        {TB_METHOD_CVODE_ADAMS, 1e-6, 5},
        {TB_METHOD_CVODE_ADAMS, 1e-8, 5},
        {TB_METHOD_CVODE_ADAMS, 1e-10, 5},
        {TB_METHOD_CVODE_BDF, 1e-4, 0},
        {TB_METHOD_CVODE_BDF, 1e-6, 0},
        {TB_METHOD_CVODE_BDF, 1e-8, 0},
        {TB_METHOD_CVODE_BDF, 1e-10, 0},
    };
    const size_t count = quick ? 3 : sizeof runs / sizeof runs[0];
    printf("method,setting,error_rad_per_s,steps,derivatives,cpu_us\n");
    for (size_t k = 0; k < count; ++k) {
        tb_integrator_def def = tb_integrator_def_default();
        def.method = runs[k].method;
        def.max_order = runs[k].max_order;
        if (tb_method_is_adaptive(def.method)) {
            def.rtol = runs[k].setting;
        } else {
            def.dt = 1.0 / runs[k].setting;
        }
        double times[9];
        result r;
        for (int i = 0; i < repeats; ++i) {
            if (!run(&def, &exact, T, &r)) {
                fprintf(stderr, "%s failed\n", tb_method_name(def.method));
                return 1;
            }
            times[i] = r.seconds;
        }
        printf("%s%s,%g,%.3e,%ld,%ld,%.1f\n", tb_method_name(def.method),
               runs[k].max_order == 5 ? "-order-5" : "", runs[k].setting, r.error, r.stats.steps,
               r.stats.derivative_evals, 1e6 * bench_median(times, (size_t)repeats));
    }
    return 0;
}

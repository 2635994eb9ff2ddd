/* ark-imex (ARKODE's ARKStep) against cvode-bdf with the same sparse contact Jacobian,
 * cvode-adams and rk4 at the scene's default step, on three example scenes: dice (twelve dice
 * thrown onto a table), dominoes, stack (five boxes turned on each other), their first 0.5 s at
 * rtol 1e-6 (the scenes' absolute tolerances), frames at 30 per second. Prints CSV: scene,
 * method, status (ok, the failure, or budget: stopped after the CPU budget), simulated s
 * reached, steps, error-test failures, Newton convergence failures, Jacobians, derivative
 * evaluations, CPU s, CPU s per simulated second. The processor and the load go to stderr.
 *
 * usage: bench_ark_imex [--quick] [--scene NAME] [EXAMPLES_DIR]
 * (--quick: 0.2% of the span, 0.5 s of CPU at most a run; without it 60 s) */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_args.h"
#include "bench_common.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef BENCH_EXAMPLES
#define BENCH_EXAMPLES "examples/scenes"
#endif

static tb_integrator *create(tb_scene *scene, tb_method method)
{
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator_def_set_method(&def, method);
    if (!tb_method_is_adaptive(method)) {
        def.dt = 0.0; /* the scene's default step */
    } else if (method != TB_METHOD_CVODE_ADAMS) {
        def.linear_solver = TB_LINEAR_SOLVER_SPARSE;
    }
    tb_integrator *integrator = NULL;
    if (tb_scene_integrator_create(scene, &def, 0.0, &integrator) != TB_STATUS_OK) {
        fprintf(stderr, "bench_ark_imex: %s\n", tb_scene_detail(scene));
    }
    return integrator;
}

/* One row: the scene's first span seconds under method, stopped at the first frame after budget
 * CPU seconds. */
static void run(const char *name, const char *examples, tb_method method, double span,
                double budget)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.json", examples, name);
    tb_scene *scene = NULL;
    tb_run_def settings;
    if (tb_scene_load_file(path, &scene, &settings, NULL) != TB_STATUS_OK) {
        fprintf(stderr, "bench_ark_imex: cannot load %s\n", path);
        exit(1);
    }
    tb_integrator *integrator = create(scene, method);
    tb_status status = integrator != NULL ? TB_STATUS_OK : TB_STATUS_INVALID_ARGUMENT;
    const char *what = status == TB_STATUS_OK ? "ok" : tb_status_name(status);
    const double start = bench_cpu_seconds();
    double t = 0.0;
    for (int frame = 1; status == TB_STATUS_OK && t < span - 1e-12; ++frame) {
        status = tb_integrator_advance(integrator, fmin(span, frame / 30.0));
        if (status != TB_STATUS_OK) {
            what = tb_status_name(status);
            fprintf(stderr, "bench_ark_imex: %s %s: %s\n", name, tb_method_name(method),
                    tb_integrator_detail(integrator));
            break;
        }
        t = tb_integrator_time(integrator);
        if (bench_cpu_seconds() - start > budget && t < span - 1e-12) {
            what = "budget";
            break;
        }
    }
    if (integrator != NULL) {
        t = tb_integrator_time(integrator);
    }
    const double cpu = bench_cpu_seconds() - start;
    tb_integrator_stats stats = {0};
    if (integrator != NULL) {
        tb_integrator_get_stats(integrator, &stats);
    }
    printf("%s,%s,%s,%.4g,%ld,%ld,%ld,%ld,%ld,%.4g,%.4g\n", name, tb_method_name(method), what, t,
           stats.steps, stats.error_test_failures, stats.nonlinear_failures, stats.jacobian_evals,
           stats.derivative_evals, cpu, t > 0.0 ? cpu / t : NAN);
    fflush(stdout);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(int argc, char **argv)
{
    const bench_args args = bench_parse_args(argc, argv, BENCH_EXAMPLES, false);
    bench_print_machine("bench_ark_imex");
    printf("scene,method,status,reached_s,steps,error_test_failures,newton_failures,jacobians,"
           "derivatives,cpu_s,cpu_s_per_s\n");
    static const char *const scenes[] = {"dice", "dominoes", "stack"};
    static const tb_method methods[] = {TB_METHOD_ARK_IMEX, TB_METHOD_CVODE_BDF,
                                        TB_METHOD_CVODE_ADAMS, TB_METHOD_RK4};
    for (size_t s = 0; s < sizeof scenes / sizeof scenes[0]; ++s) {
        for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
            if (bench_wanted(args.scene, scenes[s])) {
                run(scenes[s], args.examples, methods[m], args.quick ? 0.001 : 0.5,
                    args.quick ? 0.5 : 60.0);
            }
        }
    }
    return 0;
}

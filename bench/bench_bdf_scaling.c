/* How BDF's cost per step grows with the number of bodies, for the dense linear solver
 * (O(n^3) per Jacobian factorisation) and the Krylov solver with its preconditioner (block
 * diagonal here: the bodies do not interact), O(n). N free, tumbling boxes under gravity; each
 * run advances 1 s of animation at 24 fps with rtol 1e-6. Prints CSV: solver, bodies, steps,
 * derivatives per step, median CPU microseconds per step, and per step and body. Timings are
 * medians of repeated runs measured in one process; compare ratios, not absolute numbers, across
 * machines.
 *
 * usage: bench_bdf_scaling [--quick]   (--quick: small N, one repeat, for a smoke test) */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "tumble/tumble.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static tb_scene *make_scene(int bodies)
{
    tb_scene_def scene_def = tb_scene_def_default();
    scene_def.body_capacity = (size_t)bodies;
    tb_scene *scene = NULL;
    if (tb_scene_create(&scene_def, &scene, NULL) != TB_STATUS_OK) {
        return NULL;
    }
    for (int k = 0; k < bodies; ++k) {
        tb_body_def def = tb_body_def_default();
        const double size[3] = {0.1, 0.2 + 0.001 * (k % 50), 0.4};
        tb_mass_from_box(TB_MASS_DENSITY, 500.0, size, &def.mass, NULL);
        def.position[0] = k;
        def.velocity[2] = 5.0;
        def.angular_velocity[0] = 0.1;
        def.angular_velocity[1] = 4.0 + 0.01 * (k % 100);
        if (tb_scene_add_body(scene, &def, NULL) != TB_STATUS_OK) {
            tb_scene_destroy(scene);
            return NULL;
        }
    }
    tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
    return scene;
}

/* One timed run; returns CPU seconds, or a negative number on failure. */
static double run(int bodies, tb_linear_solver solver, tb_integrator_stats *stats)
{
    tb_scene *scene = make_scene(bodies);
    tb_integrator_def def = tb_integrator_def_default();
    def.method = TB_METHOD_CVODE_BDF;
    def.rtol = 1e-6;
    def.linear_solver = solver;
    tb_integrator *integrator = NULL;
    if (scene == NULL ||
        tb_scene_integrator_create(scene, &def, 0.0, &integrator) != TB_STATUS_OK) {
        tb_scene_destroy(scene);
        return -1.0;
    }
    const double start = bench_cpu_seconds();
    tb_status status = TB_STATUS_OK;
    for (int frame = 1; frame <= 24 && status == TB_STATUS_OK; ++frame) {
        status = tb_integrator_advance(integrator, frame / 24.0);
    }
    const double elapsed = bench_cpu_seconds() - start;
    if (status != TB_STATUS_OK) {
        fprintf(stderr, "%d bodies: %s\n", bodies, tb_integrator_detail(integrator));
    }
    tb_integrator_get_stats(integrator, stats);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return status == TB_STATUS_OK ? elapsed : -1.0;
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    static const int sizes[] = {1, 3, 10, 30, 100, 300, 1000, 3000};
    const int count = quick ? 4 : (int)(sizeof sizes / sizeof sizes[0]);
    const int repeats = quick ? 1 : 5;
    printf("solver,bodies,steps,derivatives_per_step,us_per_step,us_per_step_per_body\n");
    for (int solver = 0; solver < 2; ++solver) {
        const tb_linear_solver kind =
            solver == 0 ? TB_LINEAR_SOLVER_DENSE : TB_LINEAR_SOLVER_KRYLOV;
        for (int s = 0; s < count; ++s) {
            const int bodies = sizes[s];
            if (kind == TB_LINEAR_SOLVER_DENSE && bodies > 100) {
                continue; /* 1300 x 1300 dense LU per setup: minutes, and the point is made */
            }
            double times[5];
            tb_integrator_stats stats;
            for (int r = 0; r < repeats; ++r) {
                times[r] = run(bodies, kind, &stats);
                if (times[r] < 0) {
                    return 1;
                }
            }
            const double per_step =
                1e6 * bench_median(times, (size_t)repeats) / (double)stats.steps;
            printf("%s,%d,%ld,%.2f,%.2f,%.3f\n", solver == 0 ? "dense" : "krylov", bodies,
                   stats.steps, (double)stats.derivative_evals / (double)stats.steps, per_step,
                   per_step / bodies);
            fflush(stdout);
        }
    }
    return 0;
}

/* What the joints cost: a chain of ball-jointed bars (1 kg, 1 m, section 0.1 m; the first hung
 * from the world) released horizontally under gravity, stepped by RK4 at 1/240 s for 2 s of
 * simulated time: CPU microseconds per body-step (one body advanced one step: four
 * derivatives with their constraint solves, and the projection after the step), the median of
 * 7 runs. Chains of 10 (issue 21's target: at most 2 us per body-step) and 100 links show that
 * the cost is linear in the links. Prints CSV:
 *
 *   links,steps,runs,us_per_body_step,us_per_body_step_fastest
 *
 * and the processor and the load on stderr. --quick: 10 links, 0.1 s, one run (the smoke
 * test). The figures are process CPU time, so a loaded machine changes them little. */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */

#include "bench_common.h"

#include "tumble/tumble.h"

#include <math.h>

#define RUNS 7
#define DT (1.0 / 240.0)

static int fail(const char *what, tb_status status, const tb_scene *scene)
{
    fprintf(stderr, "bench_joints: %s: %s (%s)\n", what, tb_status_string(status),
            scene != NULL ? tb_scene_detail(scene) : "");
    return 1;
}

static tb_status add_link(tb_scene *scene, size_t i, size_t previous, size_t *out_id)
{
    tb_body_def body = tb_body_def_default();
    const double size[3] = {1.0, 0.1, 0.1};
    tb_status status = tb_mass_from_box(TB_MASS_GIVEN, 1.0, size, &body.mass, NULL);
    body.position[0] = (double)i + 0.5;
    if (status == TB_STATUS_OK) {
        status = tb_scene_add_body(scene, &body, out_id);
    }
    tb_joint_def joint = tb_joint_def_default();
    joint.body_a = *out_id;
    joint.body_b = previous;
    joint.anchor[0] = (double)i;
    return status == TB_STATUS_OK ? tb_scene_add_joint(scene, &joint, NULL) : status;
}

static tb_scene *make_chain(size_t links)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    tb_status status = tb_scene_create(&def, &scene, NULL);
    if (status == TB_STATUS_OK) {
        status = tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81});
    }
    size_t previous = TB_WORLD;
    for (size_t i = 0; i < links && status == TB_STATUS_OK; ++i) {
        status = add_link(scene, i, previous, &previous);
    }
    if (status != TB_STATUS_OK) {
        fail("making the chain", status, scene);
        tb_scene_destroy(scene);
        return NULL;
    }
    return scene;
}

/* One run: CPU seconds for steps RK4 steps of a new chain, or -1. */
static double time_run(size_t links, int steps)
{
    tb_scene *scene = make_chain(links);
    if (scene == NULL) {
        return -1.0;
    }
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator *integrator = NULL;
    tb_status status = tb_integrator_def_set_method(&def, TB_METHOD_RK4);
    def.dt = DT;
    if (status == TB_STATUS_OK) {
        status = tb_scene_integrator_create(scene, &def, 0.0, &integrator);
    }
    const double start = bench_cpu_seconds();
    for (int k = 0; k < steps && status == TB_STATUS_OK; ++k) {
        status = tb_integrator_step(integrator);
    }
    const double seconds = bench_cpu_seconds() - start;
    if (status != TB_STATUS_OK) {
        fail("stepping", status, scene);
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return status == TB_STATUS_OK ? seconds : -1.0;
}

static int measure(size_t links, int steps, int runs)
{
    double per_body_step[RUNS];
    for (int r = 0; r < runs; ++r) {
        const double seconds = time_run(links, steps);
        if (seconds < 0.0) {
            return 1;
        }
        per_body_step[r] = 1e6 * seconds / ((double)steps * (double)links);
    }
    const double median = bench_median(per_body_step, (size_t)runs);
    printf("%zu,%d,%d,%.4g,%.4g\n", links, steps, runs, median, per_body_step[0]);
    return 0;
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    char model[256], extensions[256];
    bench_processor(model, extensions);
    fprintf(stderr, "bench_joints: %s (%s), load %.2f\n", model, extensions, bench_load_average());
    printf("links,steps,runs,us_per_body_step,us_per_body_step_fastest\n");
    if (quick) {
        return measure(10, 24, 1);
    }
    return measure(10, 480, RUNS) || measure(100, 480, RUNS);
}

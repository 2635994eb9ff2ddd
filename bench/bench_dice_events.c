/* Twelve dice thrown onto a floor, touching the floor and each other: what CVODE costs against
 * RK4 now that its steps land on contact events (docs/effects.md, "Contact between bodies").
 *
 * Every method runs the same throw; the error is the largest distance between a die's centre
 * and the reference's, over the dice and the frames (60 per second) up to the horizon: the last
 * frame at which two independent tight references (CVODE Adams at rtol 1e-10 and RK4 at a
 * sixteenth of the default step) agree to 1e-5 m, since later a rounding-sized difference decides
 * which way a die falls. Time is the median CPU time of 3 runs (BDF: 1) over the whole throw
 * (0.5 s by default, or the frames given as the argument: by 0.5 s every die has landed).
 * Prints CSV: method,setting,steps,derivatives,failed_steps,events,cpu_ms,error_m,horizon_s.
 * --quick: a short throw, one run each. */
#define _POSIX_C_SOURCE 200809L

#include "bench_common.h"

#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DICE 12
#define FPS 60
#define SIDE 0.05  /* m */
#define MASS 0.15  /* kg: 1200 kg/m^3 */
#define AGREE 1e-5 /* m: the references agree to this up to the horizon */

/* The throw: a 3 x 4 grid 10 cm apart, 0.25 - 0.47 m up, sliding apart and spinning. */
static tb_scene *dice_scene(void)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    if (tb_scene_create(&scene_def, &scene, NULL) != TB_STATUS_OK) {
        return NULL;
    }
    const double size[3] = {SIDE, SIDE, SIDE};
    tb_contact_point corners[8];
    size_t count = 0;
    tb_contact_points_box(size, corners, 8, &count);
    for (int k = 0; k < DICE; ++k) {
        tb_body_def def = tb_body_def_default();
        tb_mass_from_box(TB_MASS_GIVEN, MASS, size, &def.mass, NULL);
        def.position[0] = 0.1 * (k % 4);
        def.position[1] = 0.1 * (k / 4);
        def.position[2] = 0.25 + 0.02 * k;
        def.velocity[0] = 0.4 * cos(1.3 * k);
        def.velocity[1] = 0.4 * sin(1.3 * k);
        def.angular_velocity[0] = 6.0 * sin(0.7 * k + 1.0);
        def.angular_velocity[1] = 6.0 * cos(0.9 * k);
        def.angular_velocity[2] = 3.0;
        size_t id = 0;
        tb_scene_add_body(scene, &def, &id);
        tb_scene_set_contact_points(scene, id, corners, count, 4);
        tb_shape shape = tb_shape_default();
        shape.type = TB_SHAPE_BOX;
        memcpy(shape.size, size, sizeof size);
        tb_scene_set_body_shape(scene, id, &shape);
    }
    tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
    const tb_ground_def ground = tb_ground_def_default();
    tb_scene_add_ground(scene, &ground);
    const tb_contact_def contact = tb_contact_def_default();
    tb_scene_add_contact(scene, &contact);
    return scene;
}

typedef struct run_result {
    double cpu_ms;
    tb_integrator_stats stats;
    tb_integrator_events events;
    int ok;
} run_result;

/* Runs the throw to frame `frames` with def, writing the dice centres of every frame into
 * centres (frames + 1 rows of 3 DICE doubles) when it is not NULL. */
static run_result run(const tb_integrator_def *def, int frames, double *centres)
{
    run_result out = {0};
    tb_scene *scene = dice_scene();
    tb_integrator *integrator = NULL;
    if (scene == NULL || tb_scene_integrator_create(scene, def, 0.0, &integrator) != 0) {
        fprintf(stderr, "set-up failed: %s\n", scene != NULL ? tb_scene_detail(scene) : "");
        tb_scene_destroy(scene);
        return out;
    }
    const double start = bench_cpu_seconds();
    out.ok = 1;
    for (int f = 0; f <= frames && out.ok; ++f) {
        if (f > 0 && tb_integrator_advance(integrator, (double)f / FPS) != TB_STATUS_OK) {
            fprintf(stderr, "%s\n", tb_integrator_detail(integrator));
            out.ok = 0;
        }
        const double *y = tb_scene_states(scene);
        for (int k = 0; centres != NULL && k < DICE; ++k) {
            memcpy(centres + (size_t)(3 * (DICE * f + k)), y + TB_STATE_SIZE * k,
                   3 * sizeof(double));
        }
    }
    out.cpu_ms = 1e3 * (bench_cpu_seconds() - start);
    tb_integrator_get_stats(integrator, &out.stats);
    tb_integrator_get_events(integrator, &out.events);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return out;
}

/* The largest distance between two runs' dice over frames [0, last]. */
static double largest_distance(const double *a, const double *b, int last)
{
    double worst = 0.0;
    for (int f = 0; f <= last; ++f) {
        for (int k = 0; k < DICE; ++k) {
            const double *p = a + 3 * (DICE * f + k), *q = b + 3 * (DICE * f + k);
            worst = fmax(worst, sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                     (p[2] - q[2]) * (p[2] - q[2])));
        }
    }
    return worst;
}

static tb_integrator_def method_def(tb_method method, double rtol, double dt)
{
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator_def_set_method(&def, method);
    if (tb_method_is_adaptive(method)) {
        def.rtol = rtol;
    } else {
        def.dt = dt;
    }
    def.max_steps = 10000000;
    return def;
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    const int frames = quick ? 3 : argc > 1 ? atoi(argv[1]) : 30, repeats = quick ? 1 : 3;
    const size_t size = (size_t)(frames + 1) * 3 * DICE;
    double *reference = malloc(size * sizeof(double)), *other = malloc(size * sizeof(double));
    double *centres = malloc(size * sizeof(double));
    tb_scene *scene = dice_scene();
    double dt = 0.0;
    tb_scene_default_step(scene, TB_METHOD_RK4, &dt);
    tb_scene_destroy(scene);
    /* the default step at the start is refused later in the throw (a tumbling die's bounds reach
     * farther, so the guard's contact rate grows): RK4 runs at half of it */
    dt *= 0.5;
    /* the horizon: where the two references part */
    tb_integrator_def tight = method_def(TB_METHOD_CVODE_ADAMS, 1e-10, 0.0);
    const run_result adams = run(&tight, frames, reference);
    tight = method_def(TB_METHOD_RK4, 0.0, (quick ? 0.5 : 0.125) * dt);
    const run_result rk4 = run(&tight, frames, other);
    if (!quick) { /* the smoke run's output is CSV alone */
        fprintf(stderr, "references: adams rtol 1e-10 %.0f ms (%ld steps), rk4 dt %.3g s %.0f ms\n",
                adams.cpu_ms, adams.stats.steps, tight.dt, rk4.cpu_ms);
    }
    int horizon = 0;
    while (horizon < frames && largest_distance(reference, other, horizon + 1) <= AGREE) {
        ++horizon;
    }
    /* max_step 2.45e-4 s: the cap of half the shortest push on every step that the step limit
     * replaced, for comparison */
    const struct {
        tb_method method;
        double rtol, max_step;
        const char *setting;
    } cases[] = {
        {TB_METHOD_RK4, 0.0, 0.0, "half default dt"},
        {TB_METHOD_CVODE_ADAMS, 1e-4, 0.0, "rtol 1e-4"},
        {TB_METHOD_CVODE_ADAMS, 1e-5, 0.0, "rtol 1e-5"},
        {TB_METHOD_CVODE_ADAMS, 1e-6, 0.0, "rtol 1e-6"},
        {TB_METHOD_CVODE_ADAMS, 1e-6, 2.45e-4, "rtol 1e-6 max_step 2.45e-4"},
        {TB_METHOD_CVODE_BDF, 1e-4, 0.0, "rtol 1e-4"},
        {TB_METHOD_CVODE_BDF, 1e-6, 0.0, "rtol 1e-6"},
    };
    printf("method,setting,steps,derivatives,failed_steps,events,cpu_ms,error_m,horizon_s\n");
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        tb_integrator_def def = method_def(cases[c].method, cases[c].rtol, dt);
        def.max_step = cases[c].max_step;
        double times[5];
        run_result result = {0};
        const int times_run = cases[c].method == TB_METHOD_CVODE_BDF ? 1 : repeats;
        for (int r = 0; r < times_run; ++r) {
            result = run(&def, frames, centres);
            times[r] = result.cpu_ms;
        }
        if (!result.ok) {
            continue;
        }
        printf("%s,%s,%ld,%ld,%ld,%ld,%.4g,%.3g,%.4g\n", tb_method_name(cases[c].method),
               cases[c].setting, result.stats.steps, result.stats.derivative_evals,
               result.stats.failed_steps, result.events.count,
               bench_median(times, (size_t)times_run),
               largest_distance(reference, centres, horizon), (double)horizon / FPS);
    }
    free(reference);
    free(other);
    free(centres);
    return 0;
}

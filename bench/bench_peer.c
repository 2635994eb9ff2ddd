/* The peer in the same run: tumble and MuJoCo (its C library, libmujoco from the mujoco-core
 * wheel; scripts/bench.sh installs it under build/) on the same scenes, run alternately so both
 * see the same load, medians of the repeats, and their ratio:
 *   boxes  N free boxes (0.1 x 0.2 x 0.3 m, 500 kg/m^3) under gravity, moving and spinning, RK4 at
 *          1/240 s, one thread: CPU ns per body-step (MuJoCo with contacts and constraints
 *          disabled: nothing touches);
 *   top    the torque-free asymmetric top, I = (1, 2, 3) kg m^2, omega_body(0) = (1, 0, 1)
 *          rad/s, for 20 s: for each engine the cheapest run whose body-frame angular velocity
 *          stays within 1e-9 rad/s of the exact solution (Jacobi elliptic functions) at every
 *          0.1 s; MuJoCo RK4 and tumble RK4 at 60 * 2^k steps a second, tumble's CVODE Adams at
 *          rtol 10^-k. The cheapest tumble run is compared with MuJoCo's.
 * The processor, its vector extensions and the vector path tumble picked go to stderr.
 * Prints CSV: case, engine, bodies, method, setting (steps/s or rtol), ns per body-step,
 * largest body-rate error (nan for boxes), CPU seconds of the timed run, and MuJoCo's time over
 * tumble's (on tumble's rows; nan without MuJoCo).
 * Built without MuJoCo, it runs tumble alone and says so.
 *
 * usage: bench_peer [--quick] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "bench_scenes.h"
#include "torque_free_top.h"
#include "tumble/tumble.h"

#include "bench_mujoco.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DT (1.0 / 240.0)
#define TOP_TIME 20.0
#define TOP_FRAMES 200 /* every 0.1 s */
#define TOP_TOLERANCE 1e-9
#define REPEATS 5

static const double top_moments[3] = {1.0, 2.0, 3.0};
static const double top_omega[3] = {1.0, 0.0, 1.0}; /* body frame = world frame at t = 0 */

/* The processor's name and vector extensions, as Linux reads them, and tumble's path. */
static void print_machine(void)
{
    char model[256], extensions[256];
    bench_processor(model, extensions);
    fprintf(stderr, "bench_peer: processor %s; vector extensions %s; tumble's path %s\n", model,
            extensions, tb_vector_path_name(tb_vector_path_best()));
}

/* --- tumble ------------------------------------------------------------------------------ */

static tb_scene *tumble_boxes(size_t bodies)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = bodies;
    tb_scene *scene = NULL;
    tb_scene_create(&def, &scene, NULL);
    bench_add_free_boxes(scene, bodies);
    return scene;
}

/* CPU seconds of `steps` RK4 steps of N boxes in one advance. */
static double tumble_boxes_seconds(size_t bodies, long steps)
{
    tb_scene *scene = tumble_boxes(bodies);
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = DT;
    tb_integrator *integrator = NULL;
    double seconds = NAN;
    if (tb_scene_integrator_create(scene, &def, 0.0, &integrator) == TB_STATUS_OK) {
        const double start = bench_cpu_seconds();
        const tb_status status = tb_integrator_advance(integrator, (double)steps * DT);
        seconds = status == TB_STATUS_OK ? bench_cpu_seconds() - start : NAN;
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return seconds;
}

/* Largest body-rate error of the top over TOP_FRAMES frames, and the CPU seconds of the
 * advances, for def; NAN error if the run failed. */
static double tumble_top(const tb_integrator_def *def, const torque_free_top *exact,
                         double *out_seconds)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    tb_body_def body = tb_body_def_default();
    const double I[9] = {top_moments[0], 0, 0, 0, top_moments[1], 0, 0, 0, top_moments[2]};
    tb_mass_from_tensor(1.0, (double[]){0, 0, 0}, I, &body.mass, NULL);
    memcpy(body.angular_velocity, top_omega, sizeof top_omega);
    tb_integrator *integrator = NULL;
    double worst = NAN, seconds = 0.0;
    if (tb_scene_create(&scene_def, &scene, NULL) == TB_STATUS_OK &&
        tb_scene_add_body(scene, &body, NULL) == TB_STATUS_OK &&
        tb_scene_integrator_create(scene, def, 0.0, &integrator) == TB_STATUS_OK) {
        worst = 0.0;
        for (int f = 1; f <= TOP_FRAMES && !isnan(worst); ++f) {
            const double t = TOP_TIME * f / TOP_FRAMES, start = bench_cpu_seconds();
            const tb_status status = tb_integrator_advance(integrator, t);
            seconds += bench_cpu_seconds() - start;
            double R[9], omega[3], w_exact[3];
            const double *y = tb_scene_states_const(scene);
            tb_scene_body_rotation(scene, y, 0, R);
            tb_scene_body_angular_velocity(scene, y, 0, omega);
            torque_free_top_omega(exact, t, w_exact);
            for (int i = 0; i < 3 && status == TB_STATUS_OK; ++i) {
                const double w = R[i] * omega[0] + R[3 + i] * omega[1] + R[6 + i] * omega[2];
                worst = fmax(worst, fabs(w - w_exact[i]));
            }
            worst = status == TB_STATUS_OK ? worst : NAN;
        }
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    *out_seconds = seconds;
    return worst;
}

/* --- MuJoCo ------------------------------------------------------------------------------ */

#ifdef TUMBLE_BENCH_MUJOCO
/* N boxes as above: free joints, no contact, no constraint; qvel (v world, omega local). */
static double mujoco_boxes_seconds(size_t bodies, long steps)
{
    const size_t size = 512 + 128 * bodies;
    char *xml = malloc(size);
    if (xml == NULL) {
        return NAN;
    }
    size_t used = (size_t)snprintf(xml, size,
                                   "<mujoco><size memory=\"%zuM\"/><option timestep=\"%.17g\" "
                                   "integrator=\"RK4\" gravity=\"0 0 -9.81\"><flag "
                                   "contact=\"disable\" constraint=\"disable\"/></option>"
                                   "<worldbody>",
                                   16 + bodies / 64, DT);
    for (size_t i = 0; i < bodies; ++i) {
        used += (size_t)snprintf(xml + used, size - used,
                                 "<body pos=\"%zu 0 0\"><freejoint/><geom type=\"box\" "
                                 "size=\"%g %g %g\" density=\"500\"/></body>",
                                 i, bench_box_size[0] / 2, bench_box_size[1] / 2,
                                 bench_box_size[2] / 2);
    }
    snprintf(xml + used, size - used, "</worldbody></mujoco>");
    mjModel *model = bench_mujoco_model("bench_peer", xml);
    free(xml);
    if (model == NULL) {
        return NAN;
    }
    mjData *data = mj_makeData(model);
    for (size_t i = 0; i < bodies; ++i) {
        const double qvel[6] = {0, 0, 3.0, 1.0, 2.0, 0};
        memcpy(data->qvel + 6 * i, qvel, sizeof qvel);
    }
    const double start = bench_cpu_seconds();
    for (long k = 0; k < steps; ++k) {
        mj_step(model, data);
    }
    const double seconds = bench_cpu_seconds() - start;
    mj_deleteData(data);
    mj_deleteModel(model);
    return seconds;
}

/* The top at steps_per_second with RK4: largest body-rate error (qvel's angular part is in the
 * body frame) and CPU seconds of the steps. */
static double mujoco_top(double steps_per_second, const torque_free_top *exact, double *out_seconds)
{
    char xml[512];
    snprintf(xml, sizeof xml,
             "<mujoco><option timestep=\"%.17g\" integrator=\"RK4\" gravity=\"0 0 0\"/>"
             "<worldbody><body><freejoint/><inertial pos=\"0 0 0\" mass=\"1\" "
             "diaginertia=\"%g %g %g\"/></body></worldbody></mujoco>",
             1.0 / steps_per_second, top_moments[0], top_moments[1], top_moments[2]);
    mjModel *model = bench_mujoco_model("bench_peer", xml);
    if (model == NULL) {
        return NAN;
    }
    mjData *data = mj_makeData(model);
    memcpy(data->qvel + 3, top_omega, sizeof top_omega);
    const long per_frame = lround(steps_per_second * TOP_TIME / TOP_FRAMES);
    double worst = 0.0, seconds = 0.0;
    for (int f = 1; f <= TOP_FRAMES; ++f) {
        const double start = bench_cpu_seconds();
        for (long k = 0; k < per_frame; ++k) {
            mj_step(model, data);
        }
        seconds += bench_cpu_seconds() - start;
        double w_exact[3];
        torque_free_top_omega(exact, TOP_TIME * f / TOP_FRAMES, w_exact);
        for (int i = 0; i < 3; ++i) {
            worst = fmax(worst, fabs(data->qvel[3 + i] - w_exact[i]));
        }
    }
    mj_deleteData(data);
    mj_deleteModel(model);
    *out_seconds = seconds;
    return worst;
}
#endif

/* --- the cases --------------------------------------------------------------------------- */

static void row(const char *scene, const char *engine, size_t bodies, const char *method,
                double setting, double ns, double error, double seconds, double ratio)
{
    printf("%s,%s,%zu,%s,%g,%.1f,%.3g,%.6f,%.2f\n", scene, engine, bodies, method, setting, ns,
           error, seconds, ratio);
}

static void boxes(size_t bodies, int repeats, double body_steps)
{
    const long tumble_steps = (long)(body_steps / (double)bodies) + 10;
    double tumble[REPEATS], peer[REPEATS];
    int have_peer = 0;
    for (int r = 0; r < repeats; ++r) { /* alternately, so both see the same load */
        tumble[r] = tumble_boxes_seconds(bodies, tumble_steps);
        peer[r] = NAN;
#ifdef TUMBLE_BENCH_MUJOCO
        peer[r] = mujoco_boxes_seconds(bodies, tumble_steps / 10 + 10);
        have_peer = 1;
#endif
    }
    const double t = bench_median(tumble, (size_t)repeats);
    const double ns = 1e9 * t / (double)tumble_steps / (double)bodies;
    const double peer_ns = have_peer ? 1e9 * bench_median(peer, (size_t)repeats) /
                                           (double)(tumble_steps / 10 + 10) / (double)bodies
                                     : NAN;
    row("boxes", "tumble", bodies, "rk4", 1.0 / DT, ns, NAN, t, peer_ns / ns);
    if (have_peer) {
        row("boxes", "mujoco", bodies, "rk4", 1.0 / DT, peer_ns, NAN,
            peer_ns * 1e-9 * (double)bodies * (double)(tumble_steps / 10 + 10), 1.0);
    }
}

/* One top run per engine and setting: the median CPU time of `repeats`; the error of the last
 * (the same every time). */
typedef struct top_run {
    const char *method;
    double setting, error, seconds;
} top_run;

static top_run tumble_top_run(tb_method method, double setting, int repeats,
                              const torque_free_top *exact)
{
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator_def_set_method(&def, method);
    if (tb_method_is_adaptive(method)) {
        def.rtol = setting;
        def.max_steps = 1000000;
    } else {
        def.dt = 1.0 / setting;
        def.max_steps = 10000000;
    }
    double times[REPEATS], error = NAN;
    for (int r = 0; r < repeats; ++r) {
        error = tumble_top(&def, exact, &times[r]);
    }
    return (top_run){tb_method_name(method), setting, error, bench_median(times, (size_t)repeats)};
}

/* The cheapest setting of a ladder that meets TOP_TOLERANCE (first = coarsest). */
static top_run tumble_top_best(tb_method method, const double *ladder, int count, int repeats,
                               const torque_free_top *exact)
{
    top_run run = {tb_method_name(method), NAN, NAN, NAN};
    for (int k = 0; k < count; ++k) {
        run = tumble_top_run(method, ladder[k], 1, exact);
        if (run.error <= TOP_TOLERANCE) {
            return tumble_top_run(method, ladder[k], repeats, exact);
        }
    }
    return run;
}

static void top(int quick, int repeats)
{
    torque_free_top exact;
    torque_free_top_init(&exact, top_moments, top_omega[0], top_omega[2]);
    static const double rates[] = {60, 120, 240, 480, 960, 1920, 3840, 7680, 15360, 30720};
    static const double rtols[] = {1e-9, 1e-10, 1e-11, 1e-12, 1e-13};
    const int rate_count = quick ? 1 : (int)(sizeof rates / sizeof rates[0]);
    const top_run rk4 =
        tumble_top_best(TB_METHOD_RK4, quick ? rates + 3 : rates, rate_count, repeats, &exact);
    const top_run adams =
        tumble_top_best(TB_METHOD_CVODE_ADAMS, rtols, quick ? 1 : 5, repeats, &exact);
    double peer_seconds = NAN, peer_error = NAN, peer_rate = NAN;
#ifdef TUMBLE_BENCH_MUJOCO
    for (int k = quick ? 3 : 0; k < (quick ? 4 : rate_count); ++k) {
        double times[REPEATS];
        peer_error = mujoco_top(rates[k], &exact, &times[0]);
        peer_rate = rates[k];
        if (peer_error <= TOP_TOLERANCE || quick) {
            for (int r = 1; r < repeats; ++r) {
                mujoco_top(rates[k], &exact, &times[r]);
            }
            peer_seconds = bench_median(times, (size_t)repeats);
            break;
        }
    }
#endif
    const top_run *runs[2] = {&rk4, &adams};
    for (int k = 0; k < 2; ++k) {
        const double steps = runs[k] == &rk4 ? runs[k]->setting * TOP_TIME : NAN;
        row("top", "tumble", 1, runs[k]->method, runs[k]->setting, 1e9 * runs[k]->seconds / steps,
            runs[k]->error, runs[k]->seconds, peer_seconds / runs[k]->seconds);
    }
    if (!isnan(peer_rate)) {
        row("top", "mujoco", 1, "rk4", peer_rate, 1e9 * peer_seconds / (peer_rate * TOP_TIME),
            peer_error, peer_seconds, 1.0);
    }
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    const int repeats = quick ? 1 : REPEATS;
    print_machine();
#ifdef TUMBLE_BENCH_MUJOCO
    fprintf(stderr, "bench_peer: MuJoCo %s\n", mj_versionString());
#else
    fprintf(stderr, "bench_peer: built without MuJoCo (scripts/bench.sh installs it under "
                    "build/bench-venv): tumble's rows only\n");
#endif
    printf("case,engine,bodies,method,setting,ns_per_body_step,body_rate_error,cpu_seconds,"
           "mujoco_over_tumble\n");
    static const size_t sizes[] = {100, 1000, 10000};
    for (size_t s = 0; s < (quick ? 1 : sizeof sizes / sizeof sizes[0]); ++s) {
        boxes(sizes[s], repeats, quick ? 2e4 : 2e6);
    }
    top(quick, repeats);
    return 0;
}

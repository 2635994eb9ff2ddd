/* Contact in the peer's hands and in tumble's, in the same run (MuJoCo's C library from the
 * mujoco-core wheel, as bench_peer), and what each setting buys:
 *   pile   200 boxes of bench_scenes.h (10 cm, 0.5 kg, columns 8 high on the floor) released at
 *          rest, 0.1 s: ns per body-step (median of 3, the engines alternately), the deepest
 *          penetration at the end (floor or the box below, from the corners' heights: the same
 *          code for both engines) and the fastest body then (at rest: small);
 *   cloud  the same 200 boxes in a 6 x 6 x 6 lattice 2 cm apart, no gravity, no floor, thrown at
 *          each other (up to 1 m/s and 5 rad/s per component, seeded) for 0.03 s: the change of
 *          total linear momentum over the sum of the bodies' |P|;
 *   die    a 5 cm, 100 g die dropped face first from 1 m onto the floor: the deepest corner
 *          through the impact (the target: 2 mm);
 *   ball   a 5 cm ball of 1000 kg/m^3 dropped from 0.5 m onto the floor with restitution 0.5:
 *          the measured ratio of rebound to impact speed (MuJoCo has no restitution parameter:
 *          its row says what its default soft contact gives).
 * tumble: the default contact (penetration 8e-7 m, mu_s 0.6, mu_k 0.5), RK4 at the scene's
 * default step (and a half and a quarter of it), CVODE Adams and BDF at rtol 1e-4 to 1e-8.
 * MuJoCo: its defaults (Euler, soft contact solref 0.02 s critically damped, Newton solver,
 * pyramidal cone, friction 0.5: one coefficient where tumble has mu_s and mu_k), at tumble's RK4
 * step and at its own default 2 ms (the drops also at 0.5 ms). What differs is said beside the
 * numbers in docs/accuracy.md: MuJoCo solves for soft constraint forces each step, tumble
 * integrates a compliant penalty law.
 *
 * Prints CSV: case, engine, bodies, method, setting (step s or rtol), ns per body-step, CPU
 * seconds, steps, then the case's figure: deepest penetration (m; pile, die), momentum error
 * (cloud), restitution (ball), and the fastest body at the end (m/s; pile) or nan. The
 * processor and the load average go to stderr. Built without MuJoCo, tumble's rows only.
 *
 * usage: bench_peer_contact [--quick] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "bench_scenes.h"
#include "tumble/tumble.h"

#include "bench_mujoco.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REPEATS 3
#define CLOUD_SIDE 6
#define CLOUD_PITCH 0.12
#define DIE_EDGE 0.05
#define DIE_MASS 0.1
#define DIE_DROP 1.0
#define BALL_DROP 0.5
#define BALL_RESTITUTION 0.5
#define MUJOCO_DEFAULT_STEP 0.002

typedef enum { CASE_PILE, CASE_CLOUD, CASE_DIE, CASE_BALL } case_kind;
static const char *const case_names[] = {"pile", "cloud", "die", "ball"};

/* What one run measured. */
typedef struct result {
    double seconds, figure, speed;
    long steps;
} result;

/* --- the figures, from poses: the same for both engines -------------------------------------- */

/* Lowest and highest corner heights of a cube of edge `edge` at centre x, rotation R (row-major,
 * shape to world). */
static void corner_heights(const double x[3], const double R[9], double edge, double *low,
                           double *high)
{
    const double h = 0.5 * edge;
    const double reach = h * (fabs(R[6]) + fabs(R[7]) + fabs(R[8]));
    *low = x[2] - reach;
    *high = x[2] + reach;
}

/* Deepest penetration of the pile: each box into the floor or into the box it rests on. */
static double pile_depth(size_t count, const double *x, const double *R)
{
    double deepest = -INFINITY;
    for (size_t i = 0; i < count; ++i) {
        double low, high, below_low, below_high;
        corner_heights(x + 3 * i, R + 9 * i, BENCH_PILE_EDGE, &low, &high);
        if (bench_pile_on_box(i)) {
            corner_heights(x + 3 * (i - 1), R + 9 * (i - 1), BENCH_PILE_EDGE, &below_low,
                           &below_high);
            deepest = fmax(deepest, below_high - low);
        } else {
            deepest = fmax(deepest, -low);
        }
    }
    return deepest;
}

static void cloud_position(size_t i, double out[3])
{
    out[0] = CLOUD_PITCH * (double)(i % CLOUD_SIDE);
    out[1] = CLOUD_PITCH * (double)(i / CLOUD_SIDE % CLOUD_SIDE);
    out[2] = CLOUD_PITCH * (double)(i / (CLOUD_SIDE * CLOUD_SIDE));
}

/* Body i's velocity and angular velocity (world = body frame at the start), seeded. */
static void cloud_motion(size_t i, double v[3], double w[3])
{
    unsigned long long rng = 1000 + i;
    for (int k = 0; k < 3; ++k) {
        v[k] = bench_uniform(&rng, -1.0, 1.0);
        w[k] = bench_uniform(&rng, -5.0, 5.0);
    }
}

/* --- tumble ---------------------------------------------------------------------------------- */

static tb_scene *tumble_cloud(size_t count)
{
    tb_scene *scene = bench_box_pile(count, BENCH_CONTACT);
    for (size_t i = 0; scene != NULL && i < count; ++i) {
        tb_body_state s;
        tb_scene_get_state(scene, i, &s);
        cloud_position(i, s.x);
        tb_scene_set_state(scene, i, &s);
        double v[3], w[3];
        cloud_motion(i, v, w);
        tb_scene_set_velocity(scene, i, v, w);
    }
    return scene;
}

/* One body of edge/radius `size` dropped with its bottom at `drop`: the die (box) or the ball. */
static tb_scene *tumble_drop(case_kind kind)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    tb_scene_create(&def, &scene, NULL);
    tb_body_def body = tb_body_def_default();
    tb_contact_point points[8];
    size_t count = 0, support = 1;
    const double r = BENCH_SPHERE_RADIUS, size[3] = {DIE_EDGE, DIE_EDGE, DIE_EDGE};
    tb_ground_def ground = tb_ground_def_default();
    if (kind == CASE_DIE) {
        tb_mass_from_box(TB_MASS_GIVEN, DIE_MASS, size, &body.mass, NULL);
        body.position[2] = DIE_DROP + 0.5 * DIE_EDGE;
        tb_contact_points_box(size, points, 8, &count);
        support = 4;
    } else {
        tb_mass_from_sphere(TB_MASS_DENSITY, BENCH_SPHERE_DENSITY, r, &body.mass, NULL);
        body.position[2] = BALL_DROP + r;
        tb_contact_points_sphere(r, points, 8, &count);
        ground.restitution = BALL_RESTITUTION;
    }
    tb_scene_add_body(scene, &body, NULL);
    tb_scene_set_contact_points(scene, 0, points, count, support);
    tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
    tb_scene_add_ground(scene, &ground);
    return scene;
}

static double tumble_pile_figure(const tb_scene *scene, size_t count, double *out_speed)
{
    double *x = malloc(3 * count * sizeof *x), *R = malloc(9 * count * sizeof *R);
    double depth = NAN;
    *out_speed = 0.0;
    const double *y = tb_scene_states_const(scene);
    static const double origin[3] = {0, 0, 0};
    for (size_t i = 0; x != NULL && R != NULL && i < count; ++i) {
        double v[3], e[3], u[3] = {1, 0, 0};
        tb_scene_body_point(scene, y, i, origin, x + 3 * i, v);
        *out_speed = fmax(*out_speed, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        for (int a = 0; a < 3; ++a) { /* the shape frame's axes in the world: R's columns */
            u[0] = a == 0, u[1] = a == 1, u[2] = a == 2;
            tb_scene_body_point(scene, y, i, u, e, NULL);
            for (int k = 0; k < 3; ++k) {
                R[9 * i + 3 * k + a] = e[k] - x[3 * i + k];
            }
        }
    }
    if (x != NULL && R != NULL) {
        depth = pile_depth(count, x, R);
    }
    free(x);
    free(R);
    return depth;
}

static double total_momentum_error(const tb_scene *scene, const double P0[3], double scale)
{
    double P[3];
    tb_scene_linear_momentum(scene, tb_scene_states_const(scene), P);
    return sqrt((P[0] - P0[0]) * (P[0] - P0[0]) + (P[1] - P0[1]) * (P[1] - P0[1]) +
                (P[2] - P0[2]) * (P[2] - P0[2])) /
           scale;
}

/* The sum of the bodies' |P| at the scene's state. */
static double momentum_scale(const tb_scene *scene)
{
    double sum = 0.0;
    for (size_t i = 0; i < tb_scene_body_count(scene); ++i) {
        tb_body_state s;
        tb_scene_get_state(scene, i, &s);
        sum += sqrt(s.P[0] * s.P[0] + s.P[1] * s.P[1] + s.P[2] * s.P[2]);
    }
    return sum;
}

/* The die's lowest corner or the ball's vertical velocity, tracked: deepest, or the impact
 * (most negative v_z) and the fastest rise after it. */
typedef struct drop_track {
    double deepest, impact, rebound;
} drop_track;

static void track_drop(const tb_scene *scene, case_kind kind, drop_track *t)
{
    const double *y = tb_scene_states_const(scene);
    if (kind == CASE_DIE) {
        for (int j = 0; j < 8; ++j) {
            const double h = 0.5 * DIE_EDGE;
            const double p[3] = {j & 1 ? h : -h, j & 2 ? h : -h, j & 4 ? h : -h};
            double world[3];
            tb_scene_body_point(scene, y, 0, p, world, NULL);
            t->deepest = fmax(t->deepest, -world[2]);
        }
    } else {
        double v[3];
        tb_scene_body_velocity(scene, y, 0, v);
        if (v[2] < t->impact) {
            t->impact = v[2];
            t->rebound = 0.0;
        }
        t->rebound = fmax(t->rebound, v[2]);
    }
}

/* How long each case runs (s). */
static double case_duration(case_kind kind, int quick)
{
    static const double full[] = {0.1, 0.03, 0.5, 0.35}, brief[] = {0.002, 0.002, 0.5, 0.35};
    return quick ? brief[kind] : full[kind];
}

/* The scene of a case, 0 < count for the pile and the cloud. */
static tb_scene *tumble_case(case_kind kind, size_t count)
{
    switch (kind) {
    case CASE_PILE:
        return bench_box_pile(count, BENCH_ALL);
    case CASE_CLOUD:
        return tumble_cloud(count);
    default:
        return tumble_drop(kind);
    }
}

/* The integrator for a setting: fixed steps of `setting` s, or CVODE at rtol `setting`. */
static tb_integrator *tumble_integrator(tb_scene *scene, tb_method method, double setting)
{
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator_def_set_method(&def, method);
    def.max_steps = 100000000;
    if (tb_method_is_adaptive(method)) {
        def.rtol = setting;
    } else {
        def.dt = setting;
    }
    tb_integrator *integrator = NULL;
    if (tb_scene_integrator_create(scene, &def, 0.0, &integrator) != TB_STATUS_OK) {
        fprintf(stderr, "bench_peer_contact: %s at %g refused: %s\n", tb_method_name(method),
                setting, tb_scene_detail(scene));
    }
    return integrator;
}

/* One run of a case in one advance, or, `sampled`, a drop sampled every step of a fixed method
 * and every 10 us of CVODE's interpolant (which leaves its steps as they are; the samples' cost
 * is why the drops are timed in a run of their own). */
static result tumble_run(case_kind kind, size_t count, tb_method method, double setting, int quick,
                         int sampled)
{
    result r = {NAN, NAN, NAN, 0};
    tb_scene *scene = tumble_case(kind, count);
    tb_integrator *integrator = scene != NULL ? tumble_integrator(scene, method, setting) : NULL;
    const double duration = case_duration(kind, quick);
    const double P_scale = scene != NULL ? momentum_scale(scene) : NAN;
    double P0[3] = {0, 0, 0};
    if (integrator != NULL) {
        tb_scene_linear_momentum(scene, tb_scene_states_const(scene), P0);
        drop_track track = {0.0, 0.0, 0.0};
        const double sample = tb_method_is_adaptive(method) ? 1e-5 : setting;
        const long samples = sampled ? lround(duration / sample) : 1;
        tb_status status = TB_STATUS_OK;
        const double start = bench_cpu_seconds();
        for (long k = 1; k <= samples && status == TB_STATUS_OK; ++k) {
            status = tb_integrator_advance(integrator, duration * (double)k / (double)samples);
            if (sampled) {
                track_drop(scene, kind, &track);
            }
        }
        r.seconds = bench_cpu_seconds() - start;
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        r.steps = stats.steps;
        if (status != TB_STATUS_OK) {
            fprintf(stderr, "bench_peer_contact: %s: %s\n", case_names[kind],
                    tb_integrator_detail(integrator));
            r.seconds = NAN;
        } else if (kind == CASE_PILE) {
            r.figure = tumble_pile_figure(scene, count, &r.speed);
        } else if (kind == CASE_CLOUD) {
            r.figure = total_momentum_error(scene, P0, P_scale);
        } else {
            r.figure = kind == CASE_DIE ? track.deepest : track.rebound / -track.impact;
        }
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return r;
}

/* tumble's RK4 default step on a case. */
static double tumble_default_step(case_kind kind, size_t count)
{
    tb_scene *scene = tumble_case(kind, count);
    double dt = NAN;
    if (scene != NULL) {
        tb_scene_default_step(scene, TB_METHOD_RK4, &dt);
    }
    tb_scene_destroy(scene);
    return dt;
}

/* --- MuJoCo ---------------------------------------------------------------------------------- */

#ifdef TUMBLE_BENCH_MUJOCO
/* The case's model at step dt: the same bodies, sizes, masses and start as tumble's. */
static mjModel *mujoco_case(case_kind kind, size_t count, double dt)
{
    const size_t size = 1024 + 256 * count;
    char *xml = malloc(size);
    if (xml == NULL) {
        return NULL;
    }
    size_t used = (size_t)snprintf(
        xml, size,
        "<mujoco><size memory=\"%zuM\"/><option timestep=\"%.17g\" gravity=\"0 0 %g\"/>"
        "<default><geom friction=\"0.5 0.005 0.0001\"/></default><worldbody>%s",
        64 + count / 8, dt, kind == CASE_CLOUD ? 0.0 : -9.81,
        kind == CASE_CLOUD ? "" : "<geom type=\"plane\" size=\"0 0 1\"/>");
    const double h = 0.5 * BENCH_PILE_EDGE;
    for (size_t i = 0; i < count; ++i) {
        double x[3];
        if (kind == CASE_PILE) {
            bench_pile_position(i, count, x);
        } else {
            cloud_position(i, x);
        }
        used += (size_t)snprintf(xml + used, size - used,
                                 "<body pos=\"%.17g %.17g %.17g\"><freejoint/><geom type=\"box\" "
                                 "size=\"%g %g %g\" density=\"%g\"/></body>",
                                 x[0], x[1], x[2], h, h, h, BENCH_PILE_DENSITY);
    }
    if (kind == CASE_DIE) {
        used += (size_t)snprintf(xml + used, size - used,
                                 "<body pos=\"0 0 %.17g\"><freejoint/><geom type=\"box\" "
                                 "size=\"%g %g %g\" mass=\"%g\"/></body>",
                                 DIE_DROP + 0.5 * DIE_EDGE, 0.5 * DIE_EDGE, 0.5 * DIE_EDGE,
                                 0.5 * DIE_EDGE, DIE_MASS);
    } else if (kind == CASE_BALL) {
        used += (size_t)snprintf(xml + used, size - used,
                                 "<body pos=\"0 0 %.17g\"><freejoint/><geom type=\"sphere\" "
                                 "size=\"%g\" density=\"%g\"/></body>",
                                 BALL_DROP + BENCH_SPHERE_RADIUS, BENCH_SPHERE_RADIUS,
                                 BENCH_SPHERE_DENSITY);
    }
    snprintf(xml + used, size - used, "</worldbody></mujoco>");
    mjModel *model = bench_mujoco_model("bench_peer_contact", xml);
    free(xml);
    return model;
}

/* Total linear momentum: each body's mass times its free joint's linear velocity (world, at the
 * body's origin, its centre of mass here). */
static void mujoco_momentum(const mjModel *m, const mjData *d, double P[3], double *scale)
{
    P[0] = P[1] = P[2] = 0.0;
    *scale = 0.0;
    for (int b = 1; b < m->nbody; ++b) {
        const mjtNum *v = d->qvel + 6 * (b - 1);
        for (int k = 0; k < 3; ++k) {
            P[k] += m->body_mass[b] * v[k];
        }
        *scale += m->body_mass[b] * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
}

static void mujoco_figure(const mjModel *m, const mjData *d, case_kind kind, size_t count,
                          const double P0[3], double P_scale, result *r)
{
    if (kind == CASE_PILE) {
        r->figure = pile_depth(count, d->xpos + 3, d->xmat + 9);
        r->speed = 0.0;
        for (int b = 0; b < m->nv / 6; ++b) {
            const mjtNum *v = d->qvel + 6 * b;
            r->speed = fmax(r->speed, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        }
    } else if (kind == CASE_CLOUD) {
        double P[3], scale;
        mujoco_momentum(m, d, P, &scale);
        r->figure = sqrt((P[0] - P0[0]) * (P[0] - P0[0]) + (P[1] - P0[1]) * (P[1] - P0[1]) +
                         (P[2] - P0[2]) * (P[2] - P0[2])) /
                    P_scale;
    }
}

static result mujoco_run(case_kind kind, size_t count, double dt, int quick)
{
    result r = {NAN, NAN, NAN, 0};
    mjModel *m = mujoco_case(kind, kind <= CASE_CLOUD ? count : 0, dt);
    if (m == NULL) {
        return r;
    }
    mjData *d = mj_makeData(m);
    for (size_t i = 0; kind == CASE_CLOUD && i < count; ++i) {
        cloud_motion(i, d->qvel + 6 * i, d->qvel + 6 * i + 3); /* angular: body frame = world */
    }
    double P0[3], P_scale;
    mujoco_momentum(m, d, P0, &P_scale);
    const long steps = lround(case_duration(kind, quick) / dt);
    drop_track track = {0.0, 0.0, 0.0};
    const double start = bench_cpu_seconds();
    for (long k = 0; k < steps; ++k) {
        mj_step(m, d);
        if (kind == CASE_DIE) {
            double low, high;
            corner_heights(d->xpos + 3, d->xmat + 9, DIE_EDGE, &low, &high);
            track.deepest = fmax(track.deepest, -low);
        } else if (kind == CASE_BALL) {
            if (d->qvel[2] < track.impact) {
                track.impact = d->qvel[2];
                track.rebound = 0.0;
            }
            track.rebound = fmax(track.rebound, d->qvel[2]);
        }
    }
    r.seconds = bench_cpu_seconds() - start;
    r.steps = steps;
    mujoco_figure(m, d, kind, count, P0, P_scale, &r);
    if (kind >= CASE_DIE) {
        r.figure = kind == CASE_DIE ? track.deepest : track.rebound / -track.impact;
    }
    mj_deleteData(d);
    mj_deleteModel(m);
    return r;
}
#endif

/* --- the cases ------------------------------------------------------------------------------- */

static void row(case_kind kind, const char *engine, size_t bodies, const char *method,
                double setting, const result *r)
{
    const double ns = 1e9 * r->seconds / ((double)r->steps * (double)bodies);
    printf("%s,%s,%zu,%s,%.3g,%.1f,%.4g,%ld,%.3g,%.3g\n", case_names[kind], engine, bodies, method,
           setting, ns, r->seconds, r->steps, r->figure, r->speed);
}

/* The many-body cases: tumble's RK4 at its default step and MuJoCo at that step and at its own
 * default, alternately, medians of the repeats (figures from the last). */
static void many_bodies(case_kind kind, size_t count, int quick)
{
    const int repeats = quick ? 1 : REPEATS;
    const double dt = tumble_default_step(kind, count);
    double times[3][REPEATS];
    result runs[3] = {{NAN, NAN, NAN, 0}, {NAN, NAN, NAN, 0}, {NAN, NAN, NAN, 0}};
    int engines = 1;
    for (int k = 0; k < repeats; ++k) {
        runs[0] = tumble_run(kind, count, TB_METHOD_RK4, dt, quick, 0);
        times[0][k] = runs[0].seconds;
#ifdef TUMBLE_BENCH_MUJOCO
        runs[1] = mujoco_run(kind, count, dt, quick);
        runs[2] = mujoco_run(kind, count, MUJOCO_DEFAULT_STEP, quick);
        times[1][k] = runs[1].seconds;
        times[2][k] = runs[2].seconds;
        engines = 3;
#endif
    }
    static const char *const engine[] = {"tumble", "mujoco", "mujoco"};
    static const char *const method[] = {"rk4", "euler", "euler"};
    const double settings[] = {dt, dt, MUJOCO_DEFAULT_STEP};
    for (int e = 0; e < engines; ++e) {
        runs[e].seconds = bench_median(times[e], (size_t)repeats);
        row(kind, engine[e], count, method[e], settings[e], &runs[e]);
    }
}

/* A drop timed in one advance (median of the repeats), its figure from a sampled run. */
static result tumble_drop_run(case_kind kind, tb_method method, double setting, int quick)
{
    const int repeats = quick ? 1 : REPEATS;
    double times[REPEATS];
    result r = {NAN, NAN, NAN, 0};
    for (int k = 0; k < repeats; ++k) {
        r = tumble_run(kind, 1, method, setting, quick, 0);
        times[k] = r.seconds;
    }
    r.seconds = bench_median(times, (size_t)repeats);
    r.figure = tumble_run(kind, 1, method, setting, quick, 1).figure;
    return r;
}

/* One body dropped: tumble over its settings, MuJoCo at 2 ms, 0.5 ms and tumble's step. */
static void drop(case_kind kind, int quick)
{
    const double dt = tumble_default_step(kind, 1);
    const double fixed[] = {dt, dt / 2, dt / 4}, rtols[] = {1e-4, 1e-6, 1e-8};
    for (int k = 0; k < (quick ? 1 : 3); ++k) {
        const result r = tumble_drop_run(kind, TB_METHOD_RK4, fixed[k], quick);
        row(kind, "tumble", 1, "rk4", fixed[k], &r);
    }
    static const tb_method adaptive[] = {TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    for (int m = 0; m < 2; ++m) {
        for (int k = 0; k < (quick ? 1 : 3); ++k) {
            const result r = tumble_drop_run(kind, adaptive[m], rtols[k], quick);
            row(kind, "tumble", 1, tb_method_name(adaptive[m]), rtols[k], &r);
        }
    }
#ifdef TUMBLE_BENCH_MUJOCO
    const double steps[] = {MUJOCO_DEFAULT_STEP, 5e-4, dt};
    for (int k = 0; k < (quick ? 1 : 3); ++k) {
        const result r = mujoco_run(kind, 1, steps[k], quick);
        row(kind, "mujoco", 1, "euler", steps[k], &r);
    }
#endif
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    setvbuf(stdout, NULL, _IOLBF, 0); /* a row as soon as it is measured */
    char model[256], extensions[256];
    bench_processor(model, extensions);
    fprintf(stderr, "bench_peer_contact: processor %s; load average %.2f at the start\n", model,
            bench_load_average());
#ifdef TUMBLE_BENCH_MUJOCO
    fprintf(stderr, "bench_peer_contact: MuJoCo %s\n", mj_versionString());
#else
    fprintf(stderr, "bench_peer_contact: built without MuJoCo (scripts/bench.sh installs it "
                    "under build/bench-venv): tumble's rows only\n");
#endif
    printf("case,engine,bodies,method,setting,ns_per_body_step,cpu_seconds,steps,figure,"
           "fastest_at_end\n");
    const size_t count = quick ? 16 : 200;
    many_bodies(CASE_PILE, count, quick);
    many_bodies(CASE_CLOUD, count, quick);
    drop(CASE_DIE, quick);
    drop(CASE_BALL, quick);
    fprintf(stderr, "bench_peer_contact: load average %.2f at the end\n", bench_load_average());
    return 0;
}

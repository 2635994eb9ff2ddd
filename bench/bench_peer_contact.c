/* Contact in the peers' hands and in tumble's, in the same run: MuJoCo's C library (from the
 * mujoco-core wheel, as bench_peer) here, PyBullet in bench_peer_pybullet.py, which builds its
 * world from this program's --describe and prints the same columns. The cases:
 *   dice     examples/scenes/dice.json: twelve 5 cm, 150 g dice thrown onto a 57 kg board on
 *            the floor, 5 s (all at rest well before);
 *   column   ten 10 cm, 0.5 kg boxes standing on the floor, each on the one below, 5 s;
 *   pile     200 such boxes in columns 8 high (bench_scenes.h), each 2 cm above the one below
 *            (the lowest 2 cm above the floor), dropped: 0.75 s;
 *   spheres  1000 5 cm spheres (65 g) jostling in a box of five planes (bench_scenes.h), 0.1 s;
 *   cloud    200 boxes thrown at each other, no gravity or floor, 0.03 s: the momentum error;
 *   ball     a 5 cm ball dropped from 0.5 m, restitution 0.5: the restitution measured.
 * Every body has the default contact (restitution 0.3, mu_s 0.6, mu_k 0.5, penetration 8e-7 m).
 * tumble: RK4 at the scene's default step, CVODE BDF with the contact's sparse Jacobian (KLU)
 * at rtol 1e-6 (not on the spheres and the cloud). MuJoCo: its defaults (Euler at 2 ms, soft
 * contact solref 0.02 s critically damped, Newton solver, pyramidal cone, one friction coefficient:
 * mu_k), and a stiff setting (Euler at 1 ms, solref 0.002 s), the one where its dice sink under 2
 * mm. MuJoCo has no restitution parameter: its ball row says what its soft contact gives.
 *
 * The figures (bench_peer_world.h, the same code for every engine) come from samples every 10 ms
 * (0.5 ms for the ball) taken between timed stretches of stepping: the CPU time is the stepping's
 * alone (process CPU, median of the repeats, engines alternately).
 *
 * Prints CSV: case, engine, bodies, method, setting (step s or rtol), CPU seconds per simulated
 * second, CPU seconds, steps, deepest penetration over the samples (m), fastest body over the
 * last second of the span (m/s; at the last sample for spans under 2 s), restitution (ball),
 * momentum change over the sum of the bodies' |P| (cloud); nan where a figure does not apply.
 * The processor and the load average go to stderr. Built without MuJoCo, tumble's rows only. A
 * tumble run stops at the first sample past 120 s of CPU: its row is nan, stderr says how far
 * it got and at what cost.
 *
 * usage: bench_peer_contact [--quick] [--case NAME] [--engine tumble|mujoco] [--no-bdf]
 *                           [--implicit] [--repeats N]
 *        bench_peer_contact --describe [--quick] [--case NAME]   (the worlds as a JSON array)
 * --no-bdf: tumble's RK4 rows only (the spheres and the cloud have none in any case: run_case).
 * --implicit: also rosenbrock at 1/240 s and ark-imex (sparse Jacobian) at rtol 1e-6, where
 * BDF runs. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "bench_peer_cases.h"
#include "bench_peer_world.h"
#include "tumble/tumble.h"

#include "bench_mujoco.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_REPEATS 9
#define MUJOCO_DEFAULT_STEP 0.002
#define MUJOCO_STIFF_STEP 0.001
#define MUJOCO_STIFF_SOLREF 0.002
#define BDF_RTOL 1e-6
#define ROSENBROCK_STEP (1.0 / 240.0) /* --implicit: the fixed step an animator asks for */
#define CPU_BUDGET 120.0 /* s: a tumble run stops at the first sample past it (its row nan) */
/* CVODE's steps between two samples (10 ms) at most: 2e6 steps per simulated second, 40 times
 * what BDF takes on the dice; past it BDF has stalled (on the spheres its steps fall to 1e-13 s),
 * and the run stops there instead of never reaching the next sample. */
#define ADAPTIVE_STEPS_PER_SAMPLE 20000

/* --- runs ----------------------------------------------------------------------------------- */

/* What one run measured. */
typedef struct result {
    double seconds, momentum;
    long steps;
    peer_track track;
} result;

static result no_result(void)
{
    return (result){NAN, NAN, 0, {NAN, NAN, NAN, NAN}};
}

static void momentum(size_t count, const double *masses, const double *v, double P[3],
                     double *scale)
{
    P[0] = P[1] = P[2] = *scale = 0.0;
    for (size_t i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k) {
            P[k] += masses[i] * v[3 * i + k];
        }
        *scale += masses[i] * sqrt(peer_dot(v + 3 * i, v + 3 * i));
    }
}

/* Poses, speeds and masses of every body, sampled by each engine into one place. */
typedef struct sampler {
    const peer_world *world;
    double *x, *R, *v, *mass;
    double P0[3], scale;
} sampler;

static int sampler_open(sampler *s, const peer_world *w)
{
    const size_t n = w->count > 0 ? w->count : 1;
    s->world = w;
    s->x = malloc(3 * n * sizeof(double));
    s->R = malloc(9 * n * sizeof(double));
    s->v = malloc(3 * n * sizeof(double));
    s->mass = malloc(n * sizeof(double));
    for (size_t i = 0; s->mass != NULL && i < w->count; ++i) {
        s->mass[i] = w->bodies[i].mass;
    }
    return s->x == NULL || s->R == NULL || s->v == NULL || s->mass == NULL;
}

static void sampler_close(sampler *s)
{
    free(s->x);
    free(s->R);
    free(s->v);
    free(s->mass);
}

/* The sample's figures at time t (of a span `duration`); the first sets the momentum's start. */
static void sampler_take(sampler *s, result *r, double t, double duration, int first)
{
    double P[3], scale;
    momentum(s->world->count, s->mass, s->v, P, &scale);
    if (first) {
        memcpy(s->P0, P, sizeof P);
        s->scale = scale;
        return;
    }
    peer_track_sample(&r->track, s->world, t, duration, s->x, s->R, s->v);
    const double d[3] = {P[0] - s->P0[0], P[1] - s->P0[1], P[2] - s->P0[2]};
    r->momentum = sqrt(peer_dot(d, d)) / s->scale;
}

static void tumble_sample(const tb_scene *scene, sampler *s)
{
    const double *y = tb_scene_states_const(scene);
    for (size_t i = 0; i < s->world->count; ++i) {
        double q[4];
        tb_scene_body_shape_pose(scene, y, i, s->x + 3 * i, q);
        peer_rotation(q, s->R + 9 * i);
        tb_scene_body_velocity(scene, y, i, s->v + 3 * i);
    }
}

static tb_integrator *tumble_integrator(tb_scene *scene, tb_method method, double setting)
{
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator_def_set_method(&def, method);
    def.max_steps = 100000000;
    if (tb_method_is_adaptive(method)) {
        def.max_steps = ADAPTIVE_STEPS_PER_SAMPLE;
        def.rtol = setting;
        def.linear_solver = TB_LINEAR_SOLVER_SPARSE;
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

static result tumble_run(kind k, const peer_world *w, tb_method method, double setting, int quick)
{
    result r = no_result();
    tb_scene *scene = tumble_case(k, quick);
    tb_integrator *integrator = scene != NULL ? tumble_integrator(scene, method, setting) : NULL;
    sampler s;
    if (integrator == NULL || sampler_open(&s, w) != 0) {
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
        return r;
    }
    const double duration = case_duration(k, quick), sample = case_sample(k);
    const long samples = lround(fmax(1.0, duration / sample));
    r.seconds = 0.0;
    r.track = peer_track_start();
    tumble_sample(scene, &s);
    sampler_take(&s, &r, 0.0, duration, 1);
    tb_status status = TB_STATUS_OK;
    double t = 0.0;
    for (long j = 1; j <= samples && status == TB_STATUS_OK && r.seconds < CPU_BUDGET; ++j) {
        const double start = bench_cpu_seconds();
        t = duration * (double)j / (double)samples;
        status = tb_integrator_advance(integrator, t);
        r.seconds += bench_cpu_seconds() - start;
        tumble_sample(scene, &s);
        sampler_take(&s, &r, t, duration, 0);
    }
    if (status == TB_STATUS_OK && t < duration) {
        fprintf(stderr,
                "bench_peer_contact: %s: %s stopped at t = %g s after %.1f s of CPU (%.3g s of "
                "CPU per simulated s so far)\n",
                case_names[k], tb_method_name(method), t, r.seconds, r.seconds / t);
        r.seconds = NAN;
    }
    if (status != TB_STATUS_OK) { /* before tb_integrator_get_stats, which clears the detail */
        fprintf(stderr, "bench_peer_contact: %s: %s %s %g stopped at t = %g s: %s: %s\n",
                case_names[k], tb_method_name(method),
                tb_method_is_adaptive(method) ? "rtol" : "dt", setting,
                tb_integrator_time(integrator), tb_status_string(status),
                tb_integrator_detail(integrator));
        r.seconds = NAN;
    }
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    r.steps = stats.steps;
    sampler_close(&s);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return r;
}

/* tumble's RK4 default step on a case. */
static double tumble_default_step(kind k, int quick)
{
    tb_scene *scene = tumble_case(k, quick);
    double dt = NAN;
    if (scene != NULL) {
        tb_scene_default_step(scene, TB_METHOD_RK4, &dt);
    }
    tb_scene_destroy(scene);
    return dt;
}

/* --- MuJoCo ---------------------------------------------------------------------------------- */

#ifdef TUMBLE_BENCH_MUJOCO
/* The world's model at step dt; solref > 0: every geom's contact time constant (s), critically
 * damped, in place of MuJoCo's 0.02 s. */
static mjModel *mujoco_model(const peer_world *w, double dt, double solref)
{
    const size_t size = 2048 + 400 * w->count;
    char *xml = malloc(size);
    if (xml == NULL) {
        return NULL;
    }
    char extra[64] = "";
    if (solref > 0.0) {
        snprintf(extra, sizeof extra, " solref=\"%g 1\"", solref);
    }
    size_t used = (size_t)snprintf(
        xml, size,
        "<mujoco><size memory=\"%zuM\"/><option timestep=\"%.17g\" gravity=\"0 0 %.17g\"/>"
        "<default><geom friction=\"%g 0.005 0.0001\"%s/></default><worldbody>",
        64 + w->count / 8, dt, w->gravity, w->friction, extra);
    for (size_t k = 0; k < w->planes; ++k) {
        const double *n = w->normal[k], o = w->offset[k];
        used += (size_t)snprintf(xml + used, size - used,
                                 "<geom type=\"plane\" size=\"0 0 1\" pos=\"%.17g %.17g %.17g\" "
                                 "zaxis=\"%g %g %g\"/>",
                                 o * n[0], o * n[1], o * n[2], n[0], n[1], n[2]);
    }
    for (size_t i = 0; i < w->count; ++i) {
        const peer_body *b = &w->bodies[i];
        used += (size_t)snprintf(
            xml + used, size - used,
            "<body pos=\"%.17g %.17g %.17g\" quat=\"%.17g %.17g %.17g %.17g\"><freejoint/>"
            "<geom type=\"%s\" size=\"%.17g %.17g %.17g\" mass=\"%.17g\"/></body>",
            b->x[0], b->x[1], b->x[2], b->q[0], b->q[1], b->q[2], b->q[3],
            b->sphere ? "sphere" : "box", b->half[0], b->half[1], b->half[2], b->mass);
    }
    snprintf(xml + used, size - used, "</worldbody></mujoco>");
    mjModel *model = bench_mujoco_model("bench_peer_contact", xml);
    free(xml);
    return model;
}

/* Each free joint's velocity: linear in the world, angular in the body's frame. */
static void mujoco_start(const peer_world *w, mjData *d)
{
    for (size_t i = 0; i < w->count; ++i) {
        const peer_body *b = &w->bodies[i];
        double R[9];
        peer_rotation(b->q, R);
        for (int k = 0; k < 3; ++k) {
            d->qvel[6 * i + k] = b->v[k];
            d->qvel[6 * i + 3 + k] = R[k] * b->w[0] + R[3 + k] * b->w[1] + R[6 + k] * b->w[2];
        }
    }
}

static void mujoco_sample(const mjData *d, sampler *s)
{
    const size_t n = s->world->count;
    memcpy(s->x, d->xpos + 3, 3 * n * sizeof(double));
    memcpy(s->R, d->xmat + 9, 9 * n * sizeof(double));
    for (size_t i = 0; i < n; ++i) {
        memcpy(s->v + 3 * i, d->qvel + 6 * i, 3 * sizeof(double));
    }
}

static result mujoco_run(const peer_world *w, double dt, double solref, double duration,
                         double sample)
{
    result r = no_result();
    mjModel *m = mujoco_model(w, dt, solref);
    mjData *d = m != NULL ? mj_makeData(m) : NULL;
    sampler s;
    if (d == NULL || sampler_open(&s, w) != 0) {
        mj_deleteData(d);
        mj_deleteModel(m);
        return r;
    }
    mujoco_start(w, d);
    mj_forward(m, d);
    r.seconds = 0.0;
    r.track = peer_track_start();
    mujoco_sample(d, &s);
    sampler_take(&s, &r, 0.0, duration, 1);
    const long samples = lround(fmax(1.0, duration / sample));
    for (long j = 1; j <= samples; ++j) {
        const double t = duration * (double)j / (double)samples;
        const long target = lround(t / dt);
        const double start = bench_cpu_seconds();
        for (; r.steps < target; ++r.steps) {
            mj_step(m, d);
        }
        r.seconds += bench_cpu_seconds() - start;
        mj_kinematics(m,
                      d); /* the poses at the state reached (mj_step leaves them a step behind) */
        mujoco_sample(d, &s);
        sampler_take(&s, &r, t, duration, 0);
    }
    sampler_close(&s);
    mj_deleteData(d);
    mj_deleteModel(m);
    return r;
}
#else
static result mujoco_run(const peer_world *w, double dt, double solref, double duration,
                         double sample)
{
    (void)w, (void)dt, (void)solref, (void)duration, (void)sample;
    return no_result();
}
#endif

/* --- the rows ------------------------------------------------------------------------------- */

static void row(kind k, const char *engine, size_t bodies, const char *method, double setting,
                const result *r, double duration)
{
    const int ball = k == CASE_BALL, cloud_case = k == CASE_CLOUD;
    printf("%s,%s,%zu,%s,%.4g,%.4g,%.4g,%ld,%.3g,%.3g,%.4g,%.3g,%.4g\n", case_names[k], engine,
           bodies, method, setting, r->seconds / duration, r->seconds, r->steps, r->track.deepest,
           r->track.fastest, ball ? r->track.rebound / -r->track.impact : NAN,
           cloud_case ? r->momentum : NAN,
           r->steps > 0 ? 1e6 * r->seconds / (double)r->steps : NAN);
}

typedef struct options {
    int quick, describe, repeats, tumble, mujoco, bdf, implicit;
    int cases[CASES];
} options;

/* One case: each engine's settings, alternately, medians of the repeats (figures from the last). */
static void run_case(kind k, const options *o)
{
    peer_world w;
    if (case_world(k, o->quick, &w) != 0) {
        fprintf(stderr, "bench_peer_contact: cannot make %s\n", case_names[k]);
        exit(1);
    }
    enum { SETTINGS = 6, TUMBLE_SETTINGS = 4 };
    const double dt = tumble_default_step(k, o->quick);
    static const char *const engine[] = {"tumble", "tumble", "tumble",
                                         "tumble", "mujoco", "mujoco"};
    static const char *const method[] = {
        "rk4", "cvode-bdf-sparse", "rosenbrock", "ark-imex-sparse", "euler", "euler-stiff"};
    static const tb_method methods[] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF, TB_METHOD_ROSENBROCK,
                                        TB_METHOD_ARK_IMEX};
    const double settings[] = {
        dt, BDF_RTOL, ROSENBROCK_STEP, BDF_RTOL, MUJOCO_DEFAULT_STEP, MUJOCO_STIFF_STEP};
    /* BDF not on the spheres, where it spends minutes of CPU in KLU's refactorisations within
     * one 10 ms sample (its steps fall to 1e-13 s) before any budget is checked, nor on the
     * cloud, where it stops at t = 0.017 s after 2 minutes, its steps for a sample spent */
    const int bdf = o->tumble && o->bdf && !o->quick && k != CASE_SPHERES && k != CASE_CLOUD;
    const int implicit = bdf && o->implicit;
    const int on[] = {o->tumble, bdf, implicit, implicit, o->mujoco, o->mujoco};
    double times[SETTINGS][MAX_REPEATS];
    result runs[SETTINGS];
    const double duration = case_duration(k, o->quick);
    for (int j = 0; j < o->repeats; ++j) {
        for (int e = 0; e < SETTINGS; ++e) {
            if (!on[e]) {
                continue;
            }
            if (e < TUMBLE_SETTINGS) {
                runs[e] = tumble_run(k, &w, methods[e], settings[e], o->quick);
            } else {
                runs[e] = mujoco_run(&w, settings[e], e == 5 ? MUJOCO_STIFF_SOLREF : 0.0, duration,
                                     case_sample(k));
            }
            times[e][j] = runs[e].seconds;
        }
    }
    for (int e = 0; e < SETTINGS; ++e) {
        if (on[e]) {
            runs[e].seconds = bench_median(times[e], (size_t)o->repeats);
            row(k, engine[e], w.count, method[e], settings[e], &runs[e], duration);
        }
    }
    peer_world_free(&w);
}

static void describe(const options *o)
{
    printf("[");
    int first = 1;
    for (int k = 0; k < CASES; ++k) {
        peer_world w;
        if (!o->cases[k] || case_world((kind)k, o->quick, &w) != 0) {
            continue;
        }
        printf("%s\n", first ? "" : ",");
        peer_world_write_json(stdout, case_names[k], case_duration((kind)k, o->quick),
                              case_sample((kind)k), &w);
        first = 0;
        peer_world_free(&w);
    }
    printf("]\n");
}

static void parse(int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->tumble = o->mujoco = o->bdf = 1;
    int chosen = 0;
    for (int a = 1; a < argc; ++a) {
        if (strcmp(argv[a], "--quick") == 0) {
            o->quick = 1;
        } else if (strcmp(argv[a], "--describe") == 0) {
            o->describe = 1;
        } else if (strcmp(argv[a], "--no-bdf") == 0) {
            o->bdf = 0;
        } else if (strcmp(argv[a], "--implicit") == 0) {
            o->implicit = 1;
        } else if (strcmp(argv[a], "--repeats") == 0 && a + 1 < argc) {
            o->repeats = atoi(argv[++a]);
        } else if (strcmp(argv[a], "--engine") == 0 && a + 1 < argc) {
            ++a;
            o->tumble = strcmp(argv[a], "tumble") == 0;
            o->mujoco = strcmp(argv[a], "mujoco") == 0;
        } else if (strcmp(argv[a], "--case") == 0 && a + 1 < argc) {
            ++a;
            for (int k = 0; k < CASES; ++k) {
                o->cases[k] |= strcmp(argv[a], case_names[k]) == 0;
            }
            chosen = 1;
        } else {
            fprintf(stderr, "usage: bench_peer_contact [--quick] [--describe] [--case NAME] "
                            "[--engine tumble|mujoco] [--no-bdf] [--implicit] [--repeats N]\n");
            exit(2);
        }
    }
    for (int k = 0; k < CASES && !chosen; ++k) {
        o->cases[k] = 1;
    }
    if (o->repeats < 1 || o->repeats > MAX_REPEATS) {
        o->repeats = o->quick ? 1 : 3;
    }
}

int main(int argc, char **argv)
{
    options o;
    parse(argc, argv, &o);
    if (o.describe) {
        describe(&o);
        return 0;
    }
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
    o.mujoco = 0;
#endif
    printf("case,engine,bodies,method,setting,cpu_per_simulated_s,cpu_seconds,steps,"
           "deepest_m,fastest_m_per_s,restitution,momentum_error,cpu_per_step_us\n");
    for (int k = 0; k < CASES; ++k) {
        if (o.cases[k]) {
            run_case((kind)k, &o);
        }
    }
    fprintf(stderr, "bench_peer_contact: load average %.2f at the end\n", bench_load_average());
    return 0;
}

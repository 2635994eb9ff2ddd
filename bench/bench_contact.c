/* What contact costs per body-step, and where the time goes, on two contact scenes
 * (bench/bench_scenes.h) at 100, 1000 and 10 000 bodies:
 *   spheres  5 cm spheres packed touching in a box of five ground planes, jostling at up to
 *            0.2 m/s (a poured box before it settles);
 *   pile     10 cm boxes in columns 8 high on the floor, released at rest.
 * Every body has a shape, contact points on the planes and the default contact between bodies
 * (restitution 0.3, mu_s 0.6, mu_k 0.5, penetration 8e-7 m). Each integrator runs the scene
 * from its initial state: Euler, midpoint and RK4 at the scene's default step
 * (tb_scene_default_step), CVODE Adams and BDF at rtol 1e-6 (atol per body, max_step the
 * contact's cap); CPU time of one advance, median of the repeats.
 *
 * The shares are measured on the state the run ended in, outside the integrator and without
 * touching the library's build (each a median of 7 batches of evaluations in a row): the derivative
 * of the scene with bodies and gravity only (the rigid-body part), with the ground planes too, and
 * with contact (the whole); the pair finder alone (contact/contact_pairs.h: poses, bounds and sort,
 * then the sweep with the narrow phase) and the broad phase's sweep alone (contact/broad_phase.h on
 * the same bounds). So per derivative: broad = pair finder's begin + sweep, narrow = pair finder -
 * broad, contact law = whole - (with planes) - pair finder (the law, friction and the loads at each
 * manifold point), planes = (with planes) - (bodies only), each as a share of the whole derivative.
 * The integrator's share is what the derivatives (their count per step times the whole) leave of
 * the run's time per step: the stages, renormalisation and CVODE's algebra. Shares come from
 * differences of medians on a shared machine: a small one can come out slightly negative.
 *
 * Prints CSV: scene, bodies, method, setting (dt, s, or rtol), steps, derivatives per step,
 * touching pairs per body, ns per body-step (median of the repeats), us per body per simulated
 * second, the time simulated, the derivative's ns per body, then the shares of broad phase,
 * narrow phase, contact law, ground planes and rigid-body derivative in it, and the
 * integrator's share of a step. The processor and the load average go to stderr.
 *
 * --scene NAME and --method NAME keep one scene (spheres or pile) and one method (rk4, ...).
 *
 * usage: bench_contact [--quick] [--scene NAME] [--method NAME] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "bench_scenes.h"
#include "contact/contact_pairs.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REPEATS 3
#define PART_REPEATS 7
#define CVODE_RTOL 1e-6
#define CONTACT_MARGIN 1e-3 /* the contact effect's (src/effects/effect_contact.c) */

typedef tb_scene *(*scene_maker)(size_t count, int effects);

typedef struct run_result {
    double seconds, simulated;
    long steps, derivatives;
    double dt;
    int ok;
} run_result;

/* One timed run of a fresh scene from its initial state: fixed-step methods `steps` steps of
 * the default step in one advance; CVODE advanced to window s in pieces of RK4's default step,
 * stopping early once `budget` CPU seconds are spent (CVODE's steps on these scenes are short,
 * and BDF's on the spheres collapse: the time simulated is reported). The scene is kept in
 * *out_scene for the shares. */
static run_result timed_run(scene_maker make, size_t count, tb_method method, long steps,
                            double window, double budget, tb_scene **out_scene)
{
    run_result r = {NAN, 0.0, 0, 0, NAN, 0};
    tb_scene *scene = make(count, BENCH_ALL);
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator_def_set_method(&def, method);
    def.max_steps = 10000000;
    double piece = 0.0;
    tb_scene_default_step(scene, TB_METHOD_RK4, &piece);
    if (tb_method_is_adaptive(method)) {
        def.rtol = CVODE_RTOL;
        def.max_steps = 3; /* a BDF step on 10 000 bodies can take a second */
    } else {
        def.dt = 0.0; /* the scene's default step */
        tb_scene_default_step(scene, method, &r.dt);
        piece = window = (double)steps * r.dt;
    }
    tb_integrator *integrator = NULL;
    if (scene != NULL &&
        tb_scene_integrator_create(scene, &def, 0.0, &integrator) == TB_STATUS_OK) {
        tb_status status = TB_STATUS_OK;
        const double start = bench_cpu_seconds();
        double target = 0.0;
        while (status == TB_STATUS_OK && tb_integrator_time(integrator) < window &&
               bench_cpu_seconds() - start < budget) {
            if (tb_integrator_time(integrator) >= target) {
                target = fmin(window, target + piece);
            }
            status = tb_integrator_advance(integrator, target);
            /* CVODE's steps are counted out in small allowances so the budget is checked */
            status = status == TB_STATUS_TOO_MANY_STEPS ? TB_STATUS_OK : status;
        }
        r.seconds = bench_cpu_seconds() - start;
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        r.steps = stats.steps;
        r.derivatives = stats.derivative_evals;
        r.simulated = tb_integrator_time(integrator);
        r.ok = status == TB_STATUS_OK && r.steps > 0;
        if (status != TB_STATUS_OK) {
            fprintf(stderr, "bench_contact: %s on %zu bodies: %s\n", tb_method_name(method), count,
                    tb_integrator_detail(integrator));
        }
    }
    tb_integrator_destroy(integrator);
    *out_scene = scene;
    return r;
}

/* Evaluations timed together, so that a measurement lasts milliseconds whatever the size. */
static int batch_size(size_t count)
{
    const size_t n = 20000 / (count > 0 ? count : 1);
    return n > 0 ? (int)n : 1;
}

/* Median CPU seconds of one derivative of scene at y (its own state size: the first
 * tb_scene_state_size doubles of y are used), timed over batches. */
static double derivative_seconds(tb_scene *scene, const double *y, double *dydt, int batch)
{
    double times[PART_REPEATS];
    for (int k = 0; k < PART_REPEATS; ++k) {
        const double start = bench_cpu_seconds();
        for (int j = 0; j < batch; ++j) {
            tb_scene_derivative(0.0, y, dydt, scene);
        }
        times[k] = (bench_cpu_seconds() - start) / batch;
    }
    return bench_median(times, PART_REPEATS);
}

typedef struct parts {
    double whole, planes, bodies, begin, sweep, pass; /* seconds per derivative */
    size_t touching;
} parts;

/* One pass of the pair finder; returns the touching pairs. */
static size_t pair_pass(tb__contact_pairs *pairs, const tb_scene *scene, const double *y)
{
    tb__pair_contact batch[64];
    size_t n, touching = 0;
    tb__contact_pairs_begin(pairs, scene, tb_scene_time(scene), y);
    while ((n = tb__contact_pairs_next(pairs, scene, y, batch, 64)) > 0) {
        touching += n;
    }
    return touching;
}

/* The pair finder on scene at y: begin alone, and begin + sweep + narrow phase. */
static void pair_finder_seconds(const tb_scene *scene, const double *y, int batch, parts *out)
{
    tb__contact_pairs *pairs = NULL;
    if (tb__contact_pairs_create(scene, NULL, 0, CONTACT_MARGIN, &pairs, NULL) != TB_STATUS_OK) {
        return;
    }
    double begin[PART_REPEATS], pass[PART_REPEATS];
    for (int k = 0; k < PART_REPEATS; ++k) {
        const double t0 = bench_cpu_seconds();
        for (int j = 0; j < batch; ++j) {
            tb__contact_pairs_begin(pairs, scene, tb_scene_time(scene), y);
        }
        const double t1 = bench_cpu_seconds();
        for (int j = 0; j < batch; ++j) {
            out->touching = pair_pass(pairs, scene, y);
        }
        pass[k] = (bench_cpu_seconds() - t1) / batch;
        begin[k] = (t1 - t0) / batch;
    }
    out->begin = bench_median(begin, PART_REPEATS);
    out->pass = bench_median(pass, PART_REPEATS);
    tb__contact_pairs_destroy(pairs);
}

/* The broad phase's sweep alone on the bounds the pair finder sees (shape bounds grown by half
 * the margin each way), sorted before each timed sweep (the sort is not timed: it is in
 * begin). */
static double sweep_seconds(const tb_scene *scene, const double *y, size_t count, int batch)
{
    tb__broad_phase bp;
    if (tb__broad_phase_init(&bp, count) != TB_STATUS_OK) {
        return NAN;
    }
    for (size_t i = 0; i < count; ++i) {
        tb_scene_body_shape_bounds(scene, y, i, bp.boxes[i].min, bp.boxes[i].max);
        for (int k = 0; k < 3; ++k) {
            bp.boxes[i].min[k] -= 0.5 * CONTACT_MARGIN;
            bp.boxes[i].max[k] += 0.5 * CONTACT_MARGIN;
        }
    }
    double times[PART_REPEATS];
    tb__index_pair pairs[256];
    volatile size_t found = 0;
    for (int k = 0; k < PART_REPEATS; ++k) {
        double seconds = 0.0;
        for (int j = 0; j < batch; ++j) {
            tb__broad_phase_sort(&bp, count);
            const double start = bench_cpu_seconds();
            size_t n;
            while ((n = tb__broad_phase_next(&bp, pairs, 256)) > 0) {
                found += n;
            }
            seconds += bench_cpu_seconds() - start;
        }
        times[k] = seconds / batch;
    }
    (void)found;
    tb__broad_phase_free(&bp);
    return bench_median(times, PART_REPEATS);
}

/* Every part at the state y of the whole scene (bodies first, then the planes' friction states:
 * the twin with planes has the same layout up to its own size, the twin of bodies alone the
 * bodies' 13 N). */
static parts measure_parts(scene_maker make, tb_scene *whole, size_t count)
{
    parts p = {NAN, NAN, NAN, NAN, NAN, NAN, 0};
    tb_scene *planes = make(count, BENCH_GRAVITY | BENCH_GROUND);
    tb_scene *bodies = make(count, BENCH_GRAVITY);
    const size_t n = tb_scene_state_size(whole);
    double *dydt = malloc(n * sizeof *dydt);
    const double *y = tb_scene_states_const(whole);
    if (planes != NULL && bodies != NULL && dydt != NULL && tb_scene_state_size(planes) <= n &&
        tb_scene_state_size(bodies) <= n) {
        const int batch = batch_size(count);
        p.whole = derivative_seconds(whole, y, dydt, batch);
        p.planes = derivative_seconds(planes, y, dydt, batch);
        p.bodies = derivative_seconds(bodies, y, dydt, batch);
        pair_finder_seconds(whole, y, batch, &p);
        p.sweep = sweep_seconds(whole, y, count, batch);
    }
    free(dydt);
    tb_scene_destroy(planes);
    tb_scene_destroy(bodies);
    return p;
}

/* ns per body-step and us per body per simulated second of a run */
static double per_body_step(const run_result *r, size_t count)
{
    return 1e9 * r->seconds / ((double)r->steps * (double)count);
}

static double per_body_second(const run_result *r, size_t count)
{
    return 1e6 * r->seconds / ((double)count * r->simulated);
}

static void row(const char *name, size_t count, tb_method method, const run_result *r, double total,
                double per_second, const parts *p)
{
    const double derivs = (double)r->derivatives / (double)r->steps;
    const double w = p->whole;
    printf("%s,%zu,%s,%.3g,%ld,%.2f,%.2f,%.1f,%.4g,%.4g,%.1f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n", name,
           count, tb_method_name(method), tb_method_is_adaptive(method) ? CVODE_RTOL : r->dt,
           r->steps, derivs, (double)p->touching / (double)count, total, per_second, r->simulated,
           1e9 * w / (double)count, (p->begin + p->sweep) / w, (p->pass - p->begin - p->sweep) / w,
           (w - p->planes - p->pass) / w, (p->planes - p->bodies) / w, p->bodies / w,
           1.0 - derivs * 1e9 * w / (double)count / total);
}

/* All five methods on one scene and size, or the one named (only: NULL for all). */
static void measure(const char *name, scene_maker make, size_t count, int quick, const char *only)
{
    static const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4,
                                        TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    const double body_steps = quick ? 2e3 : 2e5;
    long steps = (long)(body_steps / (double)count);
    steps = steps < 5 ? 5 : steps;
    const double window = quick ? 1e-4 : 2e-3, budget = quick ? 0.05 : 1.5;
    const int repeats = quick ? 1 : REPEATS;
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
        if (only != NULL && strcmp(only, tb_method_name(methods[m])) != 0) {
            continue;
        }
        double ns[REPEATS], us[REPEATS];
        run_result r = {0};
        parts p = {0};
        int ok = 1;
        for (int k = 0; k < repeats && ok; ++k) {
            tb_scene *scene = NULL;
            r = timed_run(make, count, methods[m], steps, window, budget, &scene);
            ok = r.ok;
            ns[k] = per_body_step(&r, count);
            us[k] = per_body_second(&r, count);
            if (k == repeats - 1 && ok) {
                p = measure_parts(make, scene, count);
            }
            tb_scene_destroy(scene);
        }
        if (ok) {
            row(name, count, methods[m], &r, bench_median(ns, (size_t)repeats),
                bench_median(us, (size_t)repeats), &p);
        }
    }
}

int main(int argc, char **argv)
{
    int quick = 0;
    const char *scene = NULL, *method = NULL;
    for (int a = 1; a < argc; ++a) {
        if (strcmp(argv[a], "--quick") == 0) {
            quick = 1;
        } else if (strcmp(argv[a], "--scene") == 0 && a + 1 < argc) {
            scene = argv[++a];
        } else if (strcmp(argv[a], "--method") == 0 && a + 1 < argc) {
            method = argv[++a];
        } else {
            fprintf(stderr, "usage: bench_contact [--quick] [--scene NAME] [--method NAME]\n");
            return 2;
        }
    }
    setvbuf(stdout, NULL, _IOLBF, 0); /* a row as soon as it is measured */
    char model[256], extensions[256];
    bench_processor(model, extensions);
    fprintf(stderr, "bench_contact: processor %s; load average %.2f at the start\n", model,
            bench_load_average());
    printf("scene,bodies,method,setting,steps,derivatives_per_step,touching_pairs_per_body,"
           "ns_per_body_step,us_per_body_simulated_second,simulated_seconds,derivative_ns_per_body,"
           "broad_share,narrow_share,contact_law_share,ground_planes_share,rigid_body_share,"
           "integrator_share\n");
    static const size_t full[] = {100, 1000, 10000};
    static const size_t brief[] = {27};
    const size_t *sizes = quick ? brief : full;
    for (size_t k = 0; k < (quick ? 1 : 3); ++k) {
        if (scene == NULL || strcmp(scene, "spheres") == 0) {
            measure("spheres", bench_spheres_in_box, sizes[k], quick, method);
        }
        if (scene == NULL || strcmp(scene, "pile") == 0) {
            measure("pile", bench_box_pile, sizes[k], quick, method);
        }
    }
    fprintf(stderr, "bench_contact: load average %.2f at the end\n", bench_load_average());
    return 0;
}

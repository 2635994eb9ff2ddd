/* The example scenes of static and keyframed bodies, each loaded from its file, run frame by
 * frame (its own integrator, or the one named on the command line) and checked against what
 * must happen:
 *   table_roll.json  a ball rolling off a static table's edge: when it leaves the table, and
 *                    where and when it lands on the floor, against the ballistic arc from the edge;
 *   platform.json    a box on a keyframed platform that rises, stops and descends: it never
 *                    loses contact, sinks by its static deflection while the platform moves at
 *                    constant speed and rises and falls with it;
 *   paddle.json      a keyframed paddle at 10 m/s hitting a 2 cm ball: the ball never passes
 *                    through it and leaves at (1 + e) times the paddle's speed;
 *   bat_sweep.json   a keyframed bat sweeping five boxes off a static table: none within its
 *                    reach passes through it, all end at rest on the floor past the table's
 *                    edge.
 *   test_example_kinds NAME [METHOD [DURATION [DT]]]
 * METHOD (rk4, cvode-bdf, ...) replaces the scene's integrator (adaptive ones at rtol 1e-7: their
 * atol from the bodies, 1e-9 of their sizes, far below the bounds below). DURATION (s) cuts the
 * run short (the sanitizer builds): the checks that need the whole run are then skipped (0: the
 * whole run). DT (s) is a fixed-step method's step (rosenbrock at a user's 1/240 s). */
#include "examples.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define G 9.81
#define MAX_TOUCHES 16

static const char *method_name;    /* NULL: the scene's own integrator */
static double cut_duration;        /* > 0: the run was cut to this many seconds */
static double step_fraction = 1.0; /* a fixed method's step: this fraction of the default */
static double step_arg;            /* > 0: a fixed method's step (s), argv[4] */

/* The scene NAME, its integrator and the frame rate; exits 1 on a refusal. */
static tb_integrator *start(const char *name, tb_scene **out_scene, double *inout_fps,
                            double *out_duration)
{
    tb_run_def run;
    *out_scene = test_example_load(TUMBLE_SCENES_DIR, name, &run);
    if (method_name != NULL) {
        tb_error error;
        tb_method method;
        if (tb_method_parse(method_name, &method, &error) != TB_STATUS_OK) {
            printf("%s\n", error.message);
            exit(1);
        }
        tb_integrator_def_set_method(&run.integrator, method);
        if (method == TB_METHOD_CVODE_ADAMS || method == TB_METHOD_CVODE_BDF) {
            run.integrator.rtol = 1e-7;
        }
    }
    *out_duration = cut_duration > 0.0 ? fmin(run.duration, cut_duration) : run.duration;
    if (!tb_method_is_adaptive(run.integrator.method) && step_fraction != 1.0) {
        double dt = 0.0;
        if (tb_scene_default_step(*out_scene, run.integrator.method, &dt) != TB_STATUS_OK) {
            printf("no default step: %s\n", tb_scene_detail(*out_scene));
            exit(1);
        }
        run.integrator.dt = step_fraction * dt;
    }
    run.integrator.dt = step_arg > 0.0 ? step_arg : run.integrator.dt;
    printf("  method %s, %g s at %g frames a second, step fraction %g\n",
           tb_method_name(run.integrator.method), *out_duration, *inout_fps, step_fraction);
    tb_integrator *integrator = NULL;
    if (tb_scene_integrator_create(*out_scene, &run.integrator, 0.0, &integrator) != TB_STATUS_OK) {
        printf("integrator refused: %s\n", tb_scene_detail(*out_scene));
        exit(1);
    }
    return integrator;
}

static void advance(tb_integrator *integrator, double t)
{
    const tb_status status = tb_integrator_advance(integrator, t);
    if (status != TB_STATUS_OK) {
        printf("advance to %g s failed: %s %s\n", t, tb_status_string(status),
               tb_integrator_detail(integrator));
        exit(1);
    }
}

/* The overlap (m; <= 0 a gap, -INFINITY apart) of bodies a < b (b TB_WORLD: the ground). */
static double depth(const tb_scene *scene, size_t a, size_t b)
{
    tb_contact_touch touches[MAX_TOUCHES];
    size_t count = 0;
    if (tb_scene_contact_touching(scene, tb_scene_states_const(scene), touches, MAX_TOUCHES,
                                  &count) != TB_STATUS_OK) {
        printf("tb_scene_contact_touching failed: %s\n", tb_scene_detail(scene));
        exit(1);
    }
    double d = -INFINITY;
    for (size_t k = 0; k < count && k < MAX_TOUCHES; ++k) {
        if (touches[k].body_a == a && touches[k].body_b == b) {
            d = fmax(d, touches[k].depth);
        }
    }
    return d;
}

static void position(const tb_scene *scene, size_t id, double out[3])
{
    double q[4];
    if (tb_scene_body_shape_pose(scene, tb_scene_states_const(scene), id, out, q) != TB_STATUS_OK) {
        printf("tb_scene_body_shape_pose failed: %s\n", tb_scene_detail(scene));
        exit(1);
    }
}

/* table_roll: the table (body 0) 1.2 m long, its top at 0.75 m; the ball (body 1, r = 5 cm) at
 * x = 0.2 m rolling at 2 m/s, sunk by the contact's 0.2 mm. Its centre passes the edge (x = 0.6)
 * at t_e = 0.2 s; the corner it pivots on then releases it within sqrt(r^2 - (r - pen)^2) / v
 * = 2.2 ms (and the edge would have to pull to hold it on a circle: v^2 / r = 80 m/s^2 > g). So the
 * last frame (1 ms apart) where it overlaps the table lies in [t_e - 1 ms, t_e + 6 ms]. From the
 * edge it falls freely from z0 = 0.7998 m: it reaches the floor (centre at r) after
 * s = sqrt(2 (z0 - r) / g) = 0.391 s, at x = 0.6 + v s = 1.382 m; the first frame overlapping the
 * floor within 2 ms of t_e + s (a frame, and the corner's push while it leaves: under the 3 mm
 * test_body_kinds bounds the arc by, 0.8 ms at the landing's 3.8 m/s), its x there within 3 mm
 * of the arc's at that frame's time. */
static void table_roll(void)
{
    tb_scene *scene;
    double fps = 1000.0, duration;
    tb_integrator *integrator = start("table_roll", &scene, &fps, &duration);
    const double r = 0.05, v = 2.0, edge = 0.6, z0 = 0.7998, t_e = (edge - 0.2) / v;
    const double s = sqrt(2.0 * (z0 - r) / G);
    double left = -1.0, landed = -1.0, land_x = 0.0;
    const long frames = lround(duration * fps);
    for (long k = 1; k <= frames && landed < 0.0; ++k) {
        const double t = (double)k / fps;
        advance(integrator, t);
        if (depth(scene, 0, 1) > 0.0) {
            left = t;
        }
        if (depth(scene, 1, TB_WORLD) > 0.0) {
            double x[3];
            position(scene, 1, x);
            landed = t, land_x = x[0];
        }
    }
    test_check(left >= t_e - 1e-3 && left <= t_e + 6e-3, "last frame on the table (s)", left, t_e);
    if (cut_duration > 0.0) {
        printf("  %-62s skipped: the run was cut to %g s\n", "the landing", cut_duration);
    } else {
        test_check(fabs(landed - (t_e + s)) < 2e-3, "first frame on the floor - arc's (s)",
                   landed - (t_e + s), 2e-3);
        const double arc_x = edge + v * (landed - t_e);
        test_check(fabs(land_x - arc_x) < 3e-3, "landing x - the arc's x at that time (m)",
                   land_x - arc_x, 3e-3);
        printf("  landed at t = %.4f s, x = %.4f m (arc: %.4f s, %.4f m)\n", landed, land_x,
               t_e + s, edge + v * s);
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* platform: the platform (body 0, its top 5 cm over its origin) and a 1 kg box (body 1, 10 cm
 * high) on it; the contact's stiffness makes the box sink by pen = 1 mm under its weight (its
 * four manifold points share k = M g / pen). The platform's accelerations (5 m/s^2) stay below
 * g, so the box never loses contact: the force it puts on the platform (the platform's reaction)
 * points down at every frame (5 ms apart). While the platform moves at constant speed (rising
 * 0.55 s to 0.8 s, descending 1.45 s to 1.6 s: 0.15 s after each ramp ends, when the ramp's
 * ringing, a/g pen = 0.5 mm, has decayed by exp(-36 / s 0.15 s) = 0.5 %) the box sinks by pen,
 * within 10 %; at rest up top (1.1 s) and at the end (2 s) it sits there too, risen 0.6 m and
 * back at 0.1 m with the platform. */
static void platform(void)
{
    tb_scene *scene;
    double fps = 200.0, duration;
    tb_integrator *integrator = start("platform", &scene, &fps, &duration);
    const double pen = 1e-3;
    double weakest = INFINITY, worst = 0.0, top = NAN, end = NAN, top_z = NAN, end_z = NAN;
    const long frames = lround(duration * fps);
    for (long k = 1; k <= frames; ++k) {
        const double t = (double)k / fps;
        advance(integrator, t);
        double force[3], torque[3], p[3], b[3];
        if (tb_scene_body_reaction(scene, tb_scene_states(scene), 0, force, torque) !=
            TB_STATUS_OK) {
            printf("tb_scene_body_reaction failed: %s\n", tb_scene_detail(scene));
            exit(1);
        }
        weakest = fmin(weakest, -force[2]);
        position(scene, 0, p);
        position(scene, 1, b);
        const double sinking = p[2] + 0.1 - b[2];
        if ((t >= 0.55 && t <= 0.8) || (t >= 1.45 && t <= 1.6)) {
            worst = fmax(worst, fabs(sinking / pen - 1.0));
        }
        if (k == lround(1.1 * fps)) {
            top = sinking, top_z = p[2];
        }
        if (k == lround(2.0 * fps)) {
            end = sinking, end_z = p[2];
        }
    }
    test_check(weakest > 0.0, "weakest push of the box on the platform (N)", weakest, 0.0);
    if (cut_duration > 0.0) {
        printf("  %-62s skipped: the run was cut to %g s\n", "riding and resting", cut_duration);
    } else {
        test_check(worst < 0.1, "sinking at constant speed: worst |sink / pen - 1|", worst, 0.1);
        test_check(fabs(top_z - 0.6) < 1e-12 && fabs(top / pen - 1.0) < 0.1,
                   "up top (platform at 0.6 m): |sink / pen - 1|", fabs(top / pen - 1.0), 0.1);
        test_check(fabs(end_z - 0.1) < 1e-12 && fabs(end / pen - 1.0) < 0.1,
                   "back down (platform at 0.1 m): |sink / pen - 1|", fabs(end / pen - 1.0), 0.1);
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* paddle: the paddle (body 0, its face 2.5 cm ahead of its origin along y) sweeps at 10 m/s; the
 * ball (body 1, r = 1 cm, 10 g) rests on the floor in its path. The paddle is infinitely heavy:
 * in its frame the ball comes in at 10 m/s and leaves at e = 0.5 times that (the law meets e
 * within 5 %, test_balls_separate_at_e_times_their_approach_speed: 0.25 m/s here), so in the
 * world at (1 + e) 10 = 15 m/s. The fastest frame (1 ms apart) is the one just after the hit:
 * the floor's friction takes mu_k g = 5 m/s^2, 5 mm/s a frame, from it. The ball's centre stays
 * ahead of the paddle's face at every frame (it never passes through). */
static double paddle_run(void)
{
    tb_scene *scene;
    double fps = 1000.0, duration;
    tb_integrator *integrator = start("paddle", &scene, &fps, &duration);
    const double r = 0.01;
    double fastest = 0.0, deepest = -INFINITY, closest = INFINITY;
    const long frames = lround(duration * fps);
    for (long k = 1; k <= frames; ++k) {
        const double t = (double)k / fps;
        advance(integrator, t);
        double p[3], b[3], v[3];
        position(scene, 0, p);
        position(scene, 1, b);
        tb_scene_body_velocity(scene, tb_scene_states_const(scene), 1, v);
        fastest = fmax(fastest, v[1]);
        closest = fmin(closest, b[1] - (p[1] + 0.025));
        deepest = fmax(deepest, depth(scene, 0, 1));
    }
    test_check(closest > 0.0, "closest the ball's centre came to the face (m)", closest, 0.0);
    printf("  deepest overlap at a frame %.3g m (the radius %.3g m); fastest %.4f m/s\n", deepest,
           r, fastest);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return fastest;
}

/* Euler's error in a bounce is of order 1 in the step: at its default step (1% growth of a
 * contact oscillation a step) the ball leaves 0.34 m/s fast (the law's 5 % of e, 0.25 m/s, is a
 * bound for the law, not for Euler's error). So under Euler the run is made at the default step h
 * and at h / 2: the excess must halve (ratio within 2 +- 0.4: order 1, the law's own error of a
 * few mm/s beside it), and the extrapolation to h = 0, 2 v(h / 2) - v(h), must meet 15 m/s
 * within the law's 0.25 m/s. */
static void paddle_euler(void)
{
    const double v_h = paddle_run();
    step_fraction = 0.5;
    const double v_half = paddle_run();
    const double ratio = (v_h - 15.0) / (v_half - 15.0), limit = 2.0 * v_half - v_h;
    test_check(fabs(ratio - 2.0) < 0.4, "Euler: (v(h) - 15) / (v(h/2) - 15), order 1", ratio, 2.0);
    test_check(fabs(limit - 15.0) < 0.25, "Euler: 2 v(h/2) - v(h) - (1 + e) 10 (m/s)", limit - 15.0,
               0.25);
}

static void paddle(void)
{
    if (cut_duration > 0.0) {
        paddle_run();
        printf("  %-62s skipped: the run was cut to %g s\n", "the ball's speed", cut_duration);
        return;
    }
    if (method_name != NULL && strcmp(method_name, "euler") == 0) {
        paddle_euler();
        return;
    }
    const double fastest = paddle_run();
    test_check(fabs(fastest - 15.0) < 0.25, "ball's speed after the hit - (1 + e) 10 (m/s)",
               fastest - 15.0, 0.25);
}

/* bat_sweep: the table (body 0, its near edge at y = -0.4 m), the bat (body 1, sweeping along -y,
 * its face 3 cm ahead of its origin, 8 cm tall) and five 6 cm boxes (bodies 2-6). The bat pushes
 * the boxes ahead of it: no box's centre within its reach comes behind its face at any frame (none
 * passes through). Within reach: the centre above the bat's underside less the box's half
 * diagonal (sqrt(3) 3 cm), lower than which no part of the box can touch the bat; a box fallen to
 * the floor (its centre 0.77 m below the bat's) may lie behind the face where the bat stops, at
 * y = -0.53 m, past the table's edge (rosenbrock at 1/240 s lands one at y = -0.526 m). By the
 * end (2 s) every box has gone off the table and rests on the floor: its centre past the edge,
 * at half its size less the ground's static sinking (0.05 mm), within 10 % of that sinking (the
 * four bottom corners share its weight), and slower than 1 mm/s. */
static void bat_sweep(void)
{
    tb_scene *scene;
    double fps = 200.0, duration;
    tb_integrator *integrator = start("bat_sweep", &scene, &fps, &duration);
    const double half = 0.03, pen = 5e-5, bat_half_height = 0.04;
    double closest = INFINITY;
    const long frames = lround(duration * fps);
    for (long k = 1; k <= frames; ++k) {
        advance(integrator, (double)k / fps);
        double bat[3];
        position(scene, 1, bat);
        for (size_t id = 2; id <= 6; ++id) {
            double b[3];
            position(scene, id, b);
            if (b[2] > bat[2] - bat_half_height - sqrt(3.0) * half) {
                closest = fmin(closest, (bat[1] - 0.03) - b[1]);
            }
        }
    }
    test_check(closest > 0.0, "closest a reachable box's centre came to the bat's face (m)",
               closest, 0.0);
    if (cut_duration > 0.0) {
        printf("  %-62s skipped: the run was cut to %g s\n", "on the floor", cut_duration);
    } else {
        for (size_t id = 2; id <= 6; ++id) {
            double b[3], v[3];
            position(scene, id, b);
            tb_scene_body_velocity(scene, tb_scene_states_const(scene), id, v);
            test_check(b[1] < -0.4 - half, "box's y past the table's edge (m)", b[1], -0.4 - half);
            const double sink = half - b[2];
            test_check(fabs(sink / pen - 1.0) < 0.1, "box on the floor: |sink / pen - 1|",
                       fabs(sink / pen - 1.0), 0.1);
            const double speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            test_check(speed < 1e-3, "box's speed (m/s)", speed, 1e-3);
        }
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(int argc, char **argv)
{
    static const test_example scenes[] = {{"table_roll", table_roll},
                                          {"platform", platform},
                                          {"paddle", paddle},
                                          {"bat_sweep", bat_sweep}};
    if (argc >= 3) {
        method_name = argv[2];
    }
    if (argc >= 4) {
        cut_duration = atof(argv[3]);
    }
    if (argc >= 5) {
        step_arg = atof(argv[4]);
    }
    return test_example_main(argc, argv, scenes, 4, 3,
                             "usage: test_example_kinds table_roll|platform|paddle|bat_sweep "
                             "[METHOD [DURATION [DT]]]");
}

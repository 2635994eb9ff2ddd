/* examples/scenes/bowl.json: a bowl of five convex pieces (a base and four walls) standing on the
 * floor, and three marbles dropped into it. Loaded from its file, run as written (RK4 at the
 * scene's default step) and checked against what must happen: the marbles stay inside the
 * bowl's inner volume at every frame, and end at rest on the base, their centres one radius
 * above it less the contact's static sinking; the bowl stays where it stands.
 *   test_example_bowl bowl [DURATION]
 * DURATION (s) cuts the run short (the sanitizer builds): the checks of the end are then
 * skipped and say so. */
#include "examples.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define MARBLES 3
#define MARBLE_RADIUS 0.01 /* m */
#define BASE_TOP 0.02      /* m: the base's top in the bowl's shape frame */
#define INNER_HALF 0.13    /* m: the walls' inner faces at x, y = +-0.13 in the bowl's frame */
#define WALL_TOP 0.12      /* m */
#define PENETRATION 8e-7   /* m: the contact's default static sinking under a body's weight */
#define DROP                                                                                       \
    0.0701 /* m: the highest marble's fall to the base (from 0.1 m to 0.03 m, and the              \
              bowl's 33 micrometres of settling) */

static double cut_duration; /* > 0: the run was cut to this many seconds */

typedef struct bowl_watch {
    double outside; /* the farthest a marble's surface came past a wall's inner face, m */
    double lowest;  /* the lowest a marble's centre came over the base's top, m */
} bowl_watch;

/* Marble i's centre in the bowl's shape frame (the frame its pieces are placed in). */
static void in_bowl(const tb_scene *scene, const double *y, size_t marble, double out[3])
{
    double pose[7], x[3];
    tb_scene_body_shape_pose(scene, y, 0, pose, pose + 3);
    tb_scene_body_point(scene, y, marble, (const double[3]){0, 0, 0}, x, NULL);
    const double d[3] = {x[0] - pose[0], x[1] - pose[1], x[2] - pose[2]};
    const double w = pose[3], u[3] = {-pose[4], -pose[5], -pose[6]}; /* world -> bowl */
    const double c[3] = {u[1] * d[2] - u[2] * d[1], u[2] * d[0] - u[0] * d[2],
                         u[0] * d[1] - u[1] * d[0]};
    const double cc[3] = {u[1] * c[2] - u[2] * c[1], u[2] * c[0] - u[0] * c[2],
                          u[0] * c[1] - u[1] * c[0]};
    for (int k = 0; k < 3; ++k) {
        out[k] = d[k] + 2.0 * (w * c[k] + cc[k]);
    }
}

static int watch(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    (void)frame, (void)t;
    bowl_watch *w = ctx;
    const double *y = tb_scene_states_const(scene);
    for (size_t m = 1; m <= MARBLES; ++m) {
        double p[3];
        in_bowl(scene, y, m, p);
        for (int k = 0; k < 2; ++k) {
            w->outside = fmax(w->outside, fabs(p[k]) + MARBLE_RADIUS - INNER_HALF);
        }
        w->lowest = fmin(w->lowest, p[2] - BASE_TOP);
    }
    return 0;
}

/* Each marble rests on the base alone: its weight on one point of stiffness M_marble g /
 * PENETRATION (the lighter body's), so its centre sits one radius less PENETRATION above the
 * base; within 2 PENETRATION (what is left of the landing's ringing and the rolling the step's
 * round-off starts, after 1.5 s at the law's damping). At rest: below 1e-4 m/s (the landings'
 * speeds, 0.8 m/s at most, decay by e = 0.3 a bounce). The bowl carries its weight and theirs
 * on the floor and stays: its centre moves by less than 1e-5 m across the floor (only the
 * marbles' landings push it, vertically) and it tilts by less than 1e-4 rad. */
static void bowl(void)
{
    tb_run_def run;
    tb_scene *scene = test_example_load(TUMBLE_SCENES_DIR, "bowl", &run);
    if (cut_duration > 0.0) {
        run.duration = fmin(run.duration, cut_duration);
    }
    run.fps = 240.0;
    const double start[2] = {tb_scene_states_const(scene)[0], tb_scene_states_const(scene)[1]};
    bowl_watch w = {-INFINITY, INFINITY};
    tb_error error;
    if (tb_scene_run(scene, &run, watch, &w, NULL, &error) != TB_STATUS_OK) {
        printf("run failed: %s\n", error.message);
        exit(1);
    }
    test_check(w.outside <= 0.0, "farthest a marble came past a wall's inner face (m)", w.outside,
               0.0);
    /* the deepest landing: the highest marble's, from DROP over the base at v = sqrt(2 g DROP); a
     * damped spring of rate omega >= sqrt(g / PENETRATION) compresses by less than v / omega */
    const double deepest = sqrt(2.0 * 9.81 * DROP) / sqrt(9.81 / PENETRATION);
    test_check(w.lowest > MARBLE_RADIUS - deepest,
               "lowest a marble's centre came over the base (m)", w.lowest,
               MARBLE_RADIUS - deepest);
    if (cut_duration > 0.0) {
        printf("  %-62s skipped: the run was cut to %g s\n", "at rest on the base", cut_duration);
        tb_scene_destroy(scene);
        return;
    }
    const double *y = tb_scene_states_const(scene);
    for (size_t m = 1; m <= MARBLES; ++m) {
        double p[3], v[3];
        in_bowl(scene, y, m, p);
        tb_scene_body_velocity(scene, y, m, v);
        const double height = p[2] - BASE_TOP - (MARBLE_RADIUS - PENETRATION);
        test_check(fabs(height) < 2 * PENETRATION, "marble's height over the base - (r - pen) (m)",
                   height, 2 * PENETRATION);
        test_check(p[2] < WALL_TOP, "marble's centre below the walls' top (m)", p[2], WALL_TOP);
        const double speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        test_check(speed < 1e-4, "marble's speed (m/s)", speed, 1e-4);
    }
    const double moved = hypot(y[0] - start[0], y[1] - start[1]);
    test_check(moved < 1e-5, "bowl's movement across the floor (m)", moved, 1e-5);
    double pose[7];
    tb_scene_body_shape_pose(scene, y, 0, pose, pose + 3);
    /* the angle between the bowl's z axis and the world's: cos = 1 - 2 (q_x^2 + q_y^2) */
    const double tilt = 2.0 * asin(fmin(1.0, hypot(pose[4], pose[5])));
    test_check(tilt < 1e-4, "bowl's tilt (rad)", tilt, 1e-4);
    tb_scene_destroy(scene);
}

int main(int argc, char **argv)
{
    static const test_example scenes[] = {{"bowl", bowl}};
    if (argc == 3) {
        cut_duration = atof(argv[2]);
    }
    return test_example_main(argc, argv, scenes, 1, 1, "usage: test_example_bowl bowl [DURATION]");
}

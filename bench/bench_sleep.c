/* What sleeping islands save: a pile of boxes built resting in a grid on the ground (layers of
 * side-by-side boxes 0.5 mm apart, each layer standing exactly on the one below), stepped under
 * RK4 at the scene's default step, costs this much CPU per simulated second while it is awake
 * (the first 0.1 s, before anything may sleep) and this much once every box is asleep (0.5 s
 * measured after the last box fell asleep). Prints CSV:
 *
 *   boxes,dt,awake_cpu_per_s,asleep_cpu_per_s,ratio,asleep_at
 *
 * (s, CPU s per simulated s, their ratio, the time the last box fell asleep). --boxes N picks
 * the pile's size (default 1000: a 10 x 10 grid 10 layers high); --quick runs 8 boxes for the
 * smoke test. --flying adds one box thrown up beside the pile, in flight (awake) until after
 * the measurement: the asleep figure is then a partly asleep scene's, where every asleep box
 * should cost nearly nothing. The figures are process CPU time, so a loaded machine changes
 * them little. */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */

#include "bench_common.h"

#include "tumble/tumble.h"

#include <math.h>

#define EDGE 0.1    /* m */
#define GAP 5e-4    /* m between side-by-side boxes: inside the contact's 1 mm margin */
#define AWAKE 0.1   /* s measured awake */
#define ASLEEP 0.5  /* s measured asleep */
#define FRAME 0.01  /* s between the run's outputs */
#define GIVE_UP 3.0 /* s: a pile that is not asleep by then is reported as such */

static int fail(const char *what, tb_status status, const tb_scene *scene)
{
    fprintf(stderr, "bench_sleep: %s: %s (%s)\n", what, tb_status_string(status),
            scene != NULL ? tb_scene_detail(scene) : "");
    return 1;
}

static int add_box(tb_scene *scene, double x, double y, double z, double up)
{
    const double size[3] = {EDGE, EDGE, EDGE};
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    shape.size[0] = shape.size[1] = shape.size[2] = EDGE;
    tb_contact_point corners[8];
    size_t count = 0, id = 0;
    tb_body_def body = tb_body_def_default();
    tb_status status = tb_contact_points_box(size, corners, 8, &count);
    if (status == TB_STATUS_OK) {
        status = tb_mass_from_box(TB_MASS_DENSITY, 700.0, size, &body.mass, NULL);
    }
    body.position[0] = x;
    body.position[1] = y;
    body.position[2] = z;
    body.velocity[2] = up;
    if (status == TB_STATUS_OK) {
        status = tb_scene_add_body(scene, &body, &id);
    }
    if (status == TB_STATUS_OK) {
        status = tb_scene_set_body_shape(scene, id, &shape);
    }
    if (status == TB_STATUS_OK) {
        status = tb_scene_set_contact_points(scene, id, corners, count, 4);
    }
    return status == TB_STATUS_OK ? 0 : fail("adding a box", status, scene);
}

/* m/s: a box thrown up at this speed flies 2 FLY_UP / g = 4.1 s, past GIVE_UP + ASLEEP */
#define FLY_UP 20.0

/* side x side boxes per layer, layers high, boxes in all: the last layer may be partial; with
 * flying one more box, thrown up 10 m beside the pile. */
static tb_scene *pile(size_t boxes, bool flying)
{
    size_t side = 1;
    while (side * side * side < boxes) {
        ++side;
    }
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = boxes + 1;
    tb_scene *scene = NULL;
    if (tb_scene_create(&def, &scene, NULL) != TB_STATUS_OK) {
        return NULL;
    }
    int rc = 0;
    for (size_t k = 0; k < boxes && rc == 0; ++k) {
        const size_t i = k % side, j = (k / side) % side, layer = k / (side * side);
        rc = add_box(scene, (double)i * (EDGE + GAP), (double)j * (EDGE + GAP),
                     EDGE * (0.5 + (double)layer), 0.0);
    }
    if (flying && rc == 0) {
        rc = add_box(scene, -10.0, 0.0, 0.5 * EDGE, FLY_UP);
    }
    tb_status status = rc == 0 ? tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}) : 1;
    tb_ground_def ground = tb_ground_def_default();
    tb_contact_def contact = tb_contact_def_default();
    if (status == TB_STATUS_OK) {
        status = tb_scene_add_ground(scene, &ground);
    }
    if (status == TB_STATUS_OK) {
        status = tb_scene_add_contact(scene, &contact);
    }
    if (status != TB_STATUS_OK) {
        tb_scene_destroy(scene);
        return NULL;
    }
    return scene;
}

/* CPU seconds per simulated second from t to t + span, in outputs FRAME apart. */
static double cost(tb_integrator *integrator, double t, double span, tb_status *status)
{
    const double start = bench_cpu_seconds();
    for (double target = t + FRAME; target < t + span + 0.5 * FRAME && *status == TB_STATUS_OK;
         target += FRAME) {
        *status = tb_integrator_advance(integrator, target);
    }
    return (bench_cpu_seconds() - start) / span;
}

int main(int argc, char **argv)
{
    size_t boxes = 1000;
    bool flying = false;
    for (int k = 1; k < argc; ++k) {
        if (strcmp(argv[k], "--quick") == 0) {
            boxes = 8;
        } else if (strcmp(argv[k], "--boxes") == 0 && k + 1 < argc) {
            boxes = (size_t)strtoul(argv[++k], NULL, 10);
        } else if (strcmp(argv[k], "--flying") == 0) {
            flying = true;
        }
    }
    tb_scene *scene = pile(boxes > 0 ? boxes : 1, flying);
    if (scene == NULL) {
        return fail("building the pile", TB_STATUS_OUT_OF_MEMORY, NULL);
    }
    tb_integrator_def def = tb_integrator_def_default();
    def.method = TB_METHOD_RK4;
    def.dt = 0.0; /* the scene's default step */
    def.max_steps = 100000000;
    tb_integrator *integrator = NULL;
    tb_status status = tb_scene_integrator_create(scene, &def, 0.0, &integrator);
    if (status != TB_STATUS_OK) {
        return fail("integrator", status, scene);
    }
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    double dt = 0.0;
    tb_scene_default_step(scene, TB_METHOD_RK4, &dt);
    const double awake = cost(integrator, 0.0, AWAKE, &status);
    double t = AWAKE;
    size_t asleep = 0;
    while (status == TB_STATUS_OK && t < GIVE_UP &&
           tb_scene_asleep_count(scene, &asleep) == TB_STATUS_OK && asleep < boxes) {
        t += FRAME;
        status = tb_integrator_advance(integrator, t);
    }
    const double asleep_at = t;
    const double slept = status == TB_STATUS_OK ? cost(integrator, t, ASLEEP, &status) : NAN;
    if (status != TB_STATUS_OK) {
        return fail("stepping", status, scene);
    }
    tb_scene_asleep_count(scene, &asleep);
    if (asleep < boxes) {
        fprintf(stderr, "bench_sleep: only %zu of %zu boxes asleep at %g s\n", asleep, boxes, t);
    }
    printf("boxes,dt,awake_cpu_per_s,asleep_cpu_per_s,ratio,asleep_at\n");
    printf("%zu,%.6g,%.6g,%.6g,%.6g,%.6g\n", boxes, dt, awake, slept, awake / slept, asleep_at);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return 0;
}

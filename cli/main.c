/* tumble: run or check a scene file from the command line.
 * Exit codes: 0 success, 1 the simulation failed, 2 bad input (usage, scene file, output). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, isatty, fileno */
#include "accuracy.h"
#include "options.h"

#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { EXIT_OK = 0, EXIT_SIMULATION = 1, EXIT_INPUT = 2 };

static const char usage[] =
    "usage: tumble run SCENE.json [options]     simulate and write frames as CSV\n"
    "       tumble check SCENE.json             validate a scene without running it\n"
    "       tumble accuracy SCENE.json [--target-error E] [--chart FILE.svg]\n"
    "                                           error against cost of every integrator\n"
    "       tumble --help | --version\n"
    "\n"
    "run options (each overrides the scene file's setting):\n"
    "  --integrator M   euler, midpoint, rk4 (fixed step) or cvode-adams, cvode-bdf (adaptive)\n"
    "  --dt H           step size in seconds, for fixed-step methods\n"
    "  --rtol R         relative tolerance, for adaptive methods (e.g. 1e-6)\n"
    "  --atol A         absolute tolerance, for adaptive methods (0: derived from the bodies)\n"
    "  --fps F          frames per second written\n"
    "  --duration T     seconds simulated\n"
    "  --out FILE.csv   where the frames go (default: standard output)\n"
    "\n"
    "accuracy runs the scene with each integrator over a sweep of its setting against a\n"
    "tight reference (cvode-bdf, rtol 1e-11), prints position and orientation errors, CPU time\n"
    "and derivative evaluations, and names the cheapest setting whose position error is at\n"
    "most E metres (default 1e-3). --fps and --duration apply to it too.\n"
    "\n"
    "The CSV has one row per body per frame:\n"
    "  t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"
    "all in the world frame and SI units: the position and unit quaternion of the body's\n"
    "shape frame (the frame its shape is described in, so a model can be placed with them),\n"
    "that frame origin's velocity, and the angular velocity. A summary goes to standard error.\n"
    "\n"
    "exit codes: 0 success, 1 the simulation failed, 2 bad input.\n"
    "The scene format is described in docs/scene-format.md.\n";

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Conserved quantities at a frame, for the summary. */
typedef struct invariants {
    double energy, P[3], L[3];
} invariants;

static void measure(const tb_scene *scene, invariants *out)
{
    const double *y = tb_scene_states_const(scene);
    double kinetic, potential;
    tb_scene_kinetic_energy(scene, y, &kinetic);
    tb_scene_potential_energy(scene, y, &potential);
    out->energy = kinetic + potential;
    tb_scene_linear_momentum(scene, y, out->P);
    tb_scene_angular_momentum(scene, y, (const double[3]){0, 0, 0}, out->L);
}

typedef struct writer {
    FILE *out;
    double duration;
    double started, last_progress;
    int progress; /* stderr is a terminal */
    int failed;   /* a write failed */
    invariants first, last;
} writer;

static void write_body(FILE *out, double t, const tb_scene *scene, size_t id)
{
    const double *y = tb_scene_states_const(scene);
    double origin[3], q[4], v[3], w[3], arm[3];
    tb_scene_body_shape_pose(scene, y, id, origin, q);
    tb_scene_body_velocity(scene, y, id, v);
    tb_scene_body_angular_velocity(scene, y, id, w);
    /* velocity of the shape origin: v + omega x (origin - centre of mass) */
    const double *x = y + TB_STATE_SIZE * id;
    for (int k = 0; k < 3; ++k) {
        arm[k] = origin[k] - x[k];
    }
    v[0] += w[1] * arm[2] - w[2] * arm[1];
    v[1] += w[2] * arm[0] - w[0] * arm[2];
    v[2] += w[0] * arm[1] - w[1] * arm[0];
    fprintf(out, "%.9g,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", t,
            tb_scene_body_name(scene, id), origin[0], origin[1], origin[2], q[0], q[1], q[2], q[3],
            v[0], v[1], v[2], w[0], w[1], w[2]);
}

static int on_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    writer *w = ctx;
    for (size_t id = 0; id < tb_scene_body_count(scene); ++id) {
        write_body(w->out, t, scene, id);
    }
    if (ferror(w->out)) {
        w->failed = 1;
        return 1;
    }
    measure(scene, frame == 0 ? &w->first : &w->last);
    const double clock = now();
    if (w->progress && clock - w->started > 1.0 && clock - w->last_progress > 0.1) {
        fprintf(stderr, "\r  t = %.2f / %.2f s (%.0f%%)", t, w->duration,
                w->duration > 0 ? 100.0 * t / w->duration : 100.0);
        w->last_progress = clock;
    }
    return 0;
}

static double norm3(const double a[3], const double b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

static double size3(const double a[3])
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

static void report_drift(const char *what, int conserved, double change, double scale,
                         const char *unit)
{
    if (!conserved) {
        fprintf(stderr, "  %-24s not conserved by this scene's effects\n", what);
    } else if (scale > 0) {
        fprintf(stderr, "  %-24s drift %.3g %s (%.3g relative)\n", what, change, unit,
                change / scale);
    } else {
        fprintf(stderr, "  %-24s drift %.3g %s\n", what, change, unit);
    }
}

static void summary(const char *path, const tb_scene *scene, const tb_run_def *run,
                    const tb_integrator_stats *stats, double seconds, const writer *w)
{
    const tb_integrator_def *i = &run->integrator;
    fprintf(stderr, "tumble: %s: %zu bodies, %zu effects, %.6g s at %.6g fps\n", path,
            tb_scene_body_count(scene), tb_scene_effect_count(scene), run->duration, run->fps);
    if (tb_method_is_adaptive(i->method)) {
        fprintf(stderr, "  integrator               %s, rtol %g, atol %s\n",
                tb_method_name(i->method), i->rtol, i->atol > 0 ? "given" : "per body");
    } else {
        fprintf(stderr, "  integrator               %s, dt %g s\n", tb_method_name(i->method),
                i->dt);
    }
    fprintf(stderr, "  steps                    %ld (%ld failed attempts)\n", stats->steps,
            stats->failed_steps);
    fprintf(stderr, "  derivative evaluations   %ld\n", stats->derivative_evals);
    fprintf(stderr, "  wall time                %.3f s\n", seconds);
    tb_conserved c;
    tb_scene_conserved(scene, &c);
    report_drift("energy", c.energy, fabs(w->last.energy - w->first.energy), fabs(w->first.energy),
                 "J");
    report_drift("linear momentum", c.linear_momentum, norm3(w->last.P, w->first.P),
                 size3(w->first.P), "kg m/s");
    report_drift("angular momentum", c.angular_momentum, norm3(w->last.L, w->first.L),
                 size3(w->first.L), "kg m^2/s");
}

static int load(const cli_options *o, tb_scene **scene, tb_run_def *run)
{
    tb_error error;
    if (tb_scene_load_file(o->scene, scene, run, &error) != TB_STATUS_OK) {
        fprintf(stderr, "tumble: %s\n", error.message);
        return EXIT_INPUT;
    }
    char message[256];
    if (!cli_apply(o, run, message, sizeof message)) {
        fprintf(stderr, "tumble: %s\n", message);
        tb_scene_destroy(*scene);
        return EXIT_INPUT;
    }
    double max_dt;
    char which[TB_DETAIL_SIZE];
    tb_scene_max_stable_step(*scene, run->integrator.method, &max_dt, which);
    if (!tb_scene_allow_unstable(*scene) && run->integrator.dt > max_dt) {
        fprintf(stderr,
                "tumble: %s: dt %g s is beyond %s's stability limit for %s: use --dt %.3g or "
                "less, or --integrator cvode-bdf\n",
                o->scene, run->integrator.dt, tb_method_name(run->integrator.method), which,
                max_dt);
        tb_scene_destroy(*scene);
        return EXIT_INPUT;
    }
    return EXIT_OK;
}

static int run_command(const cli_options *o)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    int code = load(o, &scene, &run);
    if (code != EXIT_OK) {
        return code;
    }
    writer w = {.out = o->out ? fopen(o->out, "w") : stdout, .duration = run.duration};
    if (w.out == NULL) {
        fprintf(stderr, "tumble: --out %s: cannot open for writing\n", o->out);
        tb_scene_destroy(scene);
        return EXIT_INPUT;
    }
    w.progress = isatty(fileno(stderr));
    fprintf(w.out, "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n");
    tb_integrator_stats stats;
    tb_error error;
    w.started = now();
    const tb_status status = tb_scene_run(scene, &run, on_frame, &w, &stats, &error);
    const double seconds = now() - w.started;
    if (w.progress && seconds > 1.0) {
        fprintf(stderr, "\r\033[K");
    }
    if (o->out != NULL && fclose(w.out) != 0) {
        w.failed = 1;
    }
    if (status == TB_STATUS_OK) {
        summary(o->scene, scene, &run, &stats, seconds, &w);
    } else {
        fprintf(stderr, "tumble: %s: simulation failed: %s\n", o->scene,
                w.failed ? "writing the frames failed" : error.message);
    }
    tb_scene_destroy(scene);
    return status == TB_STATUS_OK ? EXIT_OK : EXIT_SIMULATION;
}

static int check_command(const cli_options *o)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    int code = load(o, &scene, &run);
    if (code == EXIT_OK) {
        fprintf(stderr, "tumble: %s: ok: %zu bodies, %zu effects, %s, %.6g s at %.6g fps\n",
                o->scene, tb_scene_body_count(scene), tb_scene_effect_count(scene),
                tb_method_name(run.integrator.method), run.duration, run.fps);
        tb_scene_destroy(scene);
    }
    return code;
}

int main(int argc, char **argv)
{
    if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        fputs(usage, stdout);
        return EXIT_OK;
    }
    if (argc == 2 && strcmp(argv[1], "--version") == 0) {
        printf("tumble %s\n", TB_VERSION_STRING);
        return EXIT_OK;
    }
    cli_options options;
    char message[256];
    if (!cli_parse(argc, argv, &options, message, sizeof message)) {
        fprintf(stderr, "tumble: %s\n", message);
        return EXIT_INPUT;
    }
    if (strcmp(options.command, "accuracy") == 0) {
        return accuracy_command(&options);
    }
    return strcmp(options.command, "run") == 0 ? run_command(&options) : check_command(&options);
}

/* tumble run and tumble check. Both load the scene and make a dry run (tb_scene_run stopped
 * at its first frame), so check refuses exactly what run would refuse: the library applies
 * its own rules (frame limit, stability limit, settings that do not fit the method) and the
 * command repeats none of them. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, isatty, fileno */
#include "check_contact.h"
#include "check_steps.h"
#include "commands.h"
#include "events.h"
#include "interrupt.h"
#include "joints.h"
#include "output.h"
#include "summary.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int stop_at_first_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    (void)frame, (void)t, (void)scene, (void)ctx;
    return 1;
}

int cli_load(const cli_options *o, tb_scene **scene, tb_run_def *run)
{
    tb_error error;
    if (tb_scene_load_file(o->scene, scene, run, &error) != TB_STATUS_OK) {
        fprintf(stderr, "tumble: %s\n", error.message);
        return CLI_EXIT_INPUT;
    }
    char message[256];
    double error_left = 0.0;
    if (o->project_joints && tb_scene_project_joints(*scene, 0.0, &error_left) != TB_STATUS_OK) {
        fprintf(stderr, "tumble: %s: --project-joints: %s\n", o->scene, tb_scene_detail(*scene));
        tb_scene_destroy(*scene);
        *scene = NULL;
        return CLI_EXIT_INPUT;
    }
    if (!cli_apply(o, run, message, sizeof message)) {
        fprintf(stderr, "tumble: %s\n", message);
        tb_scene_destroy(*scene);
        *scene = NULL;
        return CLI_EXIT_INPUT;
    }
    return CLI_EXIT_OK;
}

/* The states are put back as they were, to the bit (the first frame may renormalise
 * quaternions). */
int cli_dry_run(const cli_options *o, tb_scene *scene, const tb_run_def *run)
{
    const size_t size = tb_scene_state_size(scene);
    double *saved = malloc(size * sizeof(double) + 1);
    if (saved == NULL) {
        fprintf(stderr, "tumble: %s: out of memory\n", o->scene);
        return CLI_EXIT_SIMULATION;
    }
    tb_error error;
    size_t frames = 0; /* run keeps every frame of every body: the library bounds them */
    if (tb_run_output_frames(tb_scene_body_count(scene), run->duration, run->fps, &frames,
                             &error) != TB_STATUS_OK) {
        fprintf(stderr, "tumble: %s: %s\n", o->scene, error.message);
        free(saved);
        return CLI_EXIT_INPUT;
    }
    memcpy(saved, tb_scene_states(scene), size * sizeof(double));
    const tb_status status = tb_scene_run(scene, run, stop_at_first_frame, NULL, NULL, &error);
    memcpy(tb_scene_states(scene), saved, size * sizeof(double));
    free(saved);
    if (status != TB_STATUS_CANCELLED) {
        fprintf(stderr, "tumble: %s: %s\n", o->scene, error.message);
        return CLI_EXIT_INPUT;
    }
    return CLI_EXIT_OK;
}

typedef struct writer {
    cli_output output;  /* CSV */
    tb_writer *frames;  /* npz, glb, gltf: the library's writer, else NULL */
    bool frames_failed; /* a write of the library's writer failed */
    cli_events events;  /* --events: open when has_events */
    bool has_events;
    bool gltf;         /* frames is a glTF writer: the events go into it too */
    cli_joints joints; /* --joints: open when has_joints */
    bool has_joints;
    double duration;
    double started, last_progress;
    int progress; /* stderr is a terminal */
    invariants first;
} writer;

static void write_body(cli_output *out, double t, const tb_scene *scene, size_t id)
{
    const double *y = tb_scene_states_const(scene);
    double origin[3], q[4], v[3], w[3], arm[3];
    tb_scene_body_shape_pose(scene, y, id, origin, q);
    tb_scene_body_velocity(scene, y, id, v);
    tb_scene_body_angular_velocity(scene, y, id, w);
    /* velocity of the shape origin: v + omega x (origin - centre of mass) */
    tb_body_state state;
    tb_scene_get_state(scene, id, &state);
    const double *x = state.x;
    for (int k = 0; k < 3; ++k) {
        arm[k] = origin[k] - x[k];
    }
    v[0] += w[1] * arm[2] - w[2] * arm[1];
    v[1] += w[2] * arm[0] - w[0] * arm[2];
    v[2] += w[0] * arm[1] - w[1] * arm[0];
    /* 17 significant digits: every double reads back as itself */
    cli_output_printf(out, "%.17g,", t);
    cli_output_csv_field(out, tb_scene_body_name(scene, id));
    cli_output_printf(out,
                      ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                      "%.17g\n",
                      origin[0], origin[1], origin[2], q[0], q[1], q[2], q[3], v[0], v[1], v[2],
                      w[0], w[1], w[2]);
}

/* The progress line on a terminal, for every output format: simulated time, the rate in
 * frames per wall-clock second, and the time left at that rate. */
static void show_progress(const writer *w, size_t frame, double t, double elapsed)
{
    const double rate = (double)(frame + 1) / elapsed;               /* frames per second */
    const double speed = t > 0 ? t / elapsed : 0.0;                  /* simulated s per wall s */
    const double left = speed > 0 ? (w->duration - t) / speed : 0.0; /* wall s */
    fprintf(stderr, "\r  t = %.2f / %.2f s (%.0f%%), %.3g frames/s, %.0f s left\033[K", t,
            w->duration, w->duration > 0 ? 100.0 * t / w->duration : 100.0, rate, left);
}

static int on_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    writer *w = ctx;
    if (cli_interrupt_caught() != 0) {
        return 1; /* stop: Ctrl-C */
    }
    if (w->frames != NULL && tb_writer_frame(w->frames, t, scene) != TB_STATUS_OK) {
        w->frames_failed = true;
        return 1; /* stop: the frames are being lost */
    }
    for (size_t id = 0; w->frames == NULL && id < tb_scene_body_count(scene); ++id) {
        write_body(&w->output, t, scene, id);
    }
    if (w->output.error != 0 || (w->has_joints && !cli_joints_frame(&w->joints, t))) {
        return 1; /* stop: the frames are being lost */
    }
    if (frame == 0) {
        summary_measure(scene, &w->first);
    }
    const double clock = now();
    if (w->progress && clock - w->started > 1.0 && clock - w->last_progress > 0.1) {
        show_progress(w, frame, t, clock - w->started);
        w->last_progress = clock;
    }
    return 0;
}

/* Finishes the output: the CSV stream into path (NULL: standard output), removed when its
 * write failed (its last line cut short, as the events' file is), or the library's writer
 * (which writes npz and glTF now, or, after a failed run, removes its unfinished file). */
static bool close_output(writer *w, const char *path, tb_status status, char *message, size_t size)
{
    if (w->frames == NULL) {
        const bool written = cli_output_close(&w->output, message, size);
        if (!written) {
            cli_output_remove_partial(path);
        }
        return written;
    }
    tb_error error;
    if (w->frames_failed) {
        snprintf(message, size, "%s", tb_writer_detail(w->frames)); /* names the file */
        tb_writer_destroy(w->frames);
        return false;
    }
    if (status != TB_STATUS_OK) {
        tb_writer_destroy(w->frames);
        return true; /* the simulation's failure is reported */
    }
    if (tb_writer_close(w->frames, &error) != TB_STATUS_OK) {
        snprintf(message, size, "%s", error.message);
        return false;
    }
    return true;
}

/* After Ctrl-C: the output is gone (the library's writer removed its side file when it was
 * destroyed; a CSV written into a regular file holds the first frames only, and is removed). */
static int interrupted(const cli_options *o, const writer *w)
{
    if (w->frames == NULL) {
        cli_output_remove_partial(o->out);
    }
    fprintf(stderr, "tumble: %s: interrupted%s%s\n", o->scene,
            o->out != NULL ? ", nothing written to " : "", o->out != NULL ? o->out : "");
    return CLI_EXIT_SIMULATION;
}

/* Runs into the opened output; the exit code. */
static int simulate(const cli_options *o, tb_scene *scene, const tb_run_def *run, writer *w)
{
    w->progress = isatty(fileno(stderr));
    if (w->frames == NULL) {
        cli_output_printf(&w->output, "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n");
    }
    tb_integrator_stats stats;
    tb_error error;
    const double dt = summary_step(scene, run); /* at the start, where the run chooses it */
    const double resolving = summary_resolving_step(scene, run);
    w->started = now();
    const tb_status status = tb_scene_run(scene, run, on_frame, w, &stats, &error);
    const double seconds = now() - w->started;
    if (w->progress && seconds > 1.0) {
        fprintf(stderr, "\r\033[K");
    }
    /* stopped by Ctrl-C (one that came after the last frame leaves the finished file) */
    const bool stopped = status == TB_STATUS_CANCELLED && cli_interrupt_caught() != 0;
    char message[TB_DETAIL_SIZE];
    if (w->has_events && w->gltf && status == TB_STATUS_OK &&
        tb_writer_set_contact_events(w->frames, w->events.events, w->events.count) !=
            TB_STATUS_OK) {
        w->frames_failed = true; /* close_output reports the writer's detail */
    }
    const bool events_ok =
        !w->has_events ||
        cli_events_close(&w->events, scene, status == TB_STATUS_OK, message, sizeof message);
    if (!events_ok && !stopped) {
        fprintf(stderr, "tumble: %s: %s\n", o->scene, message);
    }
    const bool joints_ok = !w->has_joints || cli_joints_close(&w->joints, status == TB_STATUS_OK,
                                                              message, sizeof message);
    if (!joints_ok && !stopped) {
        fprintf(stderr, "tumble: %s: %s\n", o->scene, message);
    }
    if (!close_output(w, o->out, status, message, sizeof message) && !stopped) {
        fprintf(stderr, "tumble: %s: %s\n", o->scene, message);
        return CLI_EXIT_SIMULATION;
    }
    if ((!events_ok || !joints_ok) && !stopped) {
        return CLI_EXIT_SIMULATION;
    }
    if (stopped) {
        return interrupted(o, w);
    }
    if (status != TB_STATUS_OK) {
        fprintf(stderr, "tumble: %s: simulation failed: %s\n", o->scene, error.message);
        return CLI_EXIT_SIMULATION;
    }
    invariants last;
    summary_measure(scene, &last);
    summary_print(o->scene, scene, run, dt, &stats, seconds, &w->first, &last);
    summary_print_resolution(run, dt, fmin(resolving, summary_resolving_step(scene, run)));
    summary_print_impacts(scene);
    return CLI_EXIT_OK;
}

/* Whether path's name has an extension (a dot after its last slash). */
static bool has_extension(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot != NULL && (slash == NULL || dot > slash);
}

/* The output format: --format, else --out's extension (.csv, .npz, .glb, .gltf, .usda; another
 * is refused, none is CSV), else CSV; formats other than CSV need --out; --rotation applies to
 * glTF. */
static bool choose_format(const cli_options *o, tb_writer_def *def, char *message, size_t size)
{
    if (o->format != NULL && tb_output_format_from_name(o->format, &def->format) != 0) {
        snprintf(message, size, "--format: must be csv, npz, glb, gltf or usda, got \"%s\"",
                 o->format);
        return false;
    }
    if (o->format == NULL && o->out != NULL && has_extension(o->out) &&
        !cli_output_same_file(o->out, o->scene) && /* refused as such when opened */
        tb_output_format_from_path(o->out, &def->format) != TB_STATUS_OK) {
        snprintf(message, size,
                 "--out %s: no writer for this extension: the formats are .csv, .npz, .gltf, "
                 ".glb and .usda (or give --format)",
                 o->out);
        return false;
    }
    const bool gltf = def->format == TB_OUTPUT_GLB || def->format == TB_OUTPUT_GLTF;
    if (o->rotation != NULL &&
        (!gltf || (strcmp(o->rotation, "cubic") != 0 && strcmp(o->rotation, "linear") != 0))) {
        snprintf(message, size,
                 gltf ? "--rotation: must be cubic or linear, got \"%s\""
                      : "--rotation applies to glb and gltf output, not %s",
                 gltf ? o->rotation : tb_output_format_name(def->format));
        return false;
    }
    def->rotation_keys = o->rotation != NULL && strcmp(o->rotation, "linear") == 0
                             ? TB_ROTATION_LINEAR
                             : TB_ROTATION_CUBICSPLINE;
    if (def->format != TB_OUTPUT_CSV && o->out == NULL) {
        snprintf(message, size, "--format %s: needs --out FILE (not standard output)",
                 tb_output_format_name(def->format));
        return false;
    }
    return true;
}

/* npz, glTF and USD go through the library's writer, which draws the scene's shapes. */
static int open_frames_writer(const cli_options *o, tb_writer_def *def, const tb_scene *scene,
                              writer *w)
{
    if (cli_output_same_file(o->out, o->scene)) {
        fprintf(stderr, "tumble: --out %s is the scene file %s: refusing to overwrite it\n", o->out,
                o->scene);
        return CLI_EXIT_INPUT;
    }
    tb_error error;
    if (tb_writer_open(o->out, def, scene, &w->frames, &error) != TB_STATUS_OK) {
        fprintf(stderr, "tumble: --out %s\n", error.message);
        return CLI_EXIT_INPUT;
    }
    w->output.name = o->out;
    return CLI_EXIT_OK;
}

/* --events FILE: never the frames' file; opened before it (and removed if that fails). */
static int open_events(const cli_options *o, tb_scene *scene, writer *w)
{
    char message[TB_DETAIL_SIZE];
    if (o->out != NULL &&
        (strcmp(o->events, o->out) == 0 || cli_output_same_file(o->events, o->out))) {
        snprintf(message, sizeof message, "--events %s is the --out file", o->events);
    } else if (cli_events_open(&w->events, o->events, o->scene, scene, o->hit_speed, message,
                               sizeof message)) {
        w->has_events = true;
        return CLI_EXIT_OK;
    }
    fprintf(stderr, "tumble: %s\n", message);
    return CLI_EXIT_INPUT;
}

/* --joints FILE: never the frames' or the events' file; opened before the frames' file. */
static int open_joints(const cli_options *o, tb_scene *scene, writer *w)
{
    char message[TB_DETAIL_SIZE];
    const char *const others[2] = {o->out, o->events};
    for (int k = 0; k < 2; ++k) {
        if (others[k] != NULL &&
            (strcmp(o->joints, others[k]) == 0 || cli_output_same_file(o->joints, others[k]))) {
            fprintf(stderr, "tumble: --joints %s is the %s file\n", o->joints,
                    k == 0 ? "--out" : "--events");
            return CLI_EXIT_INPUT;
        }
    }
    if (!cli_joints_open(&w->joints, o->joints, o->scene, scene, message, sizeof message)) {
        fprintf(stderr, "tumble: --joints %s\n", message);
        return CLI_EXIT_INPUT;
    }
    w->has_joints = true;
    return CLI_EXIT_OK;
}

/* --out is neither the events' nor the joints' file, which exist by now: spelt otherwise
 * (./x.csv and x.csv) before either was made, their paths could not be told apart. */
static int check_out_apart(const cli_options *o)
{
    const char *const others[2] = {o->events, o->joints};
    for (int k = 0; k < 2; ++k) {
        if (o->out != NULL && others[k] != NULL && cli_output_same_file(o->out, others[k])) {
            fprintf(stderr, "tumble: --out %s is the %s file\n", o->out,
                    k == 0 ? "--events" : "--joints");
            return CLI_EXIT_INPUT;
        }
    }
    return CLI_EXIT_OK;
}

int cli_run_command(const cli_options *o)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    int code = cli_load(o, &scene, &run);
    if (code != CLI_EXIT_OK) {
        return code;
    }
    code = cli_dry_run(o, scene, &run);
    cli_interrupt_catch(); /* before the output is opened: from then on Ctrl-C cleans it up */
    writer w = {.duration = run.duration};
    char message[TB_DETAIL_SIZE];
    tb_writer_def def = tb_writer_def_default();
    if (code == CLI_EXIT_OK && !choose_format(o, &def, message, sizeof message)) {
        fprintf(stderr, "tumble: %s\n", message);
        code = CLI_EXIT_INPUT;
    }
    def.fps = run.fps; /* USD: its time codes are frames */
    size_t frames = 0; /* npz: known, the frames stream to the file during the run */
    if (code == CLI_EXIT_OK && tb_run_output_frames(tb_scene_body_count(scene), run.duration,
                                                    run.fps, &frames, NULL) == TB_STATUS_OK) {
        def.frame_count = frames;
    }
    if (code == CLI_EXIT_OK && o->has_hit_speed && o->events == NULL) {
        fprintf(stderr, "tumble: --hit-speed applies with --events FILE\n");
        code = CLI_EXIT_INPUT;
    }
    if (code == CLI_EXIT_OK && o->events != NULL) {
        code = open_events(o, scene, &w);
    }
    if (code == CLI_EXIT_OK && o->joints != NULL) {
        code = open_joints(o, scene, &w);
    }
    if (code == CLI_EXIT_OK) {
        code = check_out_apart(o);
    }
    w.gltf = def.format == TB_OUTPUT_GLB || def.format == TB_OUTPUT_GLTF;
    if (code == CLI_EXIT_OK && def.format != TB_OUTPUT_CSV) {
        code = open_frames_writer(o, &def, scene, &w);
    } else if (code == CLI_EXIT_OK &&
               !cli_output_open(&w.output, o->out, o->scene, message, sizeof message)) {
        fprintf(stderr, "tumble: --out %s\n", message);
        code = CLI_EXIT_INPUT;
    }
    if (code == CLI_EXIT_OK) {
        code = simulate(o, scene, &run, &w);
    } else {
        if (w.has_events) {
            cli_events_close(&w.events, scene, false, message, sizeof message); /* removes it */
        }
        if (w.has_joints) {
            cli_joints_close(&w.joints, false, message, sizeof message); /* removes it */
        }
    }
    tb_scene_destroy(scene);
    cli_interrupt_finish();
    return code;
}

int cli_check_command(const cli_options *o)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    int code = cli_load(o, &scene, &run);
    if (code == CLI_EXIT_OK) {
        code = cli_dry_run(o, scene, &run);
    }
    if (code == CLI_EXIT_OK) {
        code = cli_check_joints(o->scene, scene);
    }
    if (code == CLI_EXIT_OK) {
        const size_t bodies = tb_scene_body_count(scene), effects = tb_scene_effect_count(scene);
        char joints[48];
        summary_joints(scene, joints, sizeof joints);
        fprintf(stderr, "tumble: %s: ok: %zu %s, %zu %s%s, %s, %.6g s at %.6g fps\n", o->scene,
                bodies, summary_plural(bodies, "body", "bodies"), effects,
                summary_plural(effects, "effect", "effects"), joints,
                tb_method_name(run.integrator.method), run.duration, run.fps);
        cli_check_steps(scene);
        cli_check_contact(scene);
    }
    tb_scene_destroy(scene);
    /* the report is the command's output: one standard error could not take is a failure (its
     * stream is the one that would say so, so this exit code is all that tells) */
    if (code == CLI_EXIT_OK && (fflush(stderr) != 0 || ferror(stderr))) {
        code = CLI_EXIT_SIMULATION;
    }
    return code;
}

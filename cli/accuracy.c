/* tumble accuracy: the library's sweep (tb_scene_accuracy_sweep) on the user's scene, printed
 * as a table as each setting finishes, with the cheapest setting for the error budget and an
 * optional chart. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "chart.h"
#include "commands.h"
#include "output.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

/* Seconds between progress lines (wall clock): a line when a setting is done, and within a run
 * one whenever the last line is this old, naming the run and how far it got; so a sweep of
 * minutes says where it is and a short one prints a line per setting. */
#define PROGRESS_INTERVAL 5.0

/* The sweep's progress on standard error (the table stays alone on standard output). */
typedef struct progress {
    double started, last; /* wall clock, s: the sweep's start, the last line */
} progress;

typedef struct table {
    cli_output *out;
    size_t count;
    progress *progress;
} table;

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void format_setting(char *out, size_t size, tb_method method, double setting)
{
    if (tb_method_is_adaptive(method)) {
        snprintf(out, size, "rtol %.0e", setting);
    } else {
        snprintf(out, size, "dt 1/%.0f", setting);
    }
}

/* Which run a report is about: "reference rk4 dt 1/309120", "[ 3/17] euler dt 1/336000". */
static void describe_run(char *out, size_t size, const tb_accuracy_progress *p)
{
    char setting[32];
    format_setting(setting, sizeof setting, p->method, p->setting);
    if (p->kind == TB_ACCURACY_RUN_SETTING) {
        snprintf(out, size, "[%2zu/%zu] %s %s", p->index + 1, p->count, tb_method_name(p->method),
                 setting);
    } else {
        snprintf(out, size, "%s %s %s",
                 p->kind == TB_ACCURACY_RUN_REFERENCE ? "reference" : "check",
                 tb_method_name(p->method), setting);
    }
}

static void show_progress(const tb_accuracy_progress *p, void *ctx)
{
    progress *w = ctx;
    const double clock = wall_seconds();
    if (clock - w->last < PROGRESS_INTERVAL) {
        return;
    }
    w->last = clock;
    char what[96];
    describe_run(what, sizeof what, p);
    fprintf(stderr, "tumble accuracy: %s: t = %.4g of %.4g s, %.0f s elapsed\n", what, p->t,
            p->duration, clock - w->started);
}

static int print_row(size_t index, const tb_accuracy_result *r, void *ctx)
{
    table *t = ctx;
    char setting[32];
    format_setting(setting, sizeof setting, r->method, r->setting);
    fprintf(stderr, "tumble accuracy: [%2zu/%zu] %s %s: done in %.2f s of CPU, %.0f s elapsed\n",
            index + 1, t->count, tb_method_name(r->method), setting, r->cpu_seconds,
            wall_seconds() - t->progress->started);
    t->progress->last = wall_seconds();
    if (r->status == TB_STATUS_OK) {
        cli_output_printf(t->out, "%-12s %-12s %10.3e  %12.3e  %11.3e  %8.2f  %11ld  %10.3e\n",
                          tb_method_name(r->method), setting, r->error, r->position_error,
                          r->angle_error, 1e3 * r->cpu_seconds, r->derivative_evals,
                          r->energy_error);
    } else if (r->status == TB_STATUS_UNSTABLE_STEP) {
        cli_output_printf(t->out, "%-12s %-12s refused: beyond the stability limit\n",
                          tb_method_name(r->method), setting);
    } else {
        cli_output_printf(t->out, "%-12s %-12s failed: %s%s%s\n", tb_method_name(r->method),
                          setting, tb_status_string(r->status), r->detail[0] != '\0' ? ": " : "",
                          r->detail);
    }
    return t->out->error != 0; /* stop when the table is being lost */
}

/* How the reference was made, how well it is known, and how far it is compared. */
static void print_reference(cli_output *out, const tb_accuracy_reference *r,
                            const tb_accuracy_def *def)
{
    char setting[32], check[32];
    format_setting(setting, sizeof setting, r->method, r->setting);
    format_setting(check, sizeof check, r->method, r->check_setting);
    if (r->cvode_detail[0] != '\0') {
        cli_output_printf(out, "\nthe cvode-bdf reference failed (%s),\nso the reference is rk4.",
                          r->cvode_detail);
    }
    cli_output_printf(out,
                      "\nerror: the largest displacement of a body's points at its radius of "
                      "gyration,\n|dx| + l angle, over the frames compared and all bodies, "
                      "against %s %s.\nreference uncertainty (vs %s): %.1e m (%.1e m, %.1e "
                      "rad); smaller errors are not resolved\n",
                      tb_method_name(r->method), setting, check, r->error, r->position_error,
                      r->angle_error);
    if (r->horizon_frames < r->frames) {
        cli_output_printf(out,
                          "horizon: %.6g s (%zu of %zu frames compared): past it the two "
                          "references differ by more than %g m,\nso small differences decide "
                          "the motion (chaos) and only statistics compare: energy (J) at the "
                          "end, reference's own %.1e J\n",
                          r->horizon, r->horizon_frames, r->frames, def->horizon_tolerance,
                          r->energy_error);
    } else {
        cli_output_printf(out, "horizon: none, the references agree to %g m over all %zu frames\n",
                          def->horizon_tolerance, r->frames);
    }
}

static void print_conclusion(cli_output *out, const tb_accuracy_result *results, size_t count,
                             const tb_accuracy_reference *reference, const tb_accuracy_def *def,
                             double target)
{
    print_reference(out, reference, def);
    const size_t best = tb_accuracy_cheapest(results, count, target);
    if (best < count) {
        char setting[32];
        format_setting(setting, sizeof setting, results[best].method, results[best].setting);
        cli_output_printf(out, "cheapest setting with error <= %g m: %s, %s (%.3g m in %.2f ms)",
                          target, tb_method_name(results[best].method), setting,
                          results[best].error, 1e3 * results[best].cpu_seconds);
        if (reference->horizon_frames < reference->frames) {
            cli_output_printf(out, ", judged up to the horizon, %.6g s", reference->horizon);
        }
        cli_output_printf(out, "\n");
    } else {
        cli_output_printf(out, "no setting in the sweep reaches an error of %g m\n", target);
    }
}

/* Runs the sweep into the opened table (and chart); the exit code. */
static int sweep(const cli_options *o, tb_scene *scene, const tb_run_def *run, cli_output *out,
                 cli_output *chart)
{
    tb_accuracy_setting settings[32];
    tb_accuracy_def def = tb_accuracy_def_default();
    tb_accuracy_scene_sweep(scene, settings, 32, &def.setting_count);
    def.settings = settings;
    const double target = o->has_target ? o->target_error : 1e-3;
    def.horizon_tolerance = 0.1 * target; /* the reference known to a tenth of the budget */
    progress shown = {wall_seconds(), wall_seconds()};
    def.progress = show_progress;
    def.progress_ctx = &shown;
    tb_accuracy_result results[32];
    tb_accuracy_reference reference;
    table t = {out, def.setting_count, &shown};
    tb_error error;
    fprintf(stderr,
            "tumble accuracy: %s: reference runs (cvode-bdf at rtol %g and %g; if they fail, rk4 "
            "at %g and %g of the default step)\n",
            o->scene, def.reference_rtol, def.check_rtol, def.reference_step_fraction,
            2 * def.reference_step_fraction);
    cli_output_printf(out, "method       setting       error (m)  position (m)  angle (rad)  "
                           "CPU (ms)  derivatives  energy (J)\n");
    const tb_status status =
        tb_scene_accuracy_sweep(scene, run, &def, print_row, &t, results, &reference, &error);
    if (status != TB_STATUS_OK && out->error == 0) {
        fprintf(stderr, "tumble: %s: %s\n", o->scene, error.message);
        return CLI_EXIT_SIMULATION;
    }
    if (status == TB_STATUS_OK) {
        print_conclusion(out, results, def.setting_count, &reference, &def, target);
    }
    if (chart->stream != NULL && status == TB_STATUS_OK) {
        chart_write(chart, results, def.setting_count, target);
    }
    return CLI_EXIT_OK;
}

/* Closes both outputs; the exit code after code (a failed write makes it 1). */
static int close_outputs(const cli_options *o, cli_output *out, cli_output *chart, int code)
{
    cli_output *outputs[2] = {out, chart};
    for (int k = 0; k < 2; ++k) {
        char message[512];
        if (outputs[k]->stream != NULL && !cli_output_close(outputs[k], message, sizeof message)) {
            fprintf(stderr, "tumble: %s: %s%s\n", o->scene, k == 1 ? "--chart: " : "", message);
            code = code == CLI_EXIT_OK ? CLI_EXIT_SIMULATION : code;
        }
    }
    return code;
}

int cli_accuracy_command(const cli_options *o)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    int code = cli_load(o, &scene, &run);
    if (code != CLI_EXIT_OK) {
        return code;
    }
    /* What the reference run will be asked to do, checked before minutes of work. */
    tb_run_def reference = run;
    tb_integrator_def_set_method(&reference.integrator, TB_METHOD_CVODE_BDF);
    reference.integrator.atol = 0.0;
    code = cli_dry_run(o, scene, &reference);
    cli_output out = {0}, chart = {0};
    char message[512];
    if (code == CLI_EXIT_OK && o->chart != NULL &&
        !cli_output_open(&chart, o->chart, o->scene, message, sizeof message)) {
        fprintf(stderr, "tumble: --chart %s\n", message);
        code = CLI_EXIT_INPUT;
    }
    if (code == CLI_EXIT_OK) {
        cli_output_open(&out, NULL, NULL, message, sizeof message);
        code = close_outputs(o, &out, &chart, sweep(o, scene, &run, &out, &chart));
    }
    tb_scene_destroy(scene);
    return code;
}

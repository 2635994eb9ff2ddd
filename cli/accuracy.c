/* tumble accuracy: the library's sweep (tb_scene_accuracy_sweep) on the user's scene, printed
 * as a table as each setting finishes, with the cheapest setting for the error budget and an
 * optional chart. */
#include "chart.h"
#include "commands.h"
#include "output.h"

#include <stdio.h>
#include <string.h>

typedef struct table {
    cli_output *out;
    size_t count;
} table;

static void format_setting(char *out, size_t size, tb_method method, double setting)
{
    if (tb_method_is_adaptive(method)) {
        snprintf(out, size, "rtol %.0e", setting);
    } else {
        snprintf(out, size, "dt 1/%.0f", setting);
    }
}

static int print_row(size_t index, const tb_accuracy_result *r, void *ctx)
{
    table *t = ctx;
    char setting[32];
    format_setting(setting, sizeof setting, r->method, r->setting);
    fprintf(stderr, "  [%2zu/%zu] %s %s\n", index + 1, t->count, tb_method_name(r->method),
            setting);
    if (r->status == TB_STATUS_OK) {
        cli_output_printf(t->out, "%-12s %-12s %10.3e  %12.3e  %11.3e  %8.2f  %11ld\n",
                          tb_method_name(r->method), setting, r->error, r->position_error,
                          r->angle_error, 1e3 * r->cpu_seconds, r->derivative_evals);
    } else if (r->status == TB_STATUS_UNSTABLE_STEP) {
        cli_output_printf(t->out, "%-12s %-12s refused: beyond the stability limit\n",
                          tb_method_name(r->method), setting);
    } else {
        cli_output_printf(t->out, "%-12s %-12s failed: %s\n", tb_method_name(r->method), setting,
                          tb_status_string(r->status));
    }
    return t->out->error != 0; /* stop when the table is being lost */
}

static void print_conclusion(cli_output *out, const tb_accuracy_result *results, size_t count,
                             const tb_accuracy_reference *reference, double target)
{
    cli_output_printf(out,
                      "\nerror: the largest displacement of a body's points at its radius of "
                      "gyration,\n|dx| + l angle, over all frames and bodies, against cvode-bdf "
                      "at rtol 1e-11.\nreference uncertainty (vs rtol 1e-10): %.1e m (%.1e m, "
                      "%.1e rad); smaller errors are not resolved\n",
                      reference->error, reference->position_error, reference->angle_error);
    const size_t best = tb_accuracy_cheapest(results, count, target);
    if (best < count) {
        char setting[32];
        format_setting(setting, sizeof setting, results[best].method, results[best].setting);
        cli_output_printf(out, "cheapest setting with error <= %g m: %s, %s (%.3g m in %.2f ms)\n",
                          target, tb_method_name(results[best].method), setting,
                          results[best].error, 1e3 * results[best].cpu_seconds);
    } else {
        cli_output_printf(out, "no setting in the sweep reaches an error of %g m\n", target);
    }
}

/* Runs the sweep into the opened table (and chart); the exit code. */
static int sweep(const cli_options *o, tb_scene *scene, const tb_run_def *run, cli_output *out,
                 cli_output *chart)
{
    size_t count;
    tb_accuracy_def def = tb_accuracy_def_default();
    def.settings = tb_accuracy_default_sweep(&count);
    tb_accuracy_result results[32];
    count = count < 32 ? count : 32;
    def.setting_count = count;
    tb_accuracy_reference reference;
    table t = {out, count};
    tb_error error;
    fprintf(stderr, "tumble accuracy: %s: reference runs (cvode-bdf at rtol %g and %g)\n", o->scene,
            def.reference_rtol, def.check_rtol);
    cli_output_printf(out, "method       setting       error (m)  position (m)  angle (rad)  "
                           "CPU (ms)  derivatives\n");
    const tb_status status =
        tb_scene_accuracy_sweep(scene, run, &def, print_row, &t, results, &reference, &error);
    if (status != TB_STATUS_OK && out->error == 0) {
        fprintf(stderr, "tumble: %s: %s\n", o->scene, error.message);
        return CLI_EXIT_SIMULATION;
    }
    const double target = o->has_target ? o->target_error : 1e-3;
    if (status == TB_STATUS_OK) {
        print_conclusion(out, results, count, &reference, target);
    }
    if (chart->stream != NULL && status == TB_STATUS_OK) {
        chart_write(chart, results, count, target);
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

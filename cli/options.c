#include "options.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A finite number > 0 (>= 0 when zero_ok), all of the text. */
static bool parse_number(const char *text, bool zero_ok, double *out)
{
    char *end;
    const double value = strtod(text, &end);
    if (end == text || *end != '\0' || !isfinite(value) || value < 0 || (!zero_ok && value == 0)) {
        return false;
    }
    *out = value;
    return true;
}

typedef struct number_option {
    const char *flag;
    bool zero_ok;
    size_t value_offset, seen_offset;
} number_option;

#define NUMBER(flag, zero_ok, field)                                                               \
    {                                                                                              \
        flag, zero_ok, offsetof(cli_options, field), offsetof(cli_options, has_##field)            \
    }

static const number_option number_options[] = {
    NUMBER("--dt", false, dt),
    NUMBER("--rtol", false, rtol),
    NUMBER("--atol", true, atol),
    NUMBER("--fps", false, fps),
    NUMBER("--duration", true, duration),
    {"--target-error", false, offsetof(cli_options, target_error),
     offsetof(cli_options, has_target)},
};

static bool parse_option(const char *flag, const char *value, cli_options *out, char *message,
                         size_t size)
{
    if (strcmp(flag, "--out") == 0) {
        out->out = value;
        return true;
    }
    if (strcmp(flag, "--chart") == 0) {
        out->chart = value;
        return true;
    }
    if (strcmp(flag, "--integrator") == 0) {
        out->method = value;
        return true;
    }
    for (size_t k = 0; k < sizeof number_options / sizeof number_options[0]; ++k) {
        const number_option *o = &number_options[k];
        if (strcmp(flag, o->flag) == 0) {
            if (!parse_number(value, o->zero_ok, (double *)((char *)out + o->value_offset))) {
                snprintf(message, size, "%s: expected a number %s, got \"%s\"", flag,
                         o->zero_ok ? ">= 0" : "> 0", value);
                return false;
            }
            *(bool *)((char *)out + o->seen_offset) = true;
            return true;
        }
    }
    snprintf(message, size, "unknown option \"%s\" (see tumble --help)", flag);
    return false;
}

bool cli_parse(int argc, char **argv, cli_options *out, char *message, size_t size)
{
    memset(out, 0, sizeof *out);
    if (argc < 2) {
        snprintf(message, size, "missing command: run, check or accuracy (see tumble --help)");
        return false;
    }
    out->command = argv[1];
    if (strcmp(out->command, "run") != 0 && strcmp(out->command, "check") != 0 &&
        strcmp(out->command, "accuracy") != 0) {
        snprintf(message, size,
                 "unknown command \"%s\": run, check or accuracy (see tumble --help)",
                 out->command);
        return false;
    }
    for (int i = 2; i < argc; ++i) {
        if (strncmp(argv[i], "--", 2) != 0) {
            if (out->scene != NULL) {
                snprintf(message, size, "one scene at a time: got \"%s\" and \"%s\"", out->scene,
                         argv[i]);
                return false;
            }
            out->scene = argv[i];
        } else if (i + 1 >= argc) {
            snprintf(message, size, "%s: needs a value", argv[i]);
            return false;
        } else if (!parse_option(argv[i], argv[i + 1], out, message, size)) {
            return false;
        } else {
            ++i;
        }
    }
    if (out->scene == NULL) {
        snprintf(message, size, "%s: missing the scene file", out->command);
        return false;
    }
    return true;
}

bool cli_apply(const cli_options *o, tb_run_def *run, char *message, size_t size)
{
    if (o->method != NULL && tb_method_from_name(o->method, &run->integrator.method) != 0) {
        snprintf(message, size,
                 "--integrator: expected euler, midpoint, rk4, cvode-adams or cvode-bdf, got "
                 "\"%s\"",
                 o->method);
        return false;
    }
    const bool adaptive = tb_method_is_adaptive(run->integrator.method);
    if ((o->has_dt && adaptive) || ((o->has_rtol || o->has_atol) && !adaptive)) {
        snprintf(message, size, "%s applies to %s methods, and the integrator is %s",
                 o->has_dt && adaptive ? "--dt" : "--rtol/--atol",
                 adaptive ? "fixed-step" : "adaptive (cvode-*)",
                 tb_method_name(run->integrator.method));
        return false;
    }
    if (o->has_rtol && !(o->rtol >= 1e-15 && o->rtol < 1)) {
        snprintf(message, size, "--rtol: expected a number in [1e-15, 1), got %g", o->rtol);
        return false;
    }
    run->integrator.dt = o->has_dt ? o->dt : run->integrator.dt;
    run->integrator.rtol = o->has_rtol ? o->rtol : run->integrator.rtol;
    run->integrator.atol = o->has_atol ? o->atol : run->integrator.atol;
    run->fps = o->has_fps ? o->fps : run->fps;
    run->duration = o->has_duration ? o->duration : run->duration;
    return true;
}

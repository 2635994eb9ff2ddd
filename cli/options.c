/* Command-line parsing: one table of options, each naming the commands it applies to, turned
 * into getopt_long's table; an option given to a command it does not apply to is refused. */
#define _POSIX_C_SOURCE 200809L
#include "options.h"

#include <ctype.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { ALL_COMMANDS = CLI_RUN | CLI_CHECK | CLI_ACCURACY, RUN_OR_CHECK = CLI_RUN | CLI_CHECK };

typedef enum option_kind { OPTION_FLAG, OPTION_TEXT, OPTION_NUMBER } option_kind;

typedef struct option_info {
    const char *name;
    int short_name; /* 0: long only */
    unsigned commands;
    option_kind kind;
    size_t value_offset; /* bool (flag), const char * (text) or double (number) */
    size_t seen_offset;  /* numbers: the bool saying the option was given */
    bool zero_ok;        /* numbers: 0 is allowed (otherwise > 0) */
    size_t text_offset;  /* numbers: the const char * keeping the text as typed (0: none) */
} option_info;

#define FLAG(name, short_name, commands, field)                                                    \
    {                                                                                              \
        name, short_name, commands, OPTION_FLAG, offsetof(cli_options, field), 0, false, 0         \
    }
#define TEXT(name, short_name, commands, field)                                                    \
    {                                                                                              \
        name, short_name, commands, OPTION_TEXT, offsetof(cli_options, field), 0, false, 0         \
    }
#define NUMBER(name, commands, field, seen, zero_ok)                                               \
    {                                                                                              \
        name, 0, commands, OPTION_NUMBER, offsetof(cli_options, field),                            \
            offsetof(cli_options, seen), zero_ok, 0                                                \
    }
/* A number whose range cli_apply checks, quoting the text (1e-320 is not 9.99989e-321) */
#define NUMBER_AS_TYPED(name, commands, field, seen, text)                                         \
    {                                                                                              \
        name, 0, commands, OPTION_NUMBER, offsetof(cli_options, field),                            \
            offsetof(cli_options, seen), false, offsetof(cli_options, text)                        \
    }

static const option_info option_table[] = {
    FLAG("help", 'h', ALL_COMMANDS, help),
    FLAG("project-joints", 0, RUN_OR_CHECK, project_joints),
    TEXT("out", 'o', CLI_RUN, out),
    TEXT("format", 0, CLI_RUN, format),
    TEXT("rotation", 0, CLI_RUN, rotation),
    TEXT("integrator", 0, RUN_OR_CHECK, method),
    TEXT("chart", 0, CLI_ACCURACY, chart),
    TEXT("events", 0, CLI_RUN, events),
    TEXT("joints", 0, CLI_RUN, joints),
    NUMBER("dt", RUN_OR_CHECK, dt, has_dt, false),
    NUMBER_AS_TYPED("rtol", RUN_OR_CHECK, rtol, has_rtol, rtol_text),
    NUMBER("atol", RUN_OR_CHECK, atol, has_atol, true),
    NUMBER_AS_TYPED("max-steps", RUN_OR_CHECK, max_steps, has_max_steps, max_steps_text),
    NUMBER("fps", ALL_COMMANDS, fps, has_fps, false),
    NUMBER("duration", ALL_COMMANDS, duration, has_duration, true),
    NUMBER("target-error", CLI_ACCURACY, target_error, has_target, false),
    NUMBER("hit-speed", CLI_RUN, hit_speed, has_hit_speed, true),
};
#define OPTION_COUNT (sizeof option_table / sizeof option_table[0])

static const struct {
    const char *name;
    cli_command command;
} commands[] = {{"run", CLI_RUN}, {"check", CLI_CHECK}, {"accuracy", CLI_ACCURACY}};

/* getopt_long's value for option k: its short letter, or 256 + k for long-only options. */
static int option_value(size_t k)
{
    return option_table[k].short_name != 0 ? option_table[k].short_name : 256 + (int)k;
}

static void build_getopt_table(struct option *out, char *short_options)
{
    char *s = short_options;
    *s++ = ':'; /* a missing value returns ':' instead of printing */
    for (size_t k = 0; k < OPTION_COUNT; ++k) {
        const option_info *o = &option_table[k];
        out[k] = (struct option){o->name, o->kind == OPTION_FLAG ? no_argument : required_argument,
                                 NULL, option_value(k)};
        if (o->short_name != 0) {
            *s++ = (char)o->short_name;
            if (o->kind != OPTION_FLAG) {
                *s++ = ':';
            }
        }
    }
    *s = '\0';
    out[OPTION_COUNT] = (struct option){NULL, 0, NULL, 0};
}

/* The names of the commands in mask, e.g. "run and check". */
static void command_names(unsigned mask, char *out, size_t size)
{
    out[0] = '\0';
    size_t found = 0, total = 0;
    for (size_t c = 0; c < 3; ++c) {
        total += (mask & commands[c].command) != 0;
    }
    for (size_t c = 0; c < 3; ++c) {
        if (mask & commands[c].command) {
            const size_t used = strlen(out);
            snprintf(out + used, size - used, "%s%s",
                     found == 0           ? ""
                     : found + 1 == total ? " and "
                                          : ", ",
                     commands[c].name);
            ++found;
        }
    }
}

/* The digits at *text, past them; how many. */
static size_t skip_digits(const char **text)
{
    size_t count = 0;
    while (isdigit((unsigned char)**text)) {
        ++*text;
        ++count;
    }
    return count;
}

/* Whether text is all one decimal number: [+-] digits [. digits] [e [+-] digits], with a digit
 * on one side of the point. strtod also takes leading spaces, hexadecimal (0x10 is 16), "inf",
 * "nan" and "infinity", none of which a careful user means as a step or a duration. */
static bool is_decimal(const char *text)
{
    text += *text == '+' || *text == '-';
    size_t digits = skip_digits(&text);
    if (*text == '.') {
        ++text;
        digits += skip_digits(&text);
    }
    if (digits == 0) {
        return false;
    }
    if (*text == 'e' || *text == 'E') {
        ++text;
        text += *text == '+' || *text == '-';
        if (skip_digits(&text) == 0) {
            return false;
        }
    }
    return *text == '\0';
}

/* Whether decimal text has a digit other than 0 before its exponent. */
static bool has_nonzero_digit(const char *text)
{
    for (; *text != '\0' && *text != 'e' && *text != 'E'; ++text) {
        if (*text >= '1' && *text <= '9') {
            return true;
        }
    }
    return false;
}

/* A finite decimal number > 0 (>= 0 when zero_ok, where 1e-400 is 0), all of the text;
 * *underflow when it must be > 0 and is a number other than 0 that rounds to 0 (1e-400). */
static bool parse_number(const char *text, bool zero_ok, double *out, bool *underflow)
{
    *underflow = false;
    if (!is_decimal(text)) {
        return false;
    }
    char *end;
    const double value = strtod(text, &end);
    *underflow = !zero_ok && value == 0.0 && has_nonzero_digit(text);
    if (*end != '\0' || !isfinite(value) || value < 0 || *underflow || (!zero_ok && value == 0)) {
        return false;
    }
    *out = value == 0.0 ? 0.0 : value; /* -0 is 0: "--duration -0" ran for "-0 s" */
    return true;
}

static bool store_option(const option_info *o, const char *value, const cli_options *options,
                         char *message, size_t size)
{
    char *field = (char *)options + o->value_offset;
    bool underflow = false;
    if (!(o->commands & options->command)) {
        char names[64];
        command_names(o->commands, names, sizeof names);
        snprintf(message, size, "--%s does not apply to %s (it is an option of %s)", o->name,
                 options->command_name, names);
        return false;
    }
    if (o->kind == OPTION_FLAG) {
        *(bool *)field = true;
    } else if (o->kind == OPTION_TEXT) {
        *(const char **)field = value;
    } else if (parse_number(value, o->zero_ok, (double *)field, &underflow)) {
        *(bool *)((char *)options + o->seen_offset) = true;
        if (o->text_offset != 0) {
            *(const char **)((char *)options + o->text_offset) = value;
        }
    } else {
        snprintf(message, size, "--%s: expected a finite decimal number %s, got \"%s\"%s", o->name,
                 o->zero_ok ? ">= 0" : "> 0", value,
                 underflow ? " (closer to 0 than a double can hold: it rounds to 0)" : "");
        return false;
    }
    return true;
}

static bool find_command(const char *name, cli_options *out)
{
    for (size_t c = 0; c < 3; ++c) {
        if (strcmp(name, commands[c].name) == 0) {
            out->command = commands[c].command;
            out->command_name = commands[c].name;
            return true;
        }
    }
    return false;
}

/* Options of argv[1..] (argv[0] is the command); the scene is left in argv[optind..]. */
static bool parse_options(int argc, char **argv, cli_options *out, char *message, size_t size)
{
    struct option long_options[OPTION_COUNT + 1];
    char short_options[2 * OPTION_COUNT + 2];
    build_getopt_table(long_options, short_options);
    optind = 1;
    opterr = 0;
    bool seen[OPTION_COUNT] = {false};
    int c;
    while ((c = getopt_long(argc, argv, short_options, long_options, NULL)) != -1) {
        if (c == '?' || c == ':') {
            const char *given = argv[optind - 1];
            snprintf(message, size,
                     c == ':' ? "%s: needs a value"
                              : "unknown option \"%s\" (see tumble %s --help)",
                     given, out->command_name);
            return false;
        }
        const size_t k = c >= 256 ? (size_t)(c - 256) : 0;
        const option_info *o = &option_table[k];
        for (size_t s = 0; c < 256 && s < OPTION_COUNT; ++s) {
            o = option_table[s].short_name == c ? &option_table[s] : o;
        }
        /* a second --out would silently replace the first: every option is given once */
        if (seen[o - option_table]) {
            snprintf(message, size, "--%s given twice (each option is given once)", o->name);
            return false;
        }
        seen[o - option_table] = true;
        if (!store_option(o, optarg, out, message, size)) {
            return false;
        }
    }
    return true;
}

bool cli_parse(int argc, char **argv, cli_options *out, char *message, size_t size)
{
    memset(out, 0, sizeof *out);
    if (argc < 2) {
        snprintf(message, size, "missing command: run, check or accuracy (see tumble --help)");
        return false;
    }
    if (!find_command(argv[1], out)) {
        snprintf(message, size,
                 "unknown command \"%s\": run, check or accuracy (see tumble --help)", argv[1]);
        return false;
    }
    if (!parse_options(argc - 1, argv + 1, out, message, size)) {
        return false;
    }
    char **rest = argv + 1 + optind;
    const int remaining = argc - 1 - optind;
    if (remaining > 1) {
        snprintf(message, size, "one scene at a time: got \"%s\" and \"%s\"", rest[0], rest[1]);
        return false;
    }
    out->scene = remaining == 1 ? rest[0] : NULL;
    if (out->scene == NULL && !out->help) {
        snprintf(message, size, "%s: missing the scene file", out->command_name);
        return false;
    }
    return true;
}

bool cli_apply(const cli_options *o, tb_run_def *run, char *message, size_t size)
{
    tb_error error;
    tb_method method = run->integrator.method;
    if (o->method != NULL && tb_method_parse(o->method, &method, &error) != 0) {
        snprintf(message, size, "--integrator: %s", error.message);
        return false;
    }
    /* the scene file's settings for another method (its dt, its rtol) do not carry over; a
     * fixed-step method replacing an adaptive one takes the scene's default step (dt 0) */
    const bool was_adaptive = tb_method_is_adaptive(run->integrator.method);
    tb_integrator_def_set_method(&run->integrator, method);
    if (was_adaptive && !tb_method_is_adaptive(method)) {
        run->integrator.dt = 0.0;
    }
    const bool adaptive = tb_method_is_adaptive(run->integrator.method);
    /* which settings the method reads is the library's rule */
    const struct {
        const char *setting;
        bool given;
    } settings[] = {{"dt", o->has_dt}, {"rtol", o->has_rtol}, {"atol", o->has_atol}};
    for (size_t k = 0; k < sizeof settings / sizeof settings[0]; ++k) {
        if (settings[k].given &&
            tb_method_check_setting(run->integrator.method, settings[k].setting, &error) != 0) {
            snprintf(message, size, "--%s %s", settings[k].setting, error.message);
            return false;
        }
    }
    if (o->has_max_steps && !(o->max_steps == floor(o->max_steps) && o->max_steps <= 1e18)) {
        snprintf(message, size, "--max-steps: expected a whole number from 1 to 1e18, got %s",
                 o->max_steps_text);
        return false;
    }
    if (o->has_rtol && !(o->rtol >= 1e-15 && o->rtol < 1)) {
        snprintf(message, size, "--rtol: expected a number in [1e-15, 1), got %s", o->rtol_text);
        return false;
    }
    /* every core for the chunks of a fixed step (the same bits as one thread) */
    run->integrator.threads = adaptive ? 1 : 0;
    run->integrator.dt = o->has_dt ? o->dt : run->integrator.dt;
    run->integrator.rtol = o->has_rtol ? o->rtol : run->integrator.rtol;
    run->integrator.atol = o->has_atol ? o->atol : run->integrator.atol;
    run->integrator.max_steps = o->has_max_steps ? (long)o->max_steps : run->integrator.max_steps;
    run->fps = o->has_fps ? o->fps : run->fps;
    run->duration = o->has_duration ? o->duration : run->duration;
    return true;
}

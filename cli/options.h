/* The tumble command's options. */
#ifndef TUMBLE_CLI_OPTIONS_H
#define TUMBLE_CLI_OPTIONS_H

#include "tumble/tumble.h"

#include <stdbool.h>

typedef struct cli_options {
    const char *command; /* "run", "check" or "accuracy" */
    const char *scene;
    const char *out;     /* NULL: standard output */
    const char *method;  /* NULL: the scene's */
    const char *chart;   /* accuracy: an SVG chart to write, or NULL */
    double target_error; /* accuracy: m */
    bool has_target;
    double dt, rtol, atol, fps, duration;
    bool has_dt, has_rtol, has_atol, has_fps, has_duration;
} cli_options;

/* Parses argv; on a mistake writes a message naming it into message and returns false. */
bool cli_parse(int argc, char **argv, cli_options *out, char *message, size_t size);

/* Applies the command-line overrides to the scene's run; false with a message if they do not
 * fit (a --dt for an adaptive method, ...). */
bool cli_apply(const cli_options *options, tb_run_def *run, char *message, size_t size);

#endif

/* The tumble command's options: parsed with getopt_long, each option allowed only for the
 * commands it applies to. */
#ifndef TUMBLE_CLI_OPTIONS_H
#define TUMBLE_CLI_OPTIONS_H

#include "tumble/tumble.h"

#include <stdbool.h>
#include <stddef.h>

/* Commands, as bits so that an option can name the commands it applies to. */
typedef enum cli_command {
    CLI_RUN = 1,
    CLI_CHECK = 2,
    CLI_ACCURACY = 4,
} cli_command;

typedef struct cli_options {
    cli_command command;
    const char *command_name; /* "run", "check" or "accuracy" */
    bool help;                /* --help after the command: print that command's help */
    bool project_joints;      /* run, check: project the start onto the joints first */
    const char *scene;
    const char *out;      /* NULL: standard output */
    const char *format;   /* run: csv, npz, glb or gltf; NULL: from --out's extension */
    const char *rotation; /* run, glTF: "cubic" (NULL) or "linear" rotation keys */
    const char *method;   /* NULL: the scene's */
    const char *chart;    /* accuracy: an SVG chart to write, or NULL */
    const char *events;   /* run: a .csv or .json file of contact events, or NULL */
    const char *joints;   /* run: a .csv file of the joints' reactions per frame, or NULL */
    double target_error;  /* accuracy: m */
    bool has_target;
    double dt, rtol, atol, fps, duration, max_steps;
    bool has_dt, has_rtol, has_atol, has_fps, has_duration, has_max_steps;
    const char *rtol_text, *max_steps_text; /* as typed, for the messages of their ranges */
    double hit_speed; /* run, --events: m/s, hits closing slower are left out (0: none) */
    bool has_hit_speed;
} cli_options;

/* Parses argv (argv[1] is the command); on a mistake writes a message naming it into message
 * and returns false. */
bool cli_parse(int argc, char **argv, cli_options *out, char *message, size_t size);

/* Applies the command-line overrides to the scene's run; false with a message if they do not
 * fit (a --dt for an adaptive method, ...). */
bool cli_apply(const cli_options *options, tb_run_def *run, char *message, size_t size);

/* The help text of one command (or of the whole program for 0). */
const char *cli_help(cli_command command);

#endif

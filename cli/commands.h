/* The tumble commands; each returns the process exit code. */
#ifndef TUMBLE_CLI_COMMANDS_H
#define TUMBLE_CLI_COMMANDS_H

#include "options.h"

enum {
    CLI_EXIT_OK = 0,
    CLI_EXIT_SIMULATION = 1, /* the simulation failed, or writing its output did */
    CLI_EXIT_INPUT = 2,      /* bad input: usage, scene file, settings, output path */
};

/* Loads the scene file and applies the command line's overrides to its run; on failure
 * prints why, leaves *scene NULL and returns CLI_EXIT_INPUT. */
int cli_load(const cli_options *options, tb_scene **scene, tb_run_def *run);

/* The dry run: tb_scene_run stopped at its first frame, so everything the run checks before
 * its first step is checked (by the library). On refusal prints why, returns CLI_EXIT_INPUT. */
int cli_dry_run(const cli_options *options, tb_scene *scene, const tb_run_def *run);

int cli_run_command(const cli_options *options);
int cli_check_command(const cli_options *options);
int cli_accuracy_command(const cli_options *options);

#endif

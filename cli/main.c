/* tumble: run, check or measure the accuracy of a scene file from the command line.
 * Exit codes: 0 success, 1 the simulation or writing its output failed, 2 bad input (usage,
 * scene file, settings, output path). */
#include "commands.h"
#include "output.h"

#include "tumble/tumble.h"

#include <stdio.h>
#include <string.h>

static int dispatch(int argc, char **argv)
{
    if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        fputs(cli_help(0), stdout);
        return CLI_EXIT_OK;
    }
    if (argc == 2 && strcmp(argv[1], "--version") == 0) {
        printf("tumble %s\n", TB_VERSION_STRING);
        return CLI_EXIT_OK;
    }
    cli_options options;
    char message[256];
    if (!cli_parse(argc, argv, &options, message, sizeof message)) {
        fprintf(stderr, "tumble: %s\n", message);
        return CLI_EXIT_INPUT;
    }
    if (options.help) {
        fputs(cli_help(options.command), stdout);
        return CLI_EXIT_OK;
    }
    switch (options.command) {
    case CLI_RUN:
        return cli_run_command(&options);
    case CLI_CHECK:
        return cli_check_command(&options);
    case CLI_ACCURACY:
        return cli_accuracy_command(&options);
    }
    return CLI_EXIT_INPUT;
}

int main(int argc, char **argv)
{
    cli_output_guard_stdout();
    const int code = dispatch(argc, argv);
    char message[256];
    /* A command that failed has said why already (a failed write to standard output too). */
    if (!cli_output_close_stdout(message, sizeof message) && code == CLI_EXIT_OK) {
        fprintf(stderr, "tumble: %s\n", message);
        return CLI_EXIT_SIMULATION;
    }
    return code;
}

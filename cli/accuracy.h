/* tumble accuracy: the user's own scene with every integrator across a sweep, against a tight
 * reference of the same scene. */
#ifndef TUMBLE_CLI_ACCURACY_H
#define TUMBLE_CLI_ACCURACY_H

#include "options.h"

/* Returns the process exit code (0, 1 simulation failure, 2 bad input). */
int accuracy_command(const cli_options *options);

#endif

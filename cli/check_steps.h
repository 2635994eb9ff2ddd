/* tumble check's report of the fixed steps: what each fixed-step method would take on the scene. */
#ifndef TUMBLE_CLI_CHECK_STEPS_H
#define TUMBLE_CLI_CHECK_STEPS_H

#include "tumble/tumble.h"

/* Prints, on standard error, each fixed-step method's default step on the scene at its current
 * state (tb_scene_default_step), the steps per simulated second it makes, and the stability
 * limit with what sets it (tb_scene_max_stable_step): the library's figures, none recomputed. */
void cli_check_steps(const tb_scene *scene);

#endif

/* tumble check's report of the scene's contact (what collides with what) on standard output. */
#ifndef TUMBLE_CLI_CHECK_CONTACT_H
#define TUMBLE_CLI_CHECK_CONTACT_H

#include "tumble/tumble.h"

/* Prints the report (nothing for a scene without contact or ground); the number of warnings. */
int cli_check_contact(const tb_scene *scene);

#endif

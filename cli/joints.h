/* The joints in the command line: tumble check's report of each joint and of how far the start
 * is off it, and tumble run --joints FILE, each joint's reaction on its first body per frame. */
#ifndef TUMBLE_CLI_JOINTS_H
#define TUMBLE_CLI_JOINTS_H

#include "output.h"

#include "tumble/joints.h"
#include "tumble/tumble.h"

#include <stdbool.h>
#include <stddef.h>

/* The largest position error (m, or rad as the sine of the angle) and velocity error (m/s,
 * rad/s) tumble check accepts at the start: a scene file's anchors and axes are given in the
 * world frame at the start, so the positions lie on the joints to rounding (about 1e-16 of the
 * scene's size); velocities that are not are the user's mistake (a pendulum's bob moving
 * along its rod), and 1e-6 is far above rounding and far below anything visible. */
#define CLI_JOINT_TOLERANCE 1e-6

/* Prints each joint (type, bodies, the start's errors) to standard output; refuses (message on
 * standard error, CLI_EXIT_INPUT) a start off a joint by more than CLI_JOINT_TOLERANCE. */
int cli_check_joints(const char *scene_path, const tb_scene *scene);

typedef struct cli_joints {
    cli_output output;
    tb_scene *scene;
    char detail[TB_DETAIL_SIZE]; /* the library's refusal of a read-out, "" if none */
} cli_joints;

/* Opens path (never the scene file) and writes the header t,joint,fx,fy,fz,tx,ty,tz,broken.
 * False with a message on refusal. */
bool cli_joints_open(cli_joints *j, const char *path, const char *scene_path, tb_scene *scene,
                     char *message, size_t size);

/* One row per joint at time t (the scene's states); false when a write or a read-out failed
 * (the run should stop). */
bool cli_joints_frame(cli_joints *j, double t);

/* Closes; ok false (the run failed) or a failed write or read-out: the file is removed. False
 * with a message if a write or read-out failed. */
bool cli_joints_close(cli_joints *j, bool ok, char *message, size_t size);

#endif

/* tumble check's joints and tumble run --joints FILE: every value asked of the library
 * (tb_scene_joint_def, tb_scene_joint_error, tb_scene_joint_reaction, tb_scene_joint_broken). */
#define _POSIX_C_SOURCE 200809L /* struct stat */
#include "joints.h"

#include "commands.h"

#include <math.h>
#include <stdio.h>

static const char *body_name(const tb_scene *scene, size_t id)
{
    return id == TB_WORLD ? "world" : tb_scene_body_name(scene, id);
}

/* ", soft 20 Hz (damping ratio 1), limits [0, 1.57] rad (restitution 0.2), motor to 6.28 rad/s
 * (at most 2 N m), breaks above 50 N": what the joint has beside its rows. */
static void describe_options(const tb_joint_def *def, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    if (def->soft_frequency > 0) {
        used += (size_t)snprintf(out + used, size - used, ", soft %g Hz (damping ratio %g)",
                                 def->soft_frequency, def->soft_damping_ratio);
    }
    const bool hinge = def->type == TB_JOINT_HINGE;
    if (used < size && def->has_limits) {
        used +=
            (size_t)snprintf(out + used, size - used, ", limits [%g, %g] %s (restitution %g)",
                             def->limits[0], def->limits[1], hinge ? "rad" : "m", def->restitution);
    }
    if (used < size && def->motor != TB_MOTOR_OFF) {
        const bool speed = def->motor == TB_MOTOR_VELOCITY;
        used += (size_t)snprintf(out + used, size - used, ", motor to %g %s (at most %g %s)",
                                 speed ? def->motor_speed : def->motor_target,
                                 speed ? (hinge ? "rad/s" : "m/s") : (hinge ? "rad" : "m"),
                                 def->motor_max_force, hinge ? "N m" : "N");
    }
    if (used < size && isfinite(def->break_force)) {
        used += (size_t)snprintf(out + used, size - used, ", breaks above %g N", def->break_force);
    }
    if (used < size && isfinite(def->break_torque)) {
        snprintf(out + used, size - used, ", breaks above %g N m", def->break_torque);
    }
}

int cli_check_joints(const char *scene_path, const tb_scene *scene)
{
    const size_t count = tb_scene_joint_count(scene);
    const double *y = tb_scene_states_const(scene);
    int code = CLI_EXIT_OK;
    if (count > 0) {
        printf("joints (%zu), each with how far the start is off it:\n", count);
    }
    for (size_t j = 0; j < count; ++j) {
        tb_joint_def def;
        double position = 0.0, velocity = 0.0;
        if (tb_scene_joint_def(scene, j, &def) != TB_STATUS_OK ||
            tb_scene_joint_error(scene, y, j, &position, &velocity) != TB_STATUS_OK) {
            fprintf(stderr, "tumble: %s: joints[%zu]: %s\n", scene_path, j, tb_scene_detail(scene));
            return CLI_EXIT_INPUT;
        }
        char options[TB_DETAIL_SIZE];
        describe_options(&def, options, sizeof options);
        printf("  joints[%zu]: %s, %s - %s%s, position error %.3g, velocity error %.3g\n", j,
               tb_joint_type_name(def.type), body_name(scene, def.body_a),
               body_name(scene, def.body_b), options, position, velocity);
        /* !(<=): a NaN error is off the joint too */
        if (!(position <= CLI_JOINT_TOLERANCE) || !(velocity <= CLI_JOINT_TOLERANCE)) {
            const bool moved = position <= CLI_JOINT_TOLERANCE;
            fprintf(stderr,
                    "tumble: %s: joints[%zu] (%s, %s - %s): the start is off the joint: its %s "
                    "error is %.3g %s, more than %g; give the bodies a start that keeps the "
                    "joint, or --project-joints to project it onto the joints\n",
                    scene_path, j, tb_joint_type_name(def.type), body_name(scene, def.body_a),
                    body_name(scene, def.body_b), moved ? "velocity" : "position",
                    moved ? velocity : position, moved ? "m/s (or rad/s)" : "m (or rad)",
                    CLI_JOINT_TOLERANCE);
            code = CLI_EXIT_INPUT;
        }
    }
    return code;
}

bool cli_joints_open(cli_joints *j, const char *path, const char *scene_path, tb_scene *scene,
                     char *message, size_t size)
{
    *j = (cli_joints){.scene = scene};
    if (!cli_output_open(&j->output, path, scene_path, message, size)) {
        return false;
    }
    cli_output_printf(&j->output, "t,joint,fx,fy,fz,tx,ty,tz,broken\n");
    return true;
}

bool cli_joints_frame(cli_joints *j, double t)
{
    const double *y = tb_scene_states_const(j->scene);
    for (size_t k = 0; k < tb_scene_joint_count(j->scene) && j->output.error == 0; ++k) {
        double force[3], torque[3];
        bool broken = false;
        if (tb_scene_joint_reaction(j->scene, y, k, force, torque) != TB_STATUS_OK ||
            tb_scene_joint_broken(j->scene, k, &broken) != TB_STATUS_OK) {
            snprintf(j->detail, sizeof j->detail, "joints[%zu] at t = %.17g: %s", k, t,
                     tb_scene_detail(j->scene));
            return false;
        }
        /* 17 significant digits: every double reads back as itself */
        cli_output_printf(&j->output, "%.17g,%zu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n", t, k,
                          force[0], force[1], force[2], torque[0], torque[1], torque[2],
                          broken ? 1 : 0);
    }
    return j->output.error == 0;
}

bool cli_joints_close(cli_joints *j, bool ok, char *message, size_t size)
{
    const bool written = cli_output_close(&j->output, message, size);
    if (written && j->detail[0] != '\0') {
        snprintf(message, size, "--joints %s: %s", j->output.name, j->detail);
    }
    const bool good = written && j->detail[0] == '\0';
    if (!ok || !good) {
        cli_output_remove_partial(j->output.name);
    }
    return good;
}

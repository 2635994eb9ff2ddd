/* Scene files: the "joints" section, a list of {"type": ..., "bodies": [...], ...} objects that
 * name bodies by their "name" and give the anchor and axis in the world frame at the start
 * (tb_scene_add_joint takes each body's own frames from them, at the poses just loaded). The
 * loader checks the JSON (kinds, lengths, which keys a type takes); the values' ranges are the
 * library's to check, and its message comes back prefixed with the joint's path. */
#include "io/scene_file_internal.h"

#include "tumble/joints.h"

#include <stdio.h>
#include <string.h>

/* "path.key" into where. */
static void at(char *where, size_t size, const char *path, const char *key)
{
    snprintf(where, size, "%s.%s", path, key);
}

/* "bodies": one name (the body joined to the world) or two. */
static tb_status load_joint_bodies(tb__loader *ld, const json_t *joint, const char *path,
                                   tb_joint_def *def)
{
    char where[160];
    at(where, sizeof where, path, "bodies");
    const json_t *names = json_object_get(joint, "bodies");
    if (names == NULL) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                             "missing (one body's name, joined to the world, or two)");
    }
    const size_t count = json_is_array(names) ? json_array_size(names) : 0;
    if (count != 1 && count != 2) {
        return tb__load_fail(
            ld, TB_STATUS_BAD_SCENE, where, "must be an array of one or two body names, got %s%s",
            tb__json_kind(names), json_is_array(names) ? " of another length" : "");
    }
    size_t ids[2] = {TB_WORLD, TB_WORLD};
    for (size_t k = 0; k < count; ++k) {
        const json_t *name = json_array_get(names, k);
        char item[176];
        tb__path_index(item, sizeof item, where, "", k);
        if (!json_is_string(name)) {
            return tb__load_fail(ld, TB_STATUS_BAD_SCENE, item, "must be a body's name, got %s",
                                 tb__json_kind(name));
        }
        if (tb_scene_find_body(ld->scene, json_string_value(name), &ids[k]) != TB_STATUS_OK) {
            return tb__load_fail(ld, TB_STATUS_BAD_SCENE, item, "no body is named \"%s\"",
                                 json_string_value(name));
        }
    }
    def->body_a = ids[0];
    def->body_b = ids[1];
    return TB_STATUS_OK;
}

/* "axis": 3 finite numbers, not all 0 (a direction; the library normalises it). */
static tb_status load_joint_axis(tb__loader *ld, const json_t *joint, const char *path,
                                 tb_joint_def *def)
{
    char where[160];
    at(where, sizeof where, path, "axis");
    const json_t *axis = json_object_get(joint, "axis");
    if (axis == NULL) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                             "missing (3 finite numbers, not all "
                             "0: the world direction at the "
                             "start)");
    }
    double value[3];
    if (tb__json_numbers(ld, axis, where, 3, value) != TB_STATUS_OK ||
        (value[0] == 0 && value[1] == 0 && value[2] == 0)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "must be 3 finite numbers, not all 0");
    }
    memcpy(def->axis, value, sizeof value);
    return TB_STATUS_OK;
}

/* "limits": [lower, upper] (rad for a hinge, m for a slider, from the start pose). */
static tb_status load_joint_limits(tb__loader *ld, const json_t *joint, const char *path,
                                   tb_joint_def *def)
{
    const json_t *limits = json_object_get(joint, "limits");
    if (limits == NULL) {
        return TB_STATUS_OK;
    }
    char where[160];
    at(where, sizeof where, path, "limits");
    tb_status status = tb__json_numbers(ld, limits, where, 2, def->limits);
    def->has_limits = status == TB_STATUS_OK;
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, joint, path, "restitution", false, &def->restitution);
    }
    return status;
}

/* "motor": {"speed" | "target", "max_torque" (hinge) | "max_force" (slider)}. */
static tb_status load_joint_motor(tb__loader *ld, const json_t *joint, const char *path,
                                  tb_joint_def *def)
{
    const json_t *motor = json_object_get(joint, "motor");
    if (motor == NULL) {
        return TB_STATUS_OK;
    }
    static const char *const hinge_keys[] = {"speed", "target", "max_torque", NULL};
    static const char *const slider_keys[] = {"speed", "target", "max_force", NULL};
    const bool hinge = def->type == TB_JOINT_HINGE;
    const char *const max_key = hinge ? "max_torque" : "max_force";
    char where[160];
    at(where, sizeof where, path, "motor");
    tb_status status = tb__json_object(ld, motor, where, hinge ? hinge_keys : slider_keys);
    const bool speed = json_object_get(motor, "speed") != NULL;
    if (status == TB_STATUS_OK && speed == (json_object_get(motor, "target") != NULL)) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                               "needs one of \"speed\" (%s) or \"target\" (%s)",
                               hinge ? "rad/s" : "m/s", hinge ? "rad" : "m");
    }
    if (status == TB_STATUS_OK) {
        def->motor = speed ? TB_MOTOR_VELOCITY : TB_MOTOR_POSITION;
        status = speed ? tb__json_number(ld, motor, where, "speed", true, &def->motor_speed)
                       : tb__json_number(ld, motor, where, "target", true, &def->motor_target);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, motor, where, max_key, true, &def->motor_max_force);
    }
    return status;
}

/* "soft": {"frequency" (Hz, required), "damping_ratio"}: a spring-damper on the rows. */
static tb_status load_joint_soft(tb__loader *ld, const json_t *joint, const char *path,
                                 tb_joint_def *def)
{
    const json_t *soft = json_object_get(joint, "soft");
    if (soft == NULL) {
        return TB_STATUS_OK;
    }
    static const char *const keys[] = {"frequency", "damping_ratio", NULL};
    char where[160];
    at(where, sizeof where, path, "soft");
    tb_status status = tb__json_object(ld, soft, where, keys);
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, soft, where, "frequency", true, &def->soft_frequency);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_positive_at(ld, where, "frequency", def->soft_frequency);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, soft, where, "damping_ratio", false, &def->soft_damping_ratio);
    }
    return status;
}

/* "break_force" (N) and "break_torque" (N m), each > 0 when given. */
static tb_status load_joint_breaking(tb__loader *ld, const json_t *joint, const char *path,
                                     tb_joint_def *def)
{
    tb_status status = tb__json_number(ld, joint, path, "break_force", false, &def->break_force);
    if (status == TB_STATUS_OK && json_object_get(joint, "break_force") != NULL) {
        status = tb__check_positive_at(ld, path, "break_force", def->break_force);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, joint, path, "break_torque", false, &def->break_torque);
    }
    if (status == TB_STATUS_OK && json_object_get(joint, "break_torque") != NULL) {
        status = tb__check_positive_at(ld, path, "break_torque", def->break_torque);
    }
    return status;
}

static tb_status load_joint_type(tb__loader *ld, const json_t *joint, const char *path,
                                 tb_joint_def *def)
{
    const char *type = NULL;
    tb_status status = json_is_object(joint) ? tb__json_string(ld, joint, path, "type", true, &type)
                                             : tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                                                             "must be an object with a \"type\"");
    if (status == TB_STATUS_OK && tb_joint_type_from_name(type, &def->type) != TB_STATUS_OK) {
        char where[160];
        at(where, sizeof where, path, "type");
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                               "must be one of ball, hinge, slider, fixed, got \"%s\"", type);
    }
    return status;
}

/* The keys each type takes: an axis, limits and a motor only where the joint has a free
 * direction (hinge, slider). */
static tb_status load_joint(tb__loader *ld, const json_t *joint, const char *path)
{
    static const char *const axis_keys[] = {"type",         "bodies",      "anchor", "axis",
                                            "limits",       "restitution", "motor",  "break_force",
                                            "break_torque", "soft",        NULL};
    static const char *const no_axis_keys[] = {"type",         "bodies", "anchor", "break_force",
                                               "break_torque", "soft",   NULL};
    tb_joint_def def = tb_joint_def_default();
    tb_status status = load_joint_type(ld, joint, path, &def);
    const bool has_axis = def.type == TB_JOINT_HINGE || def.type == TB_JOINT_SLIDER;
    if (status == TB_STATUS_OK) {
        status = tb__json_object(ld, joint, path, has_axis ? axis_keys : no_axis_keys);
    }
    if (status == TB_STATUS_OK) {
        status = load_joint_bodies(ld, joint, path, &def);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, joint, path, "anchor", 3, true, def.anchor);
    }
    if (status == TB_STATUS_OK && has_axis) {
        status = load_joint_axis(ld, joint, path, &def);
    }
    if (status == TB_STATUS_OK && has_axis) {
        status = load_joint_limits(ld, joint, path, &def);
    }
    if (status == TB_STATUS_OK && has_axis && json_object_get(joint, "limits") == NULL &&
        json_object_get(joint, "restitution") != NULL) {
        char where[160];
        at(where, sizeof where, path, "restitution");
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "applies at \"limits\", none given");
    }
    if (status == TB_STATUS_OK && has_axis) {
        status = load_joint_motor(ld, joint, path, &def);
    }
    if (status == TB_STATUS_OK) {
        status = load_joint_soft(ld, joint, path, &def);
    }
    if (status == TB_STATUS_OK) {
        status = load_joint_breaking(ld, joint, path, &def);
    }
    if (status == TB_STATUS_OK && tb_scene_add_joint(ld->scene, &def, NULL) != TB_STATUS_OK) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, path, "%s", tb_scene_detail(ld->scene));
    }
    return status;
}

tb_status tb__load_joints(tb__loader *ld, const json_t *joints)
{
    if (!json_is_array(joints)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, "joints", "must be an array of joints");
    }
    tb_status status = TB_STATUS_OK;
    for (size_t i = 0; i < json_array_size(joints) && status == TB_STATUS_OK; ++i) {
        char path[32];
        tb__path_index(path, sizeof path, "", "joints", i);
        status = load_joint(ld, json_array_get(joints, i), path);
    }
    return status;
}

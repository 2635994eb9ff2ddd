/* The joints' public calls: names, the def, adding a joint (every refusal changing nothing),
 * and the read-outs. */
#include "constraints/joints_internal.h"

#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TB__JOINT_COOKIE 0x10147d

static const char *const type_names[TB_JOINT_TYPE_COUNT] = {
    [TB_JOINT_BALL] = "ball",
    [TB_JOINT_HINGE] = "hinge",
    [TB_JOINT_SLIDER] = "slider",
    [TB_JOINT_FIXED] = "fixed",
};

const char *tb_joint_type_name(tb_joint_type type)
{
    return (unsigned)type < TB_JOINT_TYPE_COUNT ? type_names[type] : "unknown";
}

tb_status tb_joint_type_from_name(const char *name, tb_joint_type *out_type)
{
    if (name == NULL || out_type == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    for (int k = 0; k < TB_JOINT_TYPE_COUNT; ++k) {
        if (strcmp(name, type_names[k]) == 0) {
            *out_type = (tb_joint_type)k;
            return TB_STATUS_OK;
        }
    }
    return TB_STATUS_INVALID_ARGUMENT;
}

tb_joint_def tb_joint_def_default(void)
{
    tb_joint_def def;
    memset(&def, 0, sizeof def);
    def.type = TB_JOINT_BALL;
    def.body_a = TB_WORLD; /* required: refused until set */
    def.body_b = TB_WORLD;
    def.axis[2] = 1.0;
    def.motor = TB_MOTOR_OFF;
    def.break_force = INFINITY;
    def.break_torque = INFINITY;
    def.internal_cookie = TB__JOINT_COOKIE;
    return def;
}

/* The bodies: in range, different, one of them dynamic. */
static tb_status check_bodies(tb_scene *scene, const tb_joint_def *def)
{
    if (def->body_a == TB_WORLD) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_RANGE,
                              "body_a: required (a body id), got TB_WORLD");
    }
    tb_status status = tb__scene_check_id(scene, def->body_a, "body_a");
    if (status == TB_STATUS_OK && def->body_b != TB_WORLD) {
        status = tb__scene_check_id(scene, def->body_b, "body_b");
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (def->body_a == def->body_b) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "body_b: the same body as body_a (%zu)", def->body_a);
    }
    const bool fixed_b = def->body_b == TB_WORLD || tb__body_fixed(scene, def->body_b);
    if (tb__body_fixed(scene, def->body_a) && fixed_b) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "body_a, body_b: neither is dynamic (a joint must move a body)");
    }
    return TB_STATUS_OK;
}

/* The geometry: finite anchor and axis, a non-zero axis where the type has one. */
static tb_status check_geometry(tb_scene *scene, const tb_joint_def *def)
{
    if ((unsigned)def->type >= TB_JOINT_TYPE_COUNT) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT, "type: %d is not a joint type",
                              (int)def->type);
    }
    tb_status status = tb__validate_vector(scene->detail, def->anchor, "anchor");
    if (status == TB_STATUS_OK) {
        status = tb__validate_vector(scene->detail, def->axis, "axis");
    }
    const bool axial = def->type == TB_JOINT_HINGE || def->type == TB_JOINT_SLIDER;
    if (status == TB_STATUS_OK && axial && !(tb__v3_norm(def->axis) > 0.0)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "axis: zero (a %s needs a direction)", type_names[def->type]);
    }
    return status;
}

/* Limits, restitution and motor checked as values. */
static tb_status check_limits_and_motor(tb_scene *scene, const tb_joint_def *def)
{
    const bool axial = def->type == TB_JOINT_HINGE || def->type == TB_JOINT_SLIDER;
    tb_status status = TB_STATUS_OK;
    const double values[6] = {def->limits[0],   def->limits[1],    def->restitution,
                              def->motor_speed, def->motor_target, def->motor_max_force};
    static const char *const names[6] = {"limits[0]",   "limits[1]",    "restitution",
                                         "motor_speed", "motor_target", "motor_max_force"};
    for (int k = 0; k < 6 && status == TB_STATUS_OK; ++k) {
        status = tb__validate_finite(scene->detail, values[k], names[k]);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (def->has_limits && (!axial || def->limits[0] > def->limits[1])) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT, "limits: %s",
                              axial ? "lower > upper" : "only a hinge or slider");
    }
    const double pi = 3.14159265358979323846; /* a hinge's angle is read in (-pi, pi] */
    if (def->has_limits && def->type == TB_JOINT_HINGE &&
        (def->limits[0] < -pi || def->limits[1] > pi)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "limits: [%g, %g] (a hinge's within [-pi, pi])", def->limits[0],
                              def->limits[1]);
    }
    if (!(def->restitution >= 0.0 && def->restitution <= 1.0) ||
        (def->restitution != 0.0 && !def->has_limits)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "restitution: %g (within [0, 1], and only with limits)",
                              def->restitution);
    }
    if ((unsigned)def->motor > TB_MOTOR_POSITION ||
        (def->motor != TB_MOTOR_OFF && (!axial || !(def->motor_max_force > 0.0)))) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "motor: a known mode, on a hinge or slider, with motor_max_force "
                              "> 0");
    }
    return TB_STATUS_OK;
}

/* Breaking and softness checked as values. */
static tb_status check_breaking_and_softness(tb_scene *scene, const tb_joint_def *def)
{
    const double values[4] = {def->break_force, def->break_torque, def->soft_frequency,
                              def->soft_damping_ratio};
    static const char *const names[4] = {"break_force", "break_torque", "soft_frequency",
                                         "soft_damping_ratio"};
    for (int k = 0; k < 4; ++k) {
        if (isnan(values[k]) || (k >= 2 && !isfinite(values[k]))) {
            return tb__scene_fail(scene, TB_STATUS_NOT_FINITE, "%s: %g", names[k], values[k]);
        }
        if (!(values[k] >= 0.0) || (k < 2 && values[k] == 0.0)) {
            return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT, "%s: %g (must be %s)",
                                  names[k], values[k], k < 2 ? "> 0" : ">= 0");
        }
    }
    if (def->soft_damping_ratio != 0.0 && def->soft_frequency == 0.0) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "soft_damping_ratio: %g on a rigid joint (only with "
                              "soft_frequency > 0)",
                              def->soft_damping_ratio);
    }
    return TB_STATUS_OK;
}

static tb_status check_def(tb_scene *scene, const tb_joint_def *def)
{
    if (def == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "def is NULL");
    }
    if (def->internal_cookie != TB__JOINT_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_joint_def_default()");
    }
    tb_status status = check_geometry(scene, def);
    status = status != TB_STATUS_OK ? status : check_bodies(scene, def);
    status = status != TB_STATUS_OK ? status : check_limits_and_motor(scene, def);
    status = status != TB_STATUS_OK ? status : check_breaking_and_softness(scene, def);
    return status != TB_STATUS_OK ? status : tb__scene_check_idle(scene, "adding a joint");
}

/* The joint made from def at the scene's time and states. */
static tb__joint make_joint(const tb_scene *scene, const tb_joint_def *def)
{
    tb__joint joint = {.def = *def, .body = {def->body_a, def->body_b}};
    tb__motion m[2];
    for (int s = 0; s < 2; ++s) {
        tb__joint_motion(scene, scene->time, scene->states, joint.body[s], false, &m[s]);
    }
    tb__joint_frames(&joint, &m[0], &m[1]);
    tb__joint_soft_masses(&joint, scene);
    return joint;
}

/* The scene's joints with room for one more joint, made with its solver pattern; the scene
 * keeps its old ones on failure. */
static tb_status grow_joints(tb_scene *scene, const tb__joint *joint)
{
    tb__joints *js = scene->constraints;
    const size_t count = js == NULL ? 1 : js->count + 1;
    tb__joint *joints = tb__malloc_array(count, sizeof *joints);
    tb__joint_eval *evals = tb__malloc_array(count, sizeof *evals);
    tb__joints *grown = js != NULL ? js : calloc(1, sizeof *grown);
    tb__joint_solver solver = {0};
    tb_status status =
        joints != NULL && evals != NULL && grown != NULL ? TB_STATUS_OK : TB_STATUS_OUT_OF_MEMORY;
    if (status == TB_STATUS_OK) {
        if (count > 1) {
            memcpy(joints, js->joints, (count - 1) * sizeof *joints);
        }
        joints[count - 1] = *joint;
        memset(evals, 0, count * sizeof *evals);
        status = tb__joint_solver_build(scene, joints, count, &solver);
    }
    if (status != TB_STATUS_OK) {
        free(joints);
        free(evals);
        if (grown != js) {
            free(grown);
        }
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "room for %zu joints", count);
    }
    if (js != NULL) {
        free(js->joints);
        free(js->evals);
        tb__joint_solver_free(&js->solver);
    }
    const bool breakable = !isinf(joint->def.break_force) || !isinf(joint->def.break_torque);
    *grown =
        (tb__joints){.joints = joints,
                     .count = count,
                     .evals = evals,
                     .solver = solver,
                     .breakable = (js != NULL ? js->breakable : 0) + (breakable ? 1 : 0),
                     .limited = (js != NULL ? js->limited : 0) + (joint->def.has_limits ? 1 : 0),
                     .scratch = js != NULL ? js->scratch : NULL,
                     .scratch_size = js != NULL ? js->scratch_size : 0};
    scene->constraints = grown;
    scene->constraint_ops = &tb__joint_ops;
    return TB_STATUS_OK;
}

tb_status tb_scene_add_joint(tb_scene *scene, const tb_joint_def *def, size_t *out_id)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = check_def(scene, def);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const tb__joint joint = make_joint(scene, def);
    status = grow_joints(scene, &joint);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const size_t id = ((tb__joints *)scene->constraints)->count - 1;
    tb__scene_layout_changed(scene, "joint %zu added", id);
    tb__scene_wake_all(scene);
    if (out_id != NULL) {
        *out_id = id;
    }
    return TB_STATUS_OK;
}

size_t tb_scene_joint_count(const tb_scene *scene)
{
    return scene == NULL || scene->constraints == NULL
               ? 0
               : ((const tb__joints *)scene->constraints)->count;
}

/* The prologue of the read-outs: scene, joint index, the one required pointer. */
static tb_status begin_joint_call(const tb_scene *scene, size_t joint, const void *pointer,
                                  const char *what)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (pointer == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "%s is NULL", what);
    }
    return tb__validate_index(((tb_scene *)scene)->detail, joint, tb_scene_joint_count(scene),
                              "joint", "joints");
}

tb_status tb_scene_joint_def(const tb_scene *scene, size_t joint, tb_joint_def *out_def)
{
    const tb_status status = begin_joint_call(scene, joint, out_def, "out_def");
    if (status == TB_STATUS_OK) {
        *out_def = ((const tb__joints *)scene->constraints)->joints[joint].def;
    }
    return status;
}

tb_status tb_scene_joint_broken(const tb_scene *scene, size_t joint, bool *out_broken)
{
    const tb_status status = begin_joint_call(scene, joint, out_broken, "out_broken");
    if (status == TB_STATUS_OK) {
        *out_broken = ((const tb__joints *)scene->constraints)->joints[joint].broken;
    }
    return status;
}

tb_status tb_scene_joint_error(const tb_scene *scene, const double *y, size_t joint,
                               double *out_position, double *out_velocity)
{
    const tb_status status = begin_joint_call(scene, joint, y, "y");
    if (status != TB_STATUS_OK) {
        return status;
    }
    const tb__joints *js = scene->constraints;
    tb__joint held = js->joints[joint]; /* its rows and a stop that holds it; a motor is none */
    const bool stop = held.stop != TB__STOP_NONE && !held.broken;
    held.rows = held.base_rows + (stop || held.axial_first ? 1 : 0);
    const tb__joint *j = &held;
    tb__joint_eval eval;
    tb__motion m[2];
    const tb__body *constants[2];
    for (int s = 0; s < 2; ++s) {
        tb__joint_motion(scene, scene->time, y, j->body[s], false, &m[s]);
        constants[s] = tb__joint_body_constants(scene, j->body[s]);
    }
    tb__joint_rows(j, &m[0], &m[1], constants, &eval);
    double velocity[TB__JOINT_ROWS], worst_c = 0.0, worst_v = 0.0;
    tb__joint_row_velocities(j, &eval, &m[0], &m[1], velocity);
    for (int r = held.axial_first && !stop ? 1 : 0; r < j->rows; ++r) { /* a free axial row: no */
        worst_c = fmax(worst_c, fabs(eval.C[r]));
        worst_v = fmax(worst_v, fabs(velocity[r]));
    }
    if (out_position != NULL) {
        *out_position = worst_c;
    }
    if (out_velocity != NULL) {
        *out_velocity = worst_v;
    }
    return TB_STATUS_OK;
}

/* The derivative at y and the scene's time, for the read-outs of its solve's lambda. */
static tb_status derivative_at(tb_scene *scene, const double *y)
{
    const size_t n = tb_scene_state_size(scene);
    double *dydt = tb__malloc_array(n > 0 ? n : 1, sizeof(double));
    if (dydt == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "a derivative's scratch");
    }
    const int rc = tb_scene_derivative(scene->time, y, dydt, scene);
    free(dydt);
    return rc == 0 ? TB_STATUS_OK
                   : tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                    "the derivative failed at t = %g (%d)", scene->time, rc);
}

tb_status tb_scene_joint_reaction(tb_scene *scene, const double *y, size_t joint,
                                  double out_force[3], double out_torque[3])
{
    tb_status status = begin_joint_call(scene, joint, y, "y");
    if (status == TB_STATUS_OK && (out_force == NULL || out_torque == NULL)) {
        status = tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "%s is NULL",
                                out_force == NULL ? "out_force" : "out_torque");
    }
    status = status != TB_STATUS_OK ? status : tb__scene_check_idle(scene, "a joint reaction");
    status = status != TB_STATUS_OK ? status : derivative_at(scene, y);
    if (status == TB_STATUS_OK) {
        tb__joint_reaction(scene, scene->constraints, joint, out_force, out_torque);
    }
    return status;
}

/* The motor's and the stop's lambda on the axial row after a derivative (joint_motor_stops.c). */
static void axial_loads(const tb__joint *joint, const tb__joint_eval *eval, double *motor,
                        double *stop)
{
    const int state = joint->motor_state;
    const double lambda = eval->lambda[joint->axial_row];
    const bool motor_row =
        state == TB__MOTOR_ROW || state == TB__MOTOR_AWAY || state == TB__MOTOR_CAPPED;
    *motor = joint->broken             ? 0.0
             : motor_row               ? lambda
             : state == TB__MOTOR_LOAD ? joint->motor_load
                                       : 0.0;
    *stop = joint->broken || motor_row || joint->stop == TB__STOP_NONE ? 0.0 : lambda;
}

tb_status tb_scene_joint_axial(tb_scene *scene, const double *y, size_t joint,
                               double *out_coordinate, double *out_motor, double *out_stop)
{
    tb_status status = begin_joint_call(scene, joint, y, "y");
    const tb__joints *js = status == TB_STATUS_OK ? scene->constraints : NULL;
    const tb__joint *j = js != NULL ? &js->joints[joint] : NULL;
    if (j != NULL && j->def.type != TB_JOINT_HINGE && j->def.type != TB_JOINT_SLIDER) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "joint %zu: a %s (only a hinge or slider has an axial coordinate)",
                                joint, type_names[j->def.type]);
    }
    status = status != TB_STATUS_OK ? status : tb__scene_check_idle(scene, "a joint's axial loads");
    status = status != TB_STATUS_OK ? status : derivative_at(scene, y);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__motion m[2];
    for (int s = 0; s < 2; ++s) {
        tb__joint_motion(scene, scene->time, y, j->body[s], false, &m[s]);
    }
    double motor = 0.0, stop = 0.0;
    axial_loads(j, &js->evals[joint], &motor, &stop);
    if (out_coordinate != NULL) {
        *out_coordinate = tb__joint_axial_coordinate(j, &m[0], &m[1]);
    }
    if (out_motor != NULL) {
        *out_motor = motor;
    }
    if (out_stop != NULL) {
        *out_stop = stop;
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_set_joint_motor(tb_scene *scene, size_t joint, tb_joint_motor_mode mode,
                                   double value, double max_force)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status =
        tb__validate_index(scene->detail, joint, tb_scene_joint_count(scene), "joint", "joints");
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__joint *j = &((tb__joints *)scene->constraints)->joints[joint];
    tb_joint_def def = j->def;
    def.motor = mode;
    def.motor_speed = mode == TB_MOTOR_VELOCITY ? value : 0.0;
    def.motor_target = mode == TB_MOTOR_POSITION ? value : 0.0;
    def.motor_max_force = mode == TB_MOTOR_OFF ? 0.0 : max_force;
    status = mode == TB_MOTOR_OFF
                 ? TB_STATUS_OK
                 : tb__validate_finite(scene->detail, value,
                                       mode == TB_MOTOR_POSITION ? "motor_target" : "motor_speed");
    status = status != TB_STATUS_OK ? status : check_limits_and_motor(scene, &def);
    if (status == TB_STATUS_OK && def.motor != TB_MOTOR_OFF && def.soft_frequency > 0.0 &&
        !j->axial_first) { /* its rows were laid out without the axial row */
        status = tb__scene_fail(scene, TB_STATUS_UNSUPPORTED,
                                "motor: joint %zu is a soft joint made without limits or a motor "
                                "(its rows have no axial row): give it a motor when adding it",
                                joint);
    }
    status = status != TB_STATUS_OK ? status : tb__scene_check_idle(scene, "setting a motor");
    if (status != TB_STATUS_OK) {
        return status;
    }
    j->def = def;
    scene->effects_generation++; /* the right-hand side changed: CVODE restarts */
    tb__scene_wake_all(scene);
    return TB_STATUS_OK;
}

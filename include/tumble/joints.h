/* Joints: ball, hinge, slider and fixed joints between two bodies or a body and the world, held
 * exactly. Each joint gives rows of a constraint Jacobian; the derivative's last stage solves
 * for the joint forces that keep the rows' accelerations zero, and positions and velocities are
 * projected back onto the joints after each step and at each output (docs/joints.md names the
 * tolerance each method reaches and its tests). Units SI, vectors in the world frame, the world
 * z-up. */
#ifndef TUMBLE_JOINTS_H
#define TUMBLE_JOINTS_H

#include "tumble/export.h"

#include "tumble/effects.h" /* TB_WORLD */
#include "tumble/scene.h"
#include "tumble/status.h"

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What a joint holds (the rows it adds): */
typedef enum tb_joint_type {
    TB_JOINT_BALL = 0, /* the anchor points of both bodies coincide (3 rows); free rotation */
    TB_JOINT_HINGE,    /* ball, and the axis keeps its direction in both bodies (5 rows):
                          rotation about the axis only */
    TB_JOINT_SLIDER,   /* no relative rotation, and the anchors move along the axis only (5
                          rows): translation along the axis only */
    TB_JOINT_FIXED,    /* no relative motion at all (6 rows) */
    TB_JOINT_TYPE_COUNT
} tb_joint_type;

/* "ball", "hinge", "slider", "fixed"; "unknown" for any other value. */
TB_API const char *tb_joint_type_name(tb_joint_type type);
/* The type named name (exact lower-case spelling above); TB_STATUS_INVALID_ARGUMENT otherwise,
 * *out_type unchanged. */
TB_API tb_status tb_joint_type_from_name(const char *name, tb_joint_type *out_type);

/* What a joint's motor drives (hinge: the angle about the axis; slider: the travel along it). */
typedef enum tb_joint_motor_mode {
    TB_MOTOR_OFF = 0,  /* default */
    TB_MOTOR_VELOCITY, /* toward motor_speed (rad/s or m/s) */
    TB_MOTOR_POSITION, /* toward motor_target (rad or m, measured from the start pose) */
} tb_joint_motor_mode;

/* How a joint is made. Fill with tb_joint_def_default(), then set the fields. */
typedef struct tb_joint_def {
    tb_joint_type type; /* default TB_JOINT_BALL */
    size_t body_a;      /* required: a body id (the default, TB_WORLD, is refused) */
    size_t body_b;      /* a body id or TB_WORLD (default): the world; at least one of the two
                           bodies must be dynamic */
    double anchor[3];   /* m, world frame, at the bodies' current poses: the joint's point; each
                           body's anchor in its own frame is taken from it */
    double axis[3];     /* world frame, at the current poses, non-zero (normalised): a hinge's
                           axis, a slider's direction of travel; ignored by ball and fixed.
                           Default (0, 0, 1) */
    /* Limits (hinge and slider): the angle about the axis (rad) or the travel along it (m),
     * measured from the pose when the joint is made, kept within [lower, upper] by a stop with
     * the given restitution: at a stop the axial rate is reversed times restitution, and the
     * stop then holds the joint while it pushes (docs/joints.md, Limits). has_limits 0
     * (default): none. */
    int has_limits;
    double limits[2];   /* lower <= upper; a hinge's within [-pi, pi] */
    double restitution; /* [0, 1] at a stop; default 0 */
    /* A motor (hinge and slider), at most motor_max_force (N for a slider, N m for a hinge):
     * it asks the axial acceleration 20/s (speed - rate) (velocity) or (20/s)^2 (target -
     * coordinate) - 2 (20/s) rate (position), capped (docs/joints.md, Motors). */
    tb_joint_motor_mode motor;
    double motor_speed;     /* rad/s or m/s (TB_MOTOR_VELOCITY) */
    double motor_target;    /* rad or m (TB_MOTOR_POSITION) */
    double motor_max_force; /* > 0 with a motor */
    /* Breaking: the joint breaks (its rows are dropped for the rest of the run, and are back for
     * an integrator made or reset before the break; tb_scene_joint_broken says so) when the
     * magnitude of its reaction force (N) or torque (N m, about the anchor) on body_a exceeds these
     * (> 0), at the first step boundary where it does (fixed-step methods: every step; CVODE: its
     * outputs). INFINITY (default): never. */
    double break_force, break_torque;
    /* A soft joint: a spring-damper on the same rows instead of an exact constraint, for
     * animators' wobbly rigs: each row r pulls with -m_g (w^2 C_r + 2 zeta w dC_r/dt), w = 2 pi
     * frequency, m_g the mean effective mass (1 / (J_r M^-1 J_r^T)) of its group of rows (the
     * anchors' gap, a hinge's tilt, the relative rotation, a slider's sideways gap) when the
     * joint is made, so a row alone rings at frequency (Hz, > 0) with damping_ratio (>= 0).
     * Constant and isotropic, the spring is conservative: its energy is in
     * tb_scene_potential_energy, and an undamped one keeps the scene's energy and momenta.
     * Not projected (it is a spring); the stability guard counts its rate, 2 pi frequency at
     * damping_ratio. Limits and a motor (hinge, slider) act as on a rigid joint, through an
     * exact axial row beside the springs. frequency 0 (default): rigid. */
    double soft_frequency, soft_damping_ratio;
    int internal_cookie; /* set by tb_joint_def_default */
} tb_joint_def;

TB_API tb_joint_def tb_joint_def_default(void);

/* Adds a joint; its id (0, 1, ... in the order added) in *out_id (may be NULL). Refuses,
 * changing nothing, with a detail naming the field: a NULL scene or def
 * (TB_STATUS_NULL_POINTER), a def not from tb_joint_def_default, an unknown type, a body id out
 * of range or body_a TB_WORLD (TB_STATUS_OUT_OF_RANGE), body_a == body_b, two bodies neither
 * dynamic, a hinge's or slider's zero axis, limits reversed, a restitution outside [0, 1] or
 * without limits, a motor without a positive max force or on a ball or fixed joint, a break
 * force or torque <= 0, a negative soft frequency or damping ratio, a damping ratio on a rigid
 * joint (TB_STATUS_INVALID_ARGUMENT), a non-finite value (TB_STATUS_NOT_FINITE);
 * TB_STATUS_BUSY while an integrator steps the scene. A motor and limits on one joint work
 * together, on rigid and soft joints: at a stop the stop wins, the motor pushing into it at its
 * cap (docs/joints.md). An integrator made before the joint refuses to advance
 * (TB_STATUS_LAYOUT_CHANGED). */
TB_API tb_status tb_scene_add_joint(tb_scene *scene, const tb_joint_def *def, size_t *out_id);

TB_API size_t tb_scene_joint_count(const tb_scene *scene);

/* The definition joint was made from (body ids, type, anchor and axis as given). */
TB_API tb_status tb_scene_joint_def(const tb_scene *scene, size_t joint, tb_joint_def *out_def);

/* The force (N, world) and torque (N m, world, about the anchor on body_a) that the joint puts
 * on body_a at state y and the scene's time (body_b gets their opposite). Evaluates the
 * derivative once. A broken joint's reaction is 0. */
TB_API tb_status tb_scene_joint_reaction(tb_scene *scene, const double *y, size_t joint,
                                         double out_force[3], double out_torque[3]);

/* How far state y is off the joint: the largest position error of its rows (m for anchor
 * rows; rad for angle rows, as the sine of the angle) and the largest velocity error (m/s,
 * rad/s), at the scene's time. Either out pointer may be NULL. */
TB_API tb_status tb_scene_joint_error(const tb_scene *scene, const double *y, size_t joint,
                                      double *out_position, double *out_velocity);

/* Projects the scene's states (tb_scene_states) onto its joints at the scene's time, as after
 * every step: positions first, by the mass-weighted least change (Newton's method on the rows),
 * then velocities, so that each row's rate is 0; for a start off the joints (a scene file's
 * rounded poses). Soft and broken joints are not projected, sleeping bodies not moved.
 * tolerance (m or rad, and m/s or rad/s) is the largest joint error accepted after it; 0 asks
 * for TB_JOINT_PROJECTION_TOLERANCE. *out_error (may be NULL) gets the largest error left
 * (position or velocity). Refuses, changing nothing: a NULL scene (TB_STATUS_NULL_POINTER), a
 * negative tolerance (TB_STATUS_INVALID_ARGUMENT), a non-finite one (TB_STATUS_NOT_FINITE), a call
 * while an integrator steps the scene (TB_STATUS_BUSY), a start the projection does not bring
 * within the tolerance (TB_STATUS_SOLVER_FAILED, the detail naming the joint and its error). A
 * scene without joints is left as it is. Call it before making the integrator (CVODE keeps its own
 * copy of the states). */
#define TB_JOINT_PROJECTION_TOLERANCE 1e-12
TB_API tb_status tb_scene_project_joints(tb_scene *scene, double tolerance, double *out_error);

/* A hinge's or slider's axial read-outs at state y and the scene's time (evaluates the
 * derivative once): its coordinate (the angle of body_a about the axis relative to body_b, rad,
 * or the travel along it, m, from the pose when the joint was made), and the motor's and the
 * stop's lambda on the axial row (N m for a hinge, N for a slider; positive drives the
 * coordinate up on body_a), each 0 when not acting. A motor driving the joint into a stop that
 * holds it pushes at its cap (docs/joints.md, Motors at a stop). Any out pointer may be NULL.
 * Refuses a joint of another type (TB_STATUS_INVALID_ARGUMENT), a NULL y, a joint out of range,
 * a call while an integrator steps the scene (TB_STATUS_BUSY). */
TB_API tb_status tb_scene_joint_axial(tb_scene *scene, const double *y, size_t joint,
                                      double *out_coordinate, double *out_motor, double *out_stop);

/* Sets a hinge's or slider's motor between steps (a door's motor reversed, a wheel's speed
 * changed): mode, value (motor_speed for TB_MOTOR_VELOCITY, motor_target for
 * TB_MOTOR_POSITION, ignored for TB_MOTOR_OFF) and max_force (> 0, ignored for TB_MOTOR_OFF),
 * checked as tb_scene_add_joint checks them (the detail naming the field), nothing changed on a
 * refusal; a motor on a soft joint made without limits or a motor is refused
 * (TB_STATUS_UNSUPPORTED: its rows have no axial row). The right-hand side changes from the scene's
 * time on (CVODE restarts); the integrator keeps stepping. TB_STATUS_BUSY while an integrator steps
 * the scene. */
TB_API tb_status tb_scene_set_joint_motor(tb_scene *scene, size_t joint, tb_joint_motor_mode mode,
                                          double value, double max_force);

/* Whether the joint has broken (in the run so far). */
TB_API tb_status tb_scene_joint_broken(const tb_scene *scene, size_t joint, bool *out_broken);

#ifdef __cplusplus
}
#endif

#endif

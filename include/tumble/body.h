/* Rigid bodies: the state integrated in time and the definition a body is made from. */
#ifndef TUMBLE_BODY_H
#define TUMBLE_BODY_H

#include "tumble/export.h"

#include "tumble/mass.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The state of one body, 13 doubles with no padding, so an array of N states is one flat
 * array of 13 N doubles (the array integrators see):
 *   x  centre-of-mass position, world frame, m
 *   q  unit quaternion (w, x, y, z) rotating body (principal) frame vectors into the world
 *   P  linear momentum, world frame, kg m/s
 *   L  angular momentum about the centre of mass, world frame, kg m^2/s
 * Keeping momenta (not velocities) in the state means a torque-free body keeps L exactly
 * under every Runge-Kutta method. */
typedef struct tb_body_state {
    double x[3];
    double q[4];
    double P[3];
    double L[3];
} tb_body_state;

#define TB_STATE_SIZE 13 /* doubles per body */

/* Where each part starts in a body's 13 doubles (offsetof the fields above), so code names
 * the part instead of counting: s[TB_STATE_P + 2] is P_z. */
#define TB_STATE_X 0  /* x[3], m */
#define TB_STATE_Q 3  /* q[4], (w, x, y, z) */
#define TB_STATE_P 7  /* P[3], kg m/s */
#define TB_STATE_L 10 /* L[3], kg m^2/s */

/* How a body moves. A dynamic body has a state (13 doubles in the scene's state array) and
 * moves under its loads. A static body has no state: it stays at its pose. A keyframed body
 * has no state either: its motion is a function of time (tb_scene_set_body_motion_fn). Both
 * need no mass: for them the mass is ignored, their principal frame is their shape frame with
 * its centre at the shape origin, and every law sees them infinitely heavy (inverse mass and
 * inverse inertia 0); they push dynamic bodies through contact and are pushed by nothing. */
typedef enum tb_body_motion {
    TB_MOTION_DYNAMIC = 0, /* default */
    TB_MOTION_STATIC,
    TB_MOTION_KEYFRAMED,
} tb_body_motion;

/* How a body is made. Fill with tb_body_def_default(), then set the fields.
 * The body frame is the principal frame of mass; the pose below is the pose of the shape
 * frame (the frame mass.center and mass.rotation refer to), so a user never deals with the
 * principal frame unless they want to. */
/* Longest body name, including the terminating NUL. */
#define TB_NAME_SIZE 64

typedef struct tb_body_def {
    const char *name;           /* optional, unique in its scene, < TB_NAME_SIZE characters;
                                   copied; NULL (default) names the body "body<id>" */
    tb_mass_properties mass;    /* required: the default has mass 0, which is rejected */
    double position[3];         /* world position of the centre of mass, m; default 0 */
    double orientation[4];      /* shape frame -> world unit quaternion (w,x,y,z); identity */
    double velocity[3];         /* centre-of-mass velocity, world frame, m/s; default 0 */
    double angular_velocity[3]; /* world frame, rad/s; default 0 */
    /* TB_MOTION_DYNAMIC (default), TB_MOTION_STATIC (position: the shape origin; mass ignored;
     * velocities must be 0) or TB_MOTION_KEYFRAMED (the pose until a motion is given) */
    tb_body_motion motion;
    int internal_cookie; /* set by tb_body_def_default */
} tb_body_def;

TB_API tb_body_def tb_body_def_default(void);

typedef struct tb_scene tb_scene;

/* A keyframed body's motion at time t, world frame: its shape-frame origin's position (m),
 * the shape -> world unit quaternion (w, x, y, z), their derivatives. */
typedef struct tb_body_motion_sample {
    double position[3];             /* m */
    double orientation[4];          /* unit, (w, x, y, z) */
    double velocity[3];             /* m/s */
    double angular_velocity[3];     /* rad/s, world */
    double acceleration[3];         /* m/s^2 */
    double angular_acceleration[3]; /* rad/s^2, world */
} tb_body_motion_sample;
/* Returns 0, or nonzero to fail the derivative (the step is then refused); a sample with a NaN,
 * an infinity or a zero quaternion fails it too. Must be pure in t. */
typedef int (*tb_body_motion_fn)(double t, void *ctx, tb_body_motion_sample *out);
/* Drives keyframed body id by fn (ctx passed through, owned by the caller; fn NULL: the body
 * holds the pose it was added with). Every read of the body at time t (the derivative's t, or
 * the scene's time for read-outs, tb_scene_time) asks fn, so a contact sees its true surface
 * velocity. Refused (TB_STATUS_INVALID_ARGUMENT, nothing changed) for a body that is not
 * keyframed, and while the scene is being stepped (TB_STATUS_BUSY). Set after an integrator
 * exists, the next advance, step or reset checks the state as a start (a body moved inside
 * another is refused, as a shape grown into one is). */
TB_API tb_status tb_scene_set_body_motion_fn(tb_scene *scene, size_t id, tb_body_motion_fn fn,
                                             void *ctx);

#ifdef __cplusplus
}
#endif

#endif

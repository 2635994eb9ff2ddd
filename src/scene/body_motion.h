/* Private: the body-motion accessor (body_motion.c). Every read of a body's state asks these,
 * by id; nothing else indexes y by body. Included at the end of scene_internal.h. */
#ifndef TUMBLE_BODY_MOTION_H
#define TUMBLE_BODY_MOTION_H

#include <math.h>

/* What the accessor reads for a body with no slot: its kind, and a static body's pose. */
typedef struct tb__body_kind {
    tb_body_motion motion;
    double x[3]; /* the centre (the shape origin), world, m: the pose a body without fn holds */
    double q[4]; /* principal (= shape) -> world, unit */
    /* a keyframed body's motion source (tb__scene_set_body_motion_source) */
    tb_body_motion_fn fn;
    void *ctx;
    void (*release)(void *ctx); /* frees ctx when the source is replaced or the scene destroyed */
    /* owned, ascending: where the motion is only C1 (key times); 3 break_count doubles, the
     * largest speed and spin of the curve after each following (body_motion.c) */
    double *break_times;
    size_t break_count;
} tb__body_kind;

/* Drives keyframed body id by fn with ctx, owning ctx when release is not NULL (released when
 * replaced and at destroy, and at once on failure), and records break_times (copied, sorted;
 * times where the motion is only C1). TB_STATUS_INVALID_ARGUMENT for a body that is not
 * keyframed or non-finite times; TB_STATUS_BUSY while stepped. */
tb_status tb__scene_set_body_motion_source(tb_scene *scene, size_t id, tb_body_motion_fn fn,
                                           void *ctx, const double *break_times, size_t break_count,
                                           void (*release)(void *ctx));
/* Releases every body's motion source (tb_scene_destroy). */
void tb__scene_release_motion_sources(tb_scene *scene);
/* The earliest break time of the keyframed bodies after t (INFINITY: none): the scene's
 * tb_ode_system.events.next_break (ctx the scene). */
double tb__scene_next_break(double t, void *ctx);

/* Whether a body without a state stands elsewhere at t than at the scene's time (keys). */
bool tb__scene_fixed_poses_move(const tb_scene *scene, double t);
/* Whether a keyframed body's keys jump at t (a break within 8 ulps of t where the pose is not
 * the limit from the left: a step key), so that the state at t is checked as a start
 * (scene_ode.c). */
bool tb__scene_fixed_poses_jump(const tb_scene *scene, double t);

/* A bound of the speed of body id's points from t on (|v| + |omega| reach, m/s, reach a radius
 * about its centre that holds its shape): its speed at t, and for a keyframed body with break
 * times (keys) the largest speed plus the largest spin times reach over the pieces of its curve
 * from the one t lies in to its last key, each piece bounded by the velocity taken as quadratic
 * in time through its ends and middle (exact for linear and cubic positions: the Bezier hull of
 * the velocity; an estimate for the rotation), found once when the keys are set: O(log keys). */
double tb__body_fastest_from(const tb_scene *scene, double t, const double *y, size_t id,
                             double reach);

/* Body id's slot (the index of its 13 doubles in y), or TB_NO_SLOT. */
static inline size_t tb__body_slot(const tb_scene *scene, size_t id)
{
    return scene->slots[id];
}

/* Body id's 13 states in y (or its derivative in dydt), NULL for a body with no state. For
 * writers of a dynamic body's state and readers of its momenta. */
static inline const double *tb__body_state(const tb_scene *scene, const double *y, size_t id)
{
    const size_t slot = scene->slots[id];
    return slot == TB_NO_SLOT ? NULL : y + TB_STATE_SIZE * slot;
}
static inline double *tb__body_state_mut(const tb_scene *scene, double *y, size_t id)
{
    const size_t slot = scene->slots[id];
    return slot == TB_NO_SLOT ? NULL : y + TB_STATE_SIZE * slot;
}

/* Whether body id has no state (static or keyframed): it cannot be moved by the laws. */
static inline bool tb__body_fixed(const tb_scene *scene, size_t id)
{
    return scene->slots[id] == TB_NO_SLOT;
}

/* Whether body id is static (it never moves, at any t). */
static inline bool tb__body_static(const tb_scene *scene, size_t id)
{
    return scene->kinds[id].motion == TB_MOTION_STATIC;
}

/* Whether both bodies of a pair rest: each asleep or static (the narrow phase skips it, and
 * the friction between them stays frozen). */
static inline bool tb__pair_resting(const tb_scene *scene, size_t a, size_t b)
{
    return (tb__body_asleep(scene, a) || tb__body_static(scene, a)) &&
           (tb__body_asleep(scene, b) || tb__body_static(scene, b));
}

/* What tb_body_def_default writes into internal_cookie (scene.c), checked here. */
#define TB__BODY_COOKIE 0xb0d1e5

/* A body def checked (cookie, name, mass for a dynamic body, pose, velocities; body_def.c),
 * and the constants the derivative divides by from its mass properties (a mass or moment
 * whose inverse overflows refused, naming the field). */
tb_status tb__scene_validate_body_def(tb_scene *scene, const tb_body_def *def);
tb_status tb__scene_body_constants(tb_scene *scene, const tb_mass_properties *props, tb__body *out);

/* A non-dynamic body's def checked (a known kind; a static body without velocities) and its
 * kind made (the pose of def, principal frame = shape frame); the detail names what is wrong. */
tb_status tb__body_kind_from_def(tb_scene *scene, const tb_body_def *def, tb__body_kind *out);
/* The mass properties of a body that cannot move: infinite mass and moments, centre at the
 * shape origin, principal frame the shape frame. */
tb_mass_properties tb__fixed_mass_properties(void);
/* TB_STATUS_INVALID_ARGUMENT, with a detail naming body id and its kind, when it is not dynamic
 * (`what` names the refused change: "set_state", "a force"). */
tb_status tb__scene_check_dynamic(const tb_scene *scene, size_t id, const char *what);

/* The reduced mass m_a m_b / (m_a + m_b) of two bodies' masses (kg), m_a where m_b is infinite
 * (a body that cannot move), and the reverse. */
static inline double tb__reduced_mass(double a, double b)
{
    return isinf(b) ? a : isinf(a) ? b : a * b / (a + b);
}

/* Body id's constants: a dynamic body's, or for a body that cannot move an infinitely heavy
 * one (inverse mass and inverse inertia 0, mass INFINITY). */
const tb__body *tb__body_constants(const tb_scene *scene, size_t id);

/* Body id's motion at time t and state y: centre of mass, orientation, velocities. For a
 * dynamic body read from y (bit for bit tb__body_motion's); a static body's pose at rest; a
 * keyframed body's from its source at t. Returns 0, or the source's nonzero failure (out then
 * holds the body's added pose at rest). */
int tb__body_motion_at(const tb_scene *scene, double t, const double *y, size_t id,
                       tb__motion *out);
/* The acceleration (m/s^2) and angular acceleration (rad/s^2, world) of a body without a state
 * at t: a keyframed body's from its source, 0 for a static one (a dynamic body's come from the
 * derivative: 0 here too). */
void tb__fixed_body_acceleration_at(const tb_scene *scene, double t, size_t id, double out_a[3],
                                    double out_alpha[3]);
/* Its pose alone (centre of mass, unit principal -> world quaternion), as tb__body_motion_at
 * gives it, for the hot paths that need no velocity (shape poses of the broad phase). */
void tb__body_pose_at(const tb_scene *scene, double t, const double *y, size_t id, double out_x[3],
                      double out_q[4]);

/* dP += f and dL += arm x f for body id, by its slot (tb__add_load); nothing for a body with
 * no state (whose reaction is a read-out, not a state). */
static inline void tb__add_body_load(const tb_scene *scene, double *dydt, size_t id,
                                     const double arm[3], const double f[3])
{
    const size_t slot = tb__body_slot(scene, id);
    if (slot != TB_NO_SLOT) {
        tb__add_load(dydt, slot, arm, f);
    } else if (scene->reactions != NULL) { /* a reaction read-out is running */
        double torque[3];
        tb__v3_cross(torque, arm, f);
        tb__v3_axpy(scene->reactions + 6 * id, 1.0, f);
        tb__v3_axpy(scene->reactions + 6 * id + 3, 1.0, torque);
    }
}

#endif

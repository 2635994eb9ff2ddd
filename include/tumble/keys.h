/* Keyframe curves: a pose (position and orientation) that follows keys in time, with its
 * velocity and acceleration from the curve's own derivatives, never from differences of poses.
 * A keyframed body's motion callback (tb_body_motion_fn) is tb_keyframes_sample with the
 * keyframes as its context. The formulas are in docs/scene-format.md ("keys"). */
#ifndef TUMBLE_KEYS_H
#define TUMBLE_KEYS_H

#include "tumble/export.h"

#include "tumble/body.h"
#include "tumble/status.h"

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* tb_body_motion_sample and tb_body_motion_fn are declared in tumble/body.h. */

/* How the pose moves between two keys. */
typedef enum tb_interpolation {
    TB_INTERPOLATION_LINEAR = 0, /* constant velocity and angular velocity between keys (slerp);
                                    the velocities jump at keys */
    TB_INTERPOLATION_CUBIC,      /* cubic Hermite: velocity and angular velocity continuous (C1) */
    TB_INTERPOLATION_STEP        /* the pose of the last key at or before t; velocity 0 */
} tb_interpolation;

#define TB_INTERPOLATION_COUNT 3

/* One key. Fill with tb_body_key_default(), then set the fields. */
typedef struct tb_body_key {
    double t;                   /* s; keys' times strictly increase */
    double position[3];         /* m, world (what tb_body_motion_sample.position means) */
    double orientation[4];      /* (w, x, y, z), shape -> world: any finite nonzero quaternion,
                                   normalised when the keyframes are made, its sign chosen so
                                   the curve turns the shorter way from the key before (samples
                                   may give -q, the same rotation); default identity */
    bool has_velocity;          /* cubic only: velocity is the curve's tangent here */
    double velocity[3];         /* m/s, world; read when has_velocity */
    bool has_angular_velocity;  /* cubic only: angular_velocity is the curve's here */
    double angular_velocity[3]; /* rad/s, world; read when has_angular_velocity */
} tb_body_key;

/* A key at t = 0, position 0, identity orientation, no velocities given. */
TB_API tb_body_key tb_body_key_default(void);

typedef struct tb_keyframes tb_keyframes;

/* Makes a curve through count keys (copied; the caller keeps keys).
 * Cubic: a key's velocity / angular velocity is the curve's tangent where given, otherwise the
 * Catmull-Rom tangent from its neighbours (the derivative of the parabola through the three
 * keys, so uneven spacing is handled), zero at the first and last key. Before the first key and
 * after the last the pose holds, with zero velocity and acceleration.
 * Refusals (*out_keyframes NULL, keys unread past the first bad one, out_error (may be NULL)
 * naming the key and field, e.g. "keys[2].t: must be > keys[1].t = 0.5, got 0.5"):
 *   TB_STATUS_NULL_POINTER     keys or out_keyframes NULL
 *   TB_STATUS_INVALID_ARGUMENT count 0; an unknown interpolation; times not strictly
 *                              increasing (or an interval between them that overflows); a zero
 *                              quaternion; a velocity given to linear or step keys; keys too
 *                              far apart for the time between them (the curve overflows at a
 *                              segment's end)
 *   TB_STATUS_NOT_FINITE       NaN or infinity in a time, position, orientation or velocity
 *   TB_STATUS_OUT_OF_MEMORY    count too large to hold (checked before any key is read) */
TB_API tb_status tb_keyframes_create(const tb_body_key *keys, size_t count,
                                     tb_interpolation interpolation, tb_keyframes **out_keyframes,
                                     tb_error *out_error);

/* Frees keyframes; accepts NULL. */
TB_API void tb_keyframes_destroy(tb_keyframes *keyframes);

/* A tb_body_motion_fn: the curve at t with ctx a tb_keyframes. At a key's time it gives the
 * segment that starts there (the limit from the right; at the last key the held pose). Pure
 * and allocation-free: any number of threads may sample one curve at once. Returns 0, or -1
 * (out untouched) for a NULL ctx or out, a NaN t, or a value that overflows. */
TB_API int tb_keyframes_sample(double t, void *ctx, tb_body_motion_sample *out);

/* The same with the limit from the left at a key's time: what a step ending at that key sees
 * (the first key: the held pose before it). Elsewhere the same as tb_keyframes_sample. */
TB_API int tb_keyframes_sample_left(double t, void *ctx, tb_body_motion_sample *out);

/* The keys' times, count of them, increasing, owned by the keyframes: the times where the curve
 * is only C1 (C0 for linear, jumps for step), where fixed steps should end and CVODE stop.
 * NULL (and *out_count 0) for NULL keyframes; out_count may be NULL. */
TB_API const double *tb_keyframes_times(const tb_keyframes *keyframes, size_t *out_count);

/* "linear", "cubic", "step"; NULL for an unknown value. */
TB_API const char *tb_interpolation_name(tb_interpolation interpolation);

/* Parses an interpolation name, ignoring ASCII case. Unknown: TB_STATUS_INVALID_ARGUMENT and
 * out_error (may be NULL) naming it and listing the names; NULL name or out:
 * TB_STATUS_NULL_POINTER. *out_interpolation is written only on success. */
TB_API tb_status tb_interpolation_parse(const char *name, tb_interpolation *out_interpolation,
                                        tb_error *out_error);

/* Drives keyframed body id of scene through keys (copied; tb_keyframes_create's rules and
 * refusals, the detail in the scene naming the key) with its velocity and acceleration from the
 * curve: tb_scene_set_body_motion_fn with a curve the scene owns, whose key times end fixed
 * steps and stop CVODE (the curve is only C1 there). Also refused (nothing changed): a body
 * that is not keyframed (TB_STATUS_INVALID_ARGUMENT), an id out of range
 * (TB_STATUS_OUT_OF_RANGE), while the scene is being stepped (TB_STATUS_BUSY). */
TB_API tb_status tb_scene_set_body_keys(tb_scene *scene, size_t id, const tb_body_key *keys,
                                        size_t count, tb_interpolation interpolation);

#ifdef __cplusplus
}
#endif

#endif

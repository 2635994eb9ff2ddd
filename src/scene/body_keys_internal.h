/* Private: a keyframe curve's layout, shared by the object (body_keys.c) and the curves it
 * evaluates (body_keys_curves.c). */
#ifndef TUMBLE_BODY_KEYS_INTERNAL_H
#define TUMBLE_BODY_KEYS_INTERNAL_H

#include "tumble/keys.h"

/* A key as the curve uses it. */
typedef struct tb__key_node {
    double position[3];         /* m, world */
    double orientation[4];      /* unit, its sign chosen so q_k . q_(k-1) >= 0 (shortest way) */
    double velocity[3];         /* cubic: the tangent dx/dt here (given, Catmull-Rom or 0) */
    double angular_velocity[3]; /* cubic: omega here, world (given, Catmull-Rom or 0) */
} tb__key_node;

/* What a segment [t_k, t_(k+1)] needs besides its two nodes. Its orientation is
 * q(t) = exp(phi(t)) (x) q_k with phi(t_k) = 0 and phi(t_(k+1)) = rotation. */
typedef struct tb__key_segment {
    double rotation[3]; /* phi_1 = log(q_(k+1) (x) q_k*), rad, world, |phi_1| <= pi */
    double end_rate[3]; /* cubic: dphi/dt at t_(k+1), J_l(phi_1)^-1 omega_(k+1), rad/s */
} tb__key_segment;

struct tb_keyframes {
    tb_interpolation interpolation;
    size_t count;
    double *times;             /* count, strictly increasing, s */
    tb__key_node *nodes;       /* count */
    tb__key_segment *segments; /* count - 1 (one allocated when count is 1) */
};

/* Rotation vectors (phi, rad, world) and unit quaternions (w, x, y, z). */
void tb__rotation_exp(double q[4], const double phi[3]);
/* q must be unit with w >= 0: |phi| <= pi. */
void tb__rotation_log(double phi[3], const double q[4]);
/* out = J_l(phi)^-1 w: dphi/dt of the curve exp(phi(t)) whose angular velocity is w. */
void tb__rotation_rate_of(double out[3], const double phi[3], const double w[3]);

/* Segment k of a linear or cubic curve at t in [t_k, t_(k+1)] (s = (t - t_k) / h in [0, 1]):
 * the pose, velocities and accelerations into out. */
void tb__keys_segment_sample(const tb_keyframes *keyframes, size_t k, double t,
                             tb_body_motion_sample *out);

#endif

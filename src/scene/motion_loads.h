/* Private: how a body moves (tb__motion, read from y once per evaluation) and how a load at a
 * point meets it (lever arms, inverse masses, adding a load). Included at the end of
 * scene_internal.h, which it needs (tb_scene, tb__body). */
#ifndef TUMBLE_MOTION_LOADS_H
#define TUMBLE_MOTION_LOADS_H

#include "math/tb_math.h"

/* How body i moves, read from y once for an effect that looks at several of its points. */
typedef struct tb__motion {
    double x[3];     /* centre of mass, world */
    double q[4];     /* unit, principal -> world */
    double v[3];     /* centre-of-mass velocity */
    double omega[3]; /* angular velocity, world */
} tb__motion;

/* A dynamic body's motion from its 13 states s (the hot loops' form). */
void tb__body_motion(const tb__body *body, const double *s, tb__motion *out);

/* Body id's motion at the y of the evaluation of tb_scene_derivative running now: for the
 * coupled effects' apply only (the derivative's kinematics filled it from that y), bit for bit
 * tb__body_motion's. */
static inline const tb__motion *tb__derivative_motion(const tb_scene *scene, size_t id)
{
    return &scene->motions[id];
}

/* A body point r (principal frame, from the centre of mass): its lever arm R r (world),
 * and the velocity v + omega x arm of the material point at arm. */
static inline void tb__point_arm(const tb__motion *motion, const double r[3], double arm[3])
{
    tb__q_rotate(arm, motion->q, r);
}

static inline void tb__point_velocity(const tb__motion *motion, const double arm[3],
                                      double velocity[3])
{
    tb__v3_cross(velocity, motion->omega, arm);
    tb__v3_axpy(velocity, 1.0, motion->v);
}

/* The inverse mass (1/kg) that a force along the unit vector u at lever arm `arm` (world, from
 * the centre of mass) meets at its point: 1/M + (arm x u) . I^-1 (arm x u), with I^-1 the
 * world-frame inverse inertia of the body turned as motion says. */
double tb__inverse_mass_along(const tb__body *body, const tb__motion *motion, const double arm[3],
                              const double u[3]);
/* The largest of tb__inverse_mass_along over the unit vectors u perpendicular to the unit n: the
 * lightest a tangential force at arm finds the body. */
double tb__inverse_mass_across(const tb__body *body, const tb__motion *motion, const double arm[3],
                               const double n[3]);
/* The orthonormal basis t1, t2 of the plane normal to the unit n that tb__inverse_mass_across
 * uses (the ground's tangent basis, to the bit), and the same inverse mass from it: for a
 * normal met more than once (a plane, both bodies of a pair), the basis is worked out once. */
void tb__tangent_basis(const double n[3], double t1[3], double t2[3]);
double tb__inverse_mass_across_basis(const tb__body *body, const tb__motion *motion,
                                     const double arm[3], const double t1[3], const double t2[3]);

/* M (1/M + max over unit u of (r x u) . I^-1 (r x u)) (>= 1), r in the principal frame from the
 * centre of mass (m): how much lighter than the body a force at r finds it in the worst
 * direction. At most tb__inverse_mass_at's M (1/M + |r|^2 / I_min), and far less for a thin
 * body, whose smallest moment only turns it about its long axis. */
double tb__lightness_at(const tb__body *body, const double r[3]);

/* dP += f and dL += arm x f for the body in slot `slot` (y's index, as the per-body effects'
 * ranges count). Inline, as the two above: every contact point of every derivative adds one. */
static inline void tb__add_load(double *dydt, size_t slot, const double arm[3], const double f[3])
{
    double torque[3];
    tb__v3_cross(torque, arm, f);
    tb__v3_axpy(dydt + TB_STATE_SIZE * slot + TB_STATE_P, 1.0, f);
    tb__v3_axpy(dydt + TB_STATE_SIZE * slot + TB_STATE_L, 1.0, torque);
}

#endif

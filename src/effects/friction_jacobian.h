/* Private: the friction laws' local derivatives (friction_jacobian.c), for the analytic rows of
 * the scene Jacobian (scene/jacobian_rows.h): the stick anchor of ground points, ground shapes and
 * contact between bodies (effect_ground.c bristles(), effect_contact_friction.c anchor_friction(),
 * one law written in world vectors) and the memoryless regularised law, each against the normal
 * force N, the tangential relative velocity v_t and the anchor z (world), with the spring's
 * stiffness and damping held fixed (they scale with the effective masses, held fixed too). */
#ifndef TUMBLE_FRICTION_JACOBIAN_H
#define TUMBLE_FRICTION_JACOBIAN_H

#include "scene/jacobian_rows.h"

/* The law's constants. */
typedef struct tb__friction_law {
    double static_friction, kinetic_friction, stribeck_velocity; /* mu_s, mu_k, m/s */
    double slip_velocity; /* m/s: the memoryless law's v_reg */
} tb__friction_law;

/* d friction / d (N, v_t, z) and d dz / d (the same), world; matrices [row][column]. */
typedef struct tb__friction_jacobian {
    double force_N[3], force_v[3][3], force_z[3][3];
    double rate_N[3], rate_v[3][3], rate_z[3][3];
    double rate[3]; /* dz itself (world), the anchor's: for its turn with body A */
} tb__friction_jacobian;

/* The stick anchor at normal n of stiffness k and damping c (N/m, N s/m) under N > 0, v_t the
 * tangential relative velocity, z the anchor (world): friction = -(k z_t + c v_t) capped at
 * mu N, dz = v_t - release (z . n) n - max rate * excess * z_t / |z_t|. */
void tb__anchor_jacobian(const tb__friction_law *law, double k, double c, double N,
                         const double n[3], const double v_t[3], const double z[3],
                         tb__friction_jacobian *out);

/* The memoryless law -mu(|v_t|) N v_t / sqrt(|v_t|^2 + v_reg^2) (no anchor: rates 0). */
void tb__slip_jacobian(const tb__friction_law *law, double N, const double v_t[3],
                       tb__friction_jacobian *out);

/* The derivatives of an anchor kept in body A's frame (z = R_a s) against A's turn dtheta
 * (world): dz_world = -[z]x dtheta moves the force and the rate, and ds = R_a^T dz_world turns with
 * A: d ds = R_a^T ([dz]x - rate_z [z]x) dtheta. R (row-major) is A's rotation, z the world anchor.
 */
void tb__anchor_turn_rows(const tb__friction_jacobian *fr, const double *R, const double z[3],
                          tb__point_jacobian *p);

/* A contact point's local rows (p's force_*, rate_*; p's bodies, arms and states left to the
 * caller): the force N(d, d') n + friction at normal n, with dN = dN_dd dd + dN_ddr dd'
 * (dd = -n . du, dd' = -n . dw), friction fr (NULL: none, and no states), and the point's own
 * count states s mapped to the world anchor by z = T s (T 3 x 3 row-major, [world][state], its
 * first count columns), their rates by ds = T^T dz. */
void tb__contact_point_rows(const double n[3], double dN_dd, double dN_ddr,
                            const tb__friction_jacobian *fr, const double *T, size_t count,
                            tb__point_jacobian *p);

#endif

/* Small builders shared by the rigid-body tests. */
#ifndef TUMBLE_TEST_BODIES_H
#define TUMBLE_TEST_BODIES_H

#include "tumble/tumble.h"

/* A scene with one body whose principal moments are `moments` (shape frame = principal
 * frame), mass `mass`, at rest at the origin with orientation q0 (NULL for identity),
 * angular velocity given in the body frame. Fails the test on error. */
tb_scene *test_scene_one_body(double mass, const double moments[3], const double q0[4],
                              const double omega_body[3]);

/* Body-frame angular velocity of body id: R^T omega. */
void test_body_omega(const tb_scene *scene, size_t id, double omega_body[3]);

/* The asymmetric top of the tests: I = (1, 2, 3) kg m^2, omega_body(0) = (1.5, 0, 1) rad/s,
 * which rotates about the I3 axis (L^2 > 2 E I2) with k^2 = 0.75, tilted by an arbitrary
 * initial orientation so every world component moves. */
extern const double test_top_moments[3];
extern const double test_top_omega[3];
extern const double test_top_q0[4];

/* Integrates the top with def up to T and returns the largest error of its body-frame
 * angular velocity against the Jacobi elliptic solution, over `frames` equally spaced output
 * times. Fills *stats if not NULL. */
double test_top_error(const tb_integrator_def *def, double T, int frames,
                      tb_integrator_stats *stats);

/* A flat box (0.4 x 0.4 x 0.1 m, 8 kg, its 8 corners as contact points, 4 carrying it) resting
 * on a ground plane through the origin tilted by `degrees` about y, under gravity -9.81 z.
 * ground's normal is set to the plane's. */
tb_scene *test_box_on_slope(double degrees, tb_ground_def *ground);

/* That box released at rest with default friction: how far it moves down the slope, along it,
 * between t0 and t1 (RK4 at the documented 240 steps per second). */
double test_slope_displacement(double degrees, double t0, double t1);

#endif

/* Jointed scenes the joint tests and the joint benchmark share, and the exact equations they
 * are checked against. Each fails the calling test (CMocka) when the library refuses. */
#ifndef TUMBLE_TEST_JOINT_SCENES_H
#define TUMBLE_TEST_JOINT_SCENES_H

#include "tumble/tumble.h"

#define TEST_G 9.81 /* m/s^2, down -z */
#define TEST_PI 3.14159265358979323846

/* A thin rod (a box length x 0.02 x 0.02 m) of mass m whose long axis points along the unit
 * direction (sin theta, 0, -cos theta) (theta from straight down, about +y), its centre at
 * center. Returns its id. */
size_t test_add_rod(tb_scene *scene, double m, double length, double theta, const double center[3]);

/* The same with a square section of side width (m). */
size_t test_add_bar(tb_scene *scene, double m, double length, double width, double theta,
                    const double center[3]);

/* The moment of inertia (kg m^2) of such a rod about its centre, across its length. */
double test_rod_moment(double m, double length);

/* A double pendulum of two 1 kg rods of 1 m under gravity: rod 0 hinged to the world at the
 * origin, rod 1 hinged to rod 0's end, both about the y axis, at angles theta1, theta2 from
 * straight down, at rest. ids (may be NULL) gets the rods' ids. */
tb_scene *test_double_pendulum(double theta1, double theta2, size_t ids[2]);

/* The same double pendulum in generalised coordinates (its Lagrange equations), integrated
 * by RK4 with steps of 1e-4 s from (theta1, theta2) at rest: out[2 k], out[2 k + 1] the angles
 * at t = k * interval, for k = 0 .. count - 1. */
void test_double_pendulum_reference(double theta1, double theta2, double interval, size_t count,
                                    double *out);

/* The angle from straight down (about +y) of rod id's long axis at state y. */
double test_rod_angle(const tb_scene *scene, const double *y, size_t id);

/* A chain of n bars (mass m, length l, section 0.1 l: thin rods spinning end over end would
 * meet the stability guard's limit for thin spinning bodies at 240 Hz) joined end to end by ball
 * joints, the first hung from the world at the origin, lying horizontally along +x at rest, under
 * gravity. */
tb_scene *test_ball_chain(size_t n, double m, double l);

/* A 20 kg door (1 m wide, 5 cm thick, 2 m tall; no collision shape), its edge on the z axis
 * through the origin and its centre at (0.5, 0, 0), swinging open about z at omega (rad/s; its
 * centre moving at 0.5 omega along +y, so the edge stays at rest). Returns its id; *hinge gets
 * the door's joint, not yet added: a hinge about z through the edge with limits [0, 90 deg]
 * (restitution 0, no motor), for the caller to complete and add. */
size_t test_add_swinging_door(tb_scene *scene, double omega, tb_joint_def *hinge);

/* Kinetic plus potential energy at the scene's states (J). */
double test_total_energy(const tb_scene *scene);

/* The largest position error of every joint at the scene's states. */
double test_largest_joint_error(const tb_scene *scene);

#endif

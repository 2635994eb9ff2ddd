/* Builders for the contact-geometry tests: shapes, poses, a reproducible random stream. */
#ifndef TUMBLE_TEST_GEOMETRY_H
#define TUMBLE_TEST_GEOMETRY_H

#include "contact/collision_shape.h"

#include <stdint.h>

/* Fails the test unless the shape is made. The caller frees it. */
tb__collision_shape *test_shape(const tb_shape *shape);
tb__collision_shape *test_sphere(double radius);
tb__collision_shape *test_box(double x, double y, double z); /* full edge lengths */
tb__collision_shape *test_capsule(double radius, double length);

/* pose = position, then the rotation by angle (rad) about axis (any length > 0). */
void test_pose(double pose[TB__POSE_SIZE], double x, double y, double z, const double axis[3],
               double angle);

/* Uniform in [low, high), from a xorshift stream. */
double test_uniform(uint64_t *state, double low, double high);
/* A uniformly random unit quaternion (Shoemake's method). */
void test_random_quaternion(uint64_t *state, double q[4]);

#endif

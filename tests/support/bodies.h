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

#endif

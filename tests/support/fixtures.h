/* The scenes and integrators most tests start from, made the same way everywhere. Each fails
 * the calling test (CMocka) when the library refuses. */
#ifndef TUMBLE_TEST_FIXTURES_H
#define TUMBLE_TEST_FIXTURES_H

#include "tumble/tumble.h"

/* A scene with the default definition and nothing in it. */
tb_scene *test_empty_scene(void);

/* Mass properties of 5 kg with principal moments 2, 3, 4 kg m^2 about axes turned 1.2 rad
 * about y against the shape frame (the quaternion (cos 0.6, 0, sin 0.6, 0)) and the centre of
 * mass at (0.1, 0.2, 0.3) m in the shape frame: a full tensor with products of inertia and an
 * off-origin centre. */
tb_mass_properties test_tilted_mass(void);

/* Adds a body of mass m (kg) whose shape is a sphere of radius r (m), centred at x moving at v
 * (world frame; v NULL: at rest), named name (NULL: unnamed). Returns its id. */
size_t test_add_ball(tb_scene *scene, const char *name, double m, double r, const double x[3],
                     const double v[3]);

/* The default integrator definition for method, with dt set for a fixed-step method (0: the
 * scene's default step) or rtol for an adaptive one; the other fields keep their defaults. */
tb_integrator_def test_integrator_def(tb_method method, double dt, double rtol);

/* An integrator for scene from t = 0 by def; on refusal the scene's detail is printed. */
tb_integrator *test_integrator(tb_scene *scene, const tb_integrator_def *def);

/* test_integrator of test_integrator_def(method, dt, rtol). */
tb_integrator *test_integrator_for(tb_scene *scene, tb_method method, double dt, double rtol);

/* A dynamic box body of mass m (kg) and edge lengths size (m), at rest at x, with a box
 * collision shape of the same size. Fails the test on error. */
size_t test_add_box(tb_scene *scene, double m, const double size[3], const double x[3]);

/* A body of mass m with a sphere (size[0] its radius) or box shape, its centre of mass the
 * shape's centre, at x turned by q (NULL: level), moving at v and w (NULL: at rest). */
size_t test_add_shaped_body(tb_scene *scene, tb_shape_type type, double m, const double size[3],
                            const double x[3], const double q[4], const double v[3],
                            const double w[3]);

#endif

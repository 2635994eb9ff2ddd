/* The scenes and integrators most tests start from, made the same way everywhere. Each fails
 * the calling test (CMocka) when the library refuses. */
#ifndef TUMBLE_TEST_FIXTURES_H
#define TUMBLE_TEST_FIXTURES_H

#include "tumble/tumble.h"

/* A scene with the default definition and nothing in it. */
tb_scene *test_empty_scene(void);

/* The default integrator definition for method, with dt set for a fixed-step method (0: the
 * scene's default step) or rtol for an adaptive one; the other fields keep their defaults. */
tb_integrator_def test_integrator_def(tb_method method, double dt, double rtol);

/* An integrator for scene from t = 0 by def; on refusal the scene's detail is printed. */
tb_integrator *test_integrator(tb_scene *scene, const tb_integrator_def *def);

/* test_integrator of test_integrator_def(method, dt, rtol). */
tb_integrator *test_integrator_for(tb_scene *scene, tb_method method, double dt, double rtol);

#endif

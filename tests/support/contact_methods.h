/* The integrators a user picks for contact, as a table the contact reference tests loop over,
 * and the scenes they build (tests/test_contact_references.c). Each fails the calling test
 * (CMocka) when the library refuses. */
#ifndef TUMBLE_TEST_CONTACT_METHODS_H
#define TUMBLE_TEST_CONTACT_METHODS_H

#include "tumble/tumble.h"

#include <stdbool.h>
#include <stddef.h>

typedef struct test_contact_method {
    const char *name;
    tb_method method;
    double dt;               /* fixed steps: 0 is the scene's default step */
    tb_linear_solver solver; /* cvode-bdf and ark-imex */
} test_contact_method;

/* rk4 at the scene's default step and at a user's 1e-4 s, rosenbrock at 1/240 s and 1/1000 s,
 * cvode-adams, cvode-bdf and ark-imex with the sparse contact Jacobian, the adaptive ones at
 * their default tolerances. */
extern const test_contact_method test_contact_methods[];
extern const size_t test_contact_method_count;

bool test_is_rosenbrock(const test_contact_method *c);

/* The integrator a user makes for c from t = 0, or NULL where the stability guard refuses the
 * user's rk4 step (the one refusal allowed: the guard is the library's documented answer, and
 * its detail is printed). */
tb_integrator *test_contact_integrator(tb_scene *scene, const test_contact_method *c);

/* An empty scene under gravity -g z (g 0: none). */
tb_scene *test_scene_with_gravity(double g);

/* A ground plane through the origin tilted by `degrees` about y (normal (-sin a, 0, cos a)). */
void test_add_tilted_plane(tb_scene *scene, double degrees, double e, double mu_s, double mu_k);

#endif

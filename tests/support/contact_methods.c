/* The integrators a user picks for contact and the scenes of the reference tests
 * (contact_methods.h). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "contact_methods.h"
#include "fixtures.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

const test_contact_method test_contact_methods[] = {
    {"rk4 default", TB_METHOD_RK4, 0.0, TB_LINEAR_SOLVER_AUTO},
    {"rk4 1e-4", TB_METHOD_RK4, 1e-4, TB_LINEAR_SOLVER_AUTO},
    {"rosenbrock 1/240", TB_METHOD_ROSENBROCK, 1.0 / 240.0, TB_LINEAR_SOLVER_AUTO},
    {"rosenbrock 1/1000", TB_METHOD_ROSENBROCK, 1e-3, TB_LINEAR_SOLVER_AUTO},
    {"cvode-adams", TB_METHOD_CVODE_ADAMS, 0.0, TB_LINEAR_SOLVER_AUTO},
    {"cvode-bdf sparse", TB_METHOD_CVODE_BDF, 0.0, TB_LINEAR_SOLVER_SPARSE},
    {"ark-imex sparse", TB_METHOD_ARK_IMEX, 0.0, TB_LINEAR_SOLVER_SPARSE},
};
const size_t test_contact_method_count = sizeof test_contact_methods / sizeof *test_contact_methods;

bool test_is_rosenbrock(const test_contact_method *c)
{
    return c->method == TB_METHOD_ROSENBROCK;
}

tb_integrator *test_contact_integrator(tb_scene *scene, const test_contact_method *c)
{
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, c->method), TB_STATUS_OK);
    if (!tb_method_is_adaptive(c->method)) {
        def.dt = c->dt;
    } else if (c->method != TB_METHOD_CVODE_ADAMS) {
        def.linear_solver = c->solver;
    }
    tb_integrator *integrator = NULL;
    const tb_status status = tb_scene_integrator_create(scene, &def, 0.0, &integrator);
    if (status != TB_STATUS_OK) {
        print_message("  %-18s refused: %s\n", c->name, tb_scene_detail(scene));
    }
    if (c->method == TB_METHOD_RK4 && c->dt > 0.0 && status != TB_STATUS_OK) {
        return NULL;
    }
    assert_int_equal(status, TB_STATUS_OK);
    return integrator;
}

tb_scene *test_scene_with_gravity(double g)
{
    tb_scene *scene = test_empty_scene();
    if (g > 0.0) {
        assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -g}), TB_STATUS_OK);
    }
    return scene;
}

void test_add_tilted_plane(tb_scene *scene, double degrees, double e, double mu_s, double mu_k)
{
    const double a = degrees * PI / 180.0;
    tb_ground_def ground = tb_ground_def_default();
    ground.normal[0] = -sin(a);
    ground.normal[2] = cos(a);
    ground.restitution = e;
    ground.static_friction = mu_s;
    ground.kinetic_friction = mu_k;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
}

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "torque_free_top.h"

#include <math.h>
#include <string.h>

tb_scene *test_scene_one_body(double mass, const double moments[3], const double q0[4],
                              const double omega_body[3])
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    const double I[9] = {moments[0], 0, 0, 0, moments[1], 0, 0, 0, moments[2]};
    const double origin[3] = {0, 0, 0};
    assert_int_equal(tb_mass_from_tensor(mass, origin, I, &def.mass, NULL), TB_STATUS_OK);
    if (q0 != NULL) {
        for (int k = 0; k < 4; ++k) {
            def.orientation[k] = q0[k];
        }
    }
    /* World angular velocity R(q0) omega_body, by the rotation matrix written out here. */
    const double *q = def.orientation;
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    const double R[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                         2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                         2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
    for (int i = 0; i < 3; ++i) {
        def.angular_velocity[i] =
            R[3 * i] * omega_body[0] + R[3 * i + 1] * omega_body[1] + R[3 * i + 2] * omega_body[2];
    }
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    return scene;
}

void test_body_omega(const tb_scene *scene, size_t id, double omega_body[3])
{
    double R[9], omega[3];
    const double *y = tb_scene_states_const(scene);
    assert_int_equal(tb_scene_body_rotation(scene, y, id, R), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_angular_velocity(scene, y, id, omega), TB_STATUS_OK);
    for (int i = 0; i < 3; ++i) { /* R^T omega */
        omega_body[i] = R[i] * omega[0] + R[3 + i] * omega[1] + R[6 + i] * omega[2];
    }
}

const double test_top_moments[3] = {1.0, 2.0, 3.0};
const double test_top_omega[3] = {1.5, 0.0, 1.0};
const double test_top_q0[4] = {0.8, 0.36, -0.48, 0.0};

double test_top_error(const tb_integrator_def *def, double T, int frames,
                      tb_integrator_stats *stats)
{
    torque_free_top exact;
    assert_int_equal(
        torque_free_top_init(&exact, test_top_moments, test_top_omega[0], test_top_omega[2]), 0);
    tb_scene *scene = test_scene_one_body(1.0, test_top_moments, test_top_q0, test_top_omega);
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, def, 0.0, &integrator), TB_STATUS_OK);
    double worst = 0.0;
    for (int f = 1; f <= frames; ++f) {
        const double t = T * f / frames;
        assert_int_equal(tb_integrator_advance(integrator, t), TB_STATUS_OK);
        double w[3], w_exact[3];
        test_body_omega(scene, 0, w);
        torque_free_top_omega(&exact, t, w_exact);
        for (int i = 0; i < 3; ++i) {
            worst = fmax(worst, fabs(w[i] - w_exact[i]));
        }
    }
    if (stats != NULL) {
        tb_integrator_get_stats(integrator, stats);
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return worst;
}

tb_scene *test_box_on_slope(double degrees, tb_ground_def *ground)
{
    const double a = degrees * 3.14159265358979323846 / 180.0;
    const double normal[3] = {-sin(a), 0.0, cos(a)};
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    const double size[3] = {0.4, 0.4, 0.1};
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 8.0, size, &def.mass, NULL), TB_STATUS_OK);
    const double q[4] = {cos(-a / 2), 0.0, sin(-a / 2), 0.0}; /* turns z onto the normal */
    memcpy(def.orientation, q, sizeof q);
    for (int i = 0; i < 3; ++i) {
        def.position[i] = 0.05 * normal[i]; /* bottom face on the plane */
    }
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    tb_contact_point corners[8];
    size_t count;
    assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_contact_points(scene, 0, corners, count, 4), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    memcpy(ground->normal, normal, sizeof normal);
    assert_int_equal(tb_scene_add_ground(scene, ground), TB_STATUS_OK);
    return scene;
}

double test_slope_displacement(double degrees, double t0, double t1)
{
    const double a = degrees * 3.14159265358979323846 / 180.0;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = test_box_on_slope(degrees, &ground);
    tb_integrator_def def = tb_integrator_def_default(); /* RK4 at the default step */
    def.dt = 0.0;
    def.max_steps = 1000000000; /* 12 s at the stiff contact's 1/13440 s */
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, t0), TB_STATUS_OK);
    const double *y = tb_scene_states(scene);
    const double start = -cos(a) * y[0] - sin(a) * y[2];
    assert_int_equal(tb_integrator_advance(integrator, t1), TB_STATUS_OK);
    const double end = -cos(a) * y[0] - sin(a) * y[2];
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return end - start;
}

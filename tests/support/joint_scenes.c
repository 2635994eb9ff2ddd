#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define ROD_WIDTH 0.02

double test_rod_moment(double m, double length)
{
    return m * (length * length + ROD_WIDTH * ROD_WIDTH) / 12.0;
}

size_t test_add_rod(tb_scene *scene, double m, double length, double theta, const double center[3])
{
    return test_add_bar(scene, m, length, ROD_WIDTH, theta, center);
}

size_t test_add_bar(tb_scene *scene, double m, double length, double width, double theta,
                    const double center[3])
{
    tb_body_def def = tb_body_def_default();
    const double size[3] = {length, width, width};
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, m, size, &def.mass, NULL), TB_STATUS_OK);
    /* the box's x axis turned about y by phi = pi/2 - theta: (cos phi, 0, -sin phi) */
    const double phi = 0.5 * TEST_PI - theta;
    const double q[4] = {cos(0.5 * phi), 0.0, sin(0.5 * phi), 0.0};
    memcpy(def.orientation, q, sizeof q);
    memcpy(def.position, center, 3 * sizeof(double));
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    return id;
}

static void add_joint(tb_scene *scene, tb_joint_type type, size_t a, size_t b,
                      const double anchor[3], const double axis[3])
{
    tb_joint_def def = tb_joint_def_default();
    def.type = type;
    def.body_a = a;
    def.body_b = b;
    memcpy(def.anchor, anchor, sizeof def.anchor);
    if (axis != NULL) {
        memcpy(def.axis, axis, sizeof def.axis);
    }
    const tb_status status = tb_scene_add_joint(scene, &def, NULL);
    if (status != TB_STATUS_OK) {
        print_message("%s\n", tb_scene_detail(scene));
    }
    assert_int_equal(status, TB_STATUS_OK);
}

tb_scene *test_double_pendulum(double theta1, double theta2, size_t ids[2])
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double d1[3] = {sin(theta1), 0.0, -cos(theta1)}, d2[3] = {sin(theta2), 0.0, -cos(theta2)};
    const double c1[3] = {0.5 * d1[0], 0.0, 0.5 * d1[2]};
    const double end[3] = {d1[0], 0.0, d1[2]};
    const double c2[3] = {end[0] + 0.5 * d2[0], 0.0, end[2] + 0.5 * d2[2]};
    const size_t a = test_add_rod(scene, 1.0, 1.0, theta1, c1);
    const size_t b = test_add_rod(scene, 1.0, 1.0, theta2, c2);
    const double axis[3] = {0.0, 1.0, 0.0}, origin[3] = {0.0, 0.0, 0.0};
    add_joint(scene, TB_JOINT_HINGE, a, TB_WORLD, origin, axis);
    add_joint(scene, TB_JOINT_HINGE, b, a, end, axis);
    if (ids != NULL) {
        ids[0] = a;
        ids[1] = b;
    }
    return scene;
}

/* The double compound pendulum's Lagrange equations: M(theta) theta'' = f, with rods of mass
 * m, length l, centre at a = l / 2, moment I about the centre:
 *   M11 = m a^2 + I + m l^2, M12 = m l a cos(t1 - t2), M22 = m a^2 + I
 *   f1 = -m l a sin(t1 - t2) w2^2 - (m a + m l) g sin t1
 *   f2 =  m l a sin(t1 - t2) w1^2 - m a g sin t2 */
static void lagrange(const double s[4], double out[4])
{
    const double m = 1.0, l = 1.0, a = 0.5, I = test_rod_moment(m, l);
    const double c = cos(s[0] - s[1]), sn = sin(s[0] - s[1]);
    const double M11 = m * a * a + I + m * l * l, M12 = m * l * a * c, M22 = m * a * a + I;
    const double f1 = -m * l * a * sn * s[3] * s[3] - (m * a + m * l) * TEST_G * sin(s[0]);
    const double f2 = m * l * a * sn * s[2] * s[2] - m * a * TEST_G * sin(s[1]);
    const double det = M11 * M22 - M12 * M12;
    out[0] = s[2];
    out[1] = s[3];
    out[2] = (M22 * f1 - M12 * f2) / det;
    out[3] = (M11 * f2 - M12 * f1) / det;
}

static void rk4(double s[4], double h)
{
    double k[4][4], t[4];
    lagrange(s, k[0]);
    for (int stage = 1; stage < 4; ++stage) {
        const double c = stage == 3 ? h : 0.5 * h;
        for (int i = 0; i < 4; ++i) {
            t[i] = s[i] + c * k[stage - 1][i];
        }
        lagrange(t, k[stage]);
    }
    for (int i = 0; i < 4; ++i) {
        s[i] += h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
    }
}

void test_double_pendulum_reference(double theta1, double theta2, double interval, size_t count,
                                    double *out)
{
    double s[4] = {theta1, theta2, 0.0, 0.0};
    const int per = (int)lround(interval / 1e-4);
    const double h = interval / per;
    for (size_t k = 0; k < count; ++k) {
        out[2 * k] = s[0];
        out[2 * k + 1] = s[1];
        for (int i = 0; i < per; ++i) {
            rk4(s, h);
        }
    }
}

double test_rod_angle(const tb_scene *scene, const double *y, size_t id)
{
    double d[3], c[3], v[3];
    assert_int_equal(tb_scene_body_point(scene, y, id, (double[]){1.0, 0.0, 0.0}, d, v),
                     TB_STATUS_OK);
    assert_int_equal(tb_scene_body_point(scene, y, id, (double[]){0.0, 0.0, 0.0}, c, v),
                     TB_STATUS_OK);
    return atan2(d[0] - c[0], -(d[2] - c[2]));
}

tb_scene *test_ball_chain(size_t n, double m, double l)
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    size_t previous = TB_WORLD;
    for (size_t i = 0; i < n; ++i) {
        const double center[3] = {(i + 0.5) * l, 0.0, 0.0};
        const size_t id = test_add_bar(scene, m, l, 0.1 * l, 0.5 * TEST_PI, center);
        add_joint(scene, TB_JOINT_BALL, id, previous, (double[]){i * l, 0.0, 0.0}, NULL);
        previous = id;
    }
    return scene;
}

size_t test_add_swinging_door(tb_scene *scene, double omega, tb_joint_def *hinge)
{
    tb_body_def body = tb_body_def_default();
    assert_int_equal(
        tb_mass_from_box(TB_MASS_GIVEN, 20.0, (double[]){1.0, 0.05, 2.0}, &body.mass, NULL),
        TB_STATUS_OK);
    body.position[0] = 0.5;
    body.angular_velocity[2] = omega;
    body.velocity[1] = 0.5 * omega; /* omega x (centre - edge) */
    size_t door = 0;
    assert_int_equal(tb_scene_add_body(scene, &body, &door), TB_STATUS_OK);
    *hinge = tb_joint_def_default();
    hinge->type = TB_JOINT_HINGE;
    hinge->body_a = door;
    hinge->has_limits = 1;
    hinge->limits[1] = TEST_PI / 2.0;
    return door;
}

double test_total_energy(const tb_scene *scene)
{
    double kinetic = 0.0, potential = 0.0;
    const double *y = tb_scene_states_const(scene);
    assert_int_equal(tb_scene_kinetic_energy(scene, y, &kinetic), TB_STATUS_OK);
    assert_int_equal(tb_scene_potential_energy(scene, y, &potential), TB_STATUS_OK);
    return kinetic + potential;
}

double test_largest_joint_error(const tb_scene *scene)
{
    double worst = 0.0;
    for (size_t j = 0; j < tb_scene_joint_count(scene); ++j) {
        double error = 0.0;
        assert_int_equal(tb_scene_joint_error(scene, tb_scene_states_const(scene), j, &error, NULL),
                         TB_STATUS_OK);
        worst = fmax(worst, error);
    }
    return worst;
}

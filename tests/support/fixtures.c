#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "math/tb_math.h"

#include <math.h>
#include <string.h>

tb_scene *test_empty_scene(void)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    return scene;
}

tb_mass_properties test_tilted_mass(void)
{
    const double q[4] = {cos(0.6), 0.0, sin(0.6), 0.0};
    double R[9], I[9];
    tb__q_to_matrix(R, q);
    tb__m3_rotate_diagonal(I, R, (double[]){2.0, 3.0, 4.0});
    tb_mass_properties mass;
    assert_int_equal(tb_mass_from_tensor(5.0, (double[]){0.1, 0.2, 0.3}, I, &mass, NULL),
                     TB_STATUS_OK);
    return mass;
}

size_t test_add_ball(tb_scene *scene, const char *name, double m, double r, const double x[3],
                     const double v[3])
{
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, m, r, &def.mass, NULL), TB_STATUS_OK);
    if (name != NULL) {
        def.name = name;
    }
    memcpy(def.position, x, sizeof def.position);
    if (v != NULL) {
        memcpy(def.velocity, v, sizeof def.velocity);
    }
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = r;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    return id;
}

tb_integrator_def test_integrator_def(tb_method method, double dt, double rtol)
{
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    if (tb_method_is_adaptive(method)) {
        def.rtol = rtol;
    } else {
        def.dt = dt;
    }
    return def;
}

tb_integrator *test_integrator(tb_scene *scene, const tb_integrator_def *def)
{
    tb_integrator *integrator = NULL;
    const tb_status status = tb_scene_integrator_create(scene, def, 0.0, &integrator);
    if (status != TB_STATUS_OK) {
        print_message("%s\n", tb_scene_detail(scene));
    }
    assert_int_equal(status, TB_STATUS_OK);
    return integrator;
}

tb_integrator *test_integrator_for(tb_scene *scene, tb_method method, double dt, double rtol)
{
    const tb_integrator_def def = test_integrator_def(method, dt, rtol);
    return test_integrator(scene, &def);
}

size_t test_add_shaped_body(tb_scene *scene, tb_shape_type type, double m, const double size[3],
                            const double x[3], const double q[4], const double v[3],
                            const double w[3])
{
    tb_body_def def = tb_body_def_default();
    tb_shape shape = tb_shape_default();
    shape.type = type;
    if (type == TB_SHAPE_SPHERE) {
        shape.radius = size[0];
        assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, m, size[0], &def.mass, NULL),
                         TB_STATUS_OK);
    } else {
        memcpy(shape.size, size, sizeof shape.size);
        assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, m, size, &def.mass, NULL), TB_STATUS_OK);
    }
    memcpy(def.position, x, sizeof def.position);
    if (q != NULL) {
        memcpy(def.orientation, q, sizeof def.orientation);
    }
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    if (v != NULL || w != NULL) { /* a new body is at rest: nothing to set, nothing woken */
        const double zero[3] = {0, 0, 0};
        assert_int_equal(tb_scene_set_velocity(scene, id, v ? v : zero, w ? w : zero),
                         TB_STATUS_OK);
    }
    return id;
}

size_t test_add_box(tb_scene *scene, double m, const double size[3], const double x[3])
{
    return test_add_shaped_body(scene, TB_SHAPE_BOX, m, size, x, NULL, NULL, NULL);
}

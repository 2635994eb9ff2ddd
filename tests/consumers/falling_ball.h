/* Shared by the consumer programs: a 1 kg ball dropped from 10 m falls g t^2 / 2 in t (RK4 is
 * exact on it). Returns 0 when the installed library gets that right. */
#include <tumble/tumble.h>

#include <math.h>
#include <stdio.h>

static int falling_ball_checks_out(void)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    if (tb_scene_create(&scene_def, &scene, NULL) != TB_STATUS_OK) {
        return 1;
    }
    tb_body_def ball = tb_body_def_default();
    tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &ball.mass, NULL);
    ball.position[2] = 10.0;
    const double g[3] = {0, 0, -9.81};
    tb_integrator_def how = tb_integrator_def_default();
    tb_integrator *integrator = NULL;
    int failed = tb_scene_add_body(scene, &ball, NULL) != TB_STATUS_OK ||
                 tb_scene_add_gravity(scene, g) != TB_STATUS_OK ||
                 tb_scene_integrator_create(scene, &how, 0.0, &integrator) != TB_STATUS_OK ||
                 tb_integrator_advance(integrator, 1.0) != TB_STATUS_OK;
    const double z = tb_scene_states(scene)[2];
    failed |= fabs(z - (10.0 - 0.5 * 9.81)) > 1e-12;
    printf("tumble %s: ball at z = %.12f after 1 s (%s)\n", TB_VERSION_STRING, z,
           failed ? "WRONG" : "ok");
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return failed;
}

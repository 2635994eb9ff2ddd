/* A box thrown into the air with a spin about its long axis, under gravity, integrated
 * with RK4 at 240 steps per second.
 *
 * Checks (exit 1 if one fails):
 *   - the centre of mass follows the parabola x0 + v0 t + g t^2 / 2 (RK4 is exact on it);
 *   - angular momentum about the centre of mass does not change (gravity exerts no torque
 *     about it);
 *   - total energy (kinetic + potential) is conserved to 1e-9 relative. */
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>

static int check(const char *what, double value, double limit)
{
    const int ok = fabs(value) <= limit;
    printf("  %-44s %10.3e  (limit %.0e)  %s\n", what, value, limit, ok ? "ok" : "FAILED");
    return ok;
}

int main(void)
{
    const double g[3] = {0.0, 0.0, -9.81};
    const double size[3] = {0.1, 0.2, 0.4}; /* m */
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    tb_error error;
    if (tb_scene_create(&scene_def, &scene, &error) != TB_STATUS_OK) {
        fprintf(stderr, "scene: %s\n", error.message);
        return 1;
    }
    tb_body_def box = tb_body_def_default();
    if (tb_mass_from_box(TB_MASS_DENSITY, 700.0, size, &box.mass, &error) != TB_STATUS_OK) {
        fprintf(stderr, "box: %s\n", error.message);
        return 1;
    }
    const double v0[3] = {2.0, 0.0, 6.0}, omega0[3] = {0.5, 1.0, 8.0};
    box.position[2] = 1.0;
    for (int i = 0; i < 3; ++i) {
        box.velocity[i] = v0[i];
        box.angular_velocity[i] = omega0[i];
    }
    size_t id;
    if (tb_scene_add_body(scene, &box, &id) != TB_STATUS_OK || tb_scene_add_gravity(scene, g)) {
        fprintf(stderr, "scene: %s\n", tb_scene_detail(scene));
        return 1;
    }
    tb_integrator_def integrator_def = tb_integrator_def_default(); /* RK4, 1/240 s */
    tb_integrator *integrator = NULL;
    if (tb_scene_integrator_create(scene, &integrator_def, 0.0, &integrator) != TB_STATUS_OK) {
        fprintf(stderr, "integrator: %s\n", tb_scene_detail(scene));
        return 1;
    }
    tb_body_state start;
    tb_scene_get_state(scene, id, &start);
    double E0;
    tb_scene_kinetic_energy(scene, tb_scene_states(scene), &E0);
    E0 -= box.mass.mass * g[2] * start.x[2];

    printf("A %.1f kg box (%.1f x %.1f x %.1f m) thrown up at %.0f m/s with a spin; RK4, dt = "
           "1/240 s\n\n   t (s)     x (m)     z (m)    spin |omega| (rad/s)\n",
           box.mass.mass, size[0], size[1], size[2], v0[2]);
    const double duration = 1.2;
    for (int frame = 0; frame <= 12; ++frame) {
        const double t = duration * frame / 12;
        if (tb_integrator_advance(integrator, t) != TB_STATUS_OK) {
            fprintf(stderr, "step failed: %s\n", tb_integrator_detail(integrator));
            return 1;
        }
        tb_body_state s;
        double omega[3];
        tb_scene_get_state(scene, id, &s);
        tb_scene_body_angular_velocity(scene, tb_scene_states(scene), id, omega);
        printf("  %5.2f  %8.4f  %8.4f   %8.4f\n", t, s.x[0], s.x[2],
               sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]));
    }

    tb_body_state end;
    tb_scene_get_state(scene, id, &end);
    const double T = tb_integrator_time(integrator);
    double position_error = 0.0, L_change = 0.0, E1;
    for (int i = 0; i < 3; ++i) {
        const double exact = start.x[i] + v0[i] * T + 0.5 * g[i] * T * T;
        position_error = fmax(position_error, fabs(end.x[i] - exact));
        L_change = fmax(L_change, fabs(end.L[i] - start.L[i]));
    }
    tb_scene_kinetic_energy(scene, tb_scene_states(scene), &E1);
    E1 -= box.mass.mass * g[2] * end.x[2];

    printf("\nchecks:\n");
    int ok = check("centre of mass off the parabola (m)", position_error, 1e-12);
    ok &= check("change of angular momentum (kg m^2/s)", L_change, 0.0);
    ok &= check("relative change of total energy", (E1 - E0) / E0, 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return ok ? 0 : 1;
}

/* An asymmetric body built from point masses, spun almost exactly about its intermediate
 * principal axis: the spin is unstable and the body flips over again and again (the
 * Dzhanibekov effect), while its world angular momentum stays fixed.
 *
 * Checks (exit 1 if one fails):
 *   - the angular velocity along the intermediate axis changes sign at least 4 times in
 *     20 s (the flips);
 *   - world angular momentum is kept exactly (dL/dt = 0, and every RK stage adds h * 0);
 *   - kinetic energy is conserved to 1e-7 relative (RK4's error at this step). */
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>

int main(void)
{
    /* Six masses on the axes at different distances: principal moments are distinct. */
    const double positions[18] = {0.3, 0,    0, -0.3, 0, 0,   0, 0.2, 0,
                                  0,   -0.2, 0, 0,    0, 0.1, 0, 0,   -0.1};
    const double masses[6] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
    tb_body_def def = tb_body_def_default();
    tb_error error;
    if (tb_mass_from_points(positions, masses, 6, &def.mass, &error) != TB_STATUS_OK) {
        fprintf(stderr, "mass: %s\n", error.message);
        return 1;
    }
    /* Moments about x, y, z: 0.05, 0.1, 0.13 kg m^2, so y is the intermediate axis. */
    def.angular_velocity[0] = 0.01;
    def.angular_velocity[1] = 6.0;
    def.angular_velocity[2] = 0.01;

    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    tb_integrator *integrator = NULL;
    tb_integrator_def integrator_def = tb_integrator_def_default();
    if (tb_scene_create(&scene_def, &scene, &error) != TB_STATUS_OK ||
        tb_scene_add_body(scene, &def, NULL) != TB_STATUS_OK ||
        tb_scene_integrator_create(scene, &integrator_def, 0.0, &integrator) != TB_STATUS_OK) {
        fprintf(stderr, "set-up failed: %s\n", scene ? tb_scene_detail(scene) : error.message);
        return 1;
    }
    printf("Principal moments %.3f %.3f %.3f kg m^2; spin 6 rad/s about the middle one.\n\n",
           def.mass.moments[0], def.mass.moments[1], def.mass.moments[2]);

    tb_body_state start;
    tb_scene_get_state(scene, 0, &start);
    double E0;
    tb_scene_kinetic_energy(scene, tb_scene_states(scene), &E0);
    int flips = 0;
    double previous = 1.0;
    for (int frame = 1; frame <= 20 * 60; ++frame) {
        if (tb_integrator_advance(integrator, frame / 60.0) != TB_STATUS_OK) {
            fprintf(stderr, "step failed: %s\n", tb_integrator_detail(integrator));
            return 1;
        }
        double R[9], omega[3];
        const double *y = tb_scene_states(scene);
        tb_scene_body_rotation(scene, y, 0, R);
        tb_scene_body_angular_velocity(scene, y, 0, omega);
        /* omega along the body's y axis: (R^T omega)_y = column 1 of R dotted with omega */
        const double along = R[1] * omega[0] + R[4] * omega[1] + R[7] * omega[2];
        if (along * previous < 0) {
            ++flips;
            printf("  flip %d at t = %6.3f s\n", flips, frame / 60.0);
        }
        previous = along;
    }
    tb_body_state end;
    tb_scene_get_state(scene, 0, &end);
    double E1, L_change = 0.0;
    tb_scene_kinetic_energy(scene, tb_scene_states(scene), &E1);
    for (int i = 0; i < 3; ++i) {
        L_change = fmax(L_change, fabs(end.L[i] - start.L[i]));
    }
    const int ok = flips >= 4 && L_change == 0.0 && fabs(E1 - E0) <= 1e-7 * E0;
    printf("\nchecks: %d flips (need >= 4), change of L %.1e (need 0), relative energy change "
           "%.2e (need <= 1e-7): %s\n",
           flips, L_change, (E1 - E0) / E0, ok ? "ok" : "FAILED");
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return ok ? 0 : 1;
}

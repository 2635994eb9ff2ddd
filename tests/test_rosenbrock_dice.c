/* Dice tumbling onto a table under "rosenbrock" at a user's 1/240 s (issue 23 item 4): a die
 * landing on a corner or an edge, sliding on it while a second corner comes down inside a step,
 * is where one linearisation does not describe the step (docs/integrators.md, "Halving"). The
 * physics checked needs no reference run: the table is static and does no work, the contact's
 * dashpots and friction take energy and its springs hold it only while pressed, so a die's
 * kinetic and gravitational energy never rises above what it had when dropped. */
#include "tumble/tumble.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <string.h>

#define DROPS 40
#define DIE_EDGE 0.05 /* m */
#define DIE_MASS 0.15 /* kg: 1200 kg/m^3, as examples/scenes/dice.json */

/* A uniform number in [lo, hi) from a 64-bit linear congruential sequence (Knuth's MMIX
 * constants), the same on every platform. */
static double uniform(uint64_t *seed, double lo, double hi)
{
    *seed = *seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * (double)(*seed >> 11) / 9007199254740992.0;
}

static void add_box(tb_scene *scene, const tb_body_def *def, const double size[3])
{
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, 3 * sizeof(double));
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
}

/* The table of examples/scenes/dice.json (0.9 x 0.9 x 0.1 m, its top at z = 0.1 m), static, and
 * one die dropped over it from 16-26 cm with a random orientation, up to 1 m/s sideways, up to
 * 0.5 m/s down and 15 rad/s about each axis; gravity and the default contact. */
static tb_scene *drop_scene(uint64_t *seed)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def table = tb_body_def_default();
    table.motion = TB_MOTION_STATIC;
    table.position[2] = 0.05;
    add_box(scene, &table, (const double[]){0.9, 0.9, 0.1});
    const double edge[3] = {DIE_EDGE, DIE_EDGE, DIE_EDGE};
    tb_body_def die = tb_body_def_default();
    tb_mass_from_box(TB_MASS_GIVEN, DIE_MASS, edge, &die.mass, NULL);
    die.position[2] = uniform(seed, 0.16, 0.26);
    double norm = 0.0;
    for (int k = 0; k < 4; ++k) {
        die.orientation[k] = uniform(seed, -1.0, 1.0);
        norm += die.orientation[k] * die.orientation[k];
    }
    for (int k = 0; k < 4; ++k) {
        die.orientation[k] /= sqrt(norm);
    }
    die.velocity[0] = uniform(seed, -1.0, 1.0);
    die.velocity[1] = uniform(seed, -1.0, 1.0);
    die.velocity[2] = uniform(seed, -0.5, 0.0);
    for (int k = 0; k < 3; ++k) {
        die.angular_velocity[k] = uniform(seed, -15.0, 15.0);
    }
    add_box(scene, &die, edge);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81}), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    return scene;
}

static double energy(const tb_scene *scene)
{
    double kinetic = 0.0, potential = 0.0;
    assert_int_equal(tb_scene_kinetic_energy(scene, tb_scene_states_const(scene), &kinetic),
                     TB_STATUS_OK);
    assert_int_equal(tb_scene_potential_energy(scene, tb_scene_states_const(scene), &potential),
                     TB_STATUS_OK);
    return kinetic + potential;
}

/* The most a die's energy rose over its start, as a part of the start, at any step of 0.8 s. */
static double largest_rise(uint64_t *seed)
{
    tb_scene *scene = drop_scene(seed);
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, TB_METHOD_ROSENBROCK), TB_STATUS_OK);
    def.dt = 1.0 / 240.0;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    const double start = energy(scene);
    double rise = -INFINITY;
    for (int step = 1; step <= 192; ++step) {
        const tb_status status = tb_integrator_advance(integrator, step / 240.0);
        if (status != TB_STATUS_OK) {
            print_error("%s\n", tb_integrator_detail(integrator));
        }
        assert_int_equal(status, TB_STATUS_OK);
        rise = fmax(rise, (energy(scene) - start) / start);
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return rise;
}

/* 40 drops, each checked at every step: the die's energy stays within 1% of its start's (0.25-
 * 0.5 J) above it. The physics allows no rise at all; 1% leaves room for the step's truncation
 * (a scan of 600 such drops outside the tests: the largest rise 1.5 mJ, 0.45%). Before the
 * range check and the plain last halving (src/ode/rosenbrock.c), one of these 40 was thrown off
 * at 128 m/s, which the tunnelling guard refused, and 78 of 500 scanned drops rose by more than
 * 1 mJ, up to 36 J. */
static void test_tumbling_dice_gain_no_energy_at_240_hz(void **state)
{
    (void)state;
    uint64_t seed = 23;
    int risen = 0;
    double worst = -INFINITY;
    for (int drop = 0; drop < DROPS; ++drop) {
        const double rise = largest_rise(&seed);
        if (rise > 0.01) {
            print_message("drop %d: energy rose %.1f%% over its start\n", drop, 100.0 * rise);
            ++risen;
        }
        worst = fmax(worst, rise);
    }
    print_message("largest rise over %d drops: %.3g%% of the start (bound 1%%)\n", DROPS,
                  100.0 * worst);
    assert_int_equal(risen, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tumbling_dice_gain_no_energy_at_240_hz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

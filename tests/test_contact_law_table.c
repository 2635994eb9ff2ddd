/* The contact law's set-up tables (src/contact/contact_law_table.h) against the simulated impact
 * they were made from (contact_law.c): the damping ratio read from the table meets the
 * restitution asked when the impact is simulated, the push duration matches, and both hold
 * between the grid points, where the interpolation is worst (F33). Static builds only: the
 * law's functions are private. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "contact/contact_law.h"
#include "near.h"

#include <math.h>

/* The restitution of the largest damping ratio: the table's lowest. */
static double lowest(void)
{
    return tb__contact_restitution(TB__CONTACT_MAX_DAMPING_RATIO);
}

/* Between the table's 257 grid points (a quarter and three quarters of the way, in ln e), and
 * near 1: the simulated e at the interpolated zeta is within 2e-7 of the e asked. The cubic's
 * own error (spacing^4 times zeta's fourth derivative in ln e) is below 1e-9; what is left is
 * the simulation's: a fixed RK4 step through the kinks at touchdown and release makes e(zeta)
 * continuous but rough at 1e-7, its documented accuracy against the exact law (the bisection
 * the table replaces met that rough curve, not the law, more closely). zeta falls as e rises
 * (the law's damping only takes energy). */
static void test_the_table_s_damping_ratio_meets_the_simulated_restitution(void **state)
{
    (void)state;
    const double low = log(lowest());
    double worst = 0.0, previous = INFINITY;
    for (int k = 0; k < 256; ++k) {
        for (int q = 1; q < 4; q += 2) {
            const double e = exp(low * (1.0 - (k + 0.25 * q) / 256.0));
            const double zeta = tb__contact_damping_ratio(e);
            assert_true(zeta < previous && zeta >= 0.0);
            previous = zeta;
            worst = fmax(worst, fabs(tb__contact_restitution(zeta) - e));
        }
    }
    print_message("largest |e(zeta(e)) - e| between grid points: %.3g\n", worst);
    assert_true(worst <= 2e-7);
    const double near_one[] = {0.999, 0.9999, 1.0 - 1e-6};
    for (int k = 0; k < 3; ++k) {
        assert_near(tb__contact_restitution(tb__contact_damping_ratio(near_one[k])), near_one[k],
                    2e-7);
    }
    assert_true(tb__contact_damping_ratio(1.0) == 0.0);
    assert_true(tb__contact_damping_ratio(lowest()) == TB__CONTACT_MAX_DAMPING_RATIO);
    assert_true(tb__contact_damping_ratio(0.0) == TB__CONTACT_MAX_DAMPING_RATIO);
}

/* The push duration read for e is the simulated one at zeta(e) to within two of the
 * simulation's steps (2e-3 each, in units of 1 / omega): the simulation counts whole steps, so
 * its duration is a staircase that the table's cubic rounds off. */
static void test_the_table_s_push_duration_matches_the_simulated_impact(void **state)
{
    (void)state;
    const double low = log(lowest());
    double worst = 0.0;
    for (int k = 0; k < 256; k += 3) {
        const double e = exp(low * (1.0 - (k + 0.5) / 256.0));
        const double simulated = tb__contact_push_duration(tb__contact_damping_ratio(e));
        worst = fmax(worst, fabs(tb__contact_push_duration_for(e) - simulated));
    }
    print_message("largest push duration difference: %.3g / omega\n", worst);
    assert_true(worst <= 4e-3);
    assert_near(tb__contact_push_duration_for(1.0), 3.14159, 4e-3); /* half a period: pi */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_table_s_damping_ratio_meets_the_simulated_restitution),
        cmocka_unit_test(test_the_table_s_push_duration_matches_the_simulated_impact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

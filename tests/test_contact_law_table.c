/* The contact law's set-up tables (src/contact/contact_law_table.h) against the simulated impact
 * they were made from (contact_law.c): the damping ratio they speed up is the plain bisection's,
 * the table's estimate is close enough for that, and the push duration matches, between the
 * grid points too, where the interpolation is worst (F33). Static builds only: the
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

/* The bisection the set-up did before the table: 30 halvings of [0, 3] on the simulated e. */
static double bisection(double e)
{
    double low = 0.0, high = TB__CONTACT_MAX_DAMPING_RATIO;
    if (!(e > tb__contact_restitution(high))) {
        return high;
    }
    for (int k = 0; k < 30; ++k) {
        const double mid = 0.5 * (low + high);
        if (tb__contact_restitution(mid) > e) {
            low = mid;
        } else {
            high = mid;
        }
    }
    return 0.5 * (low + high);
}

/* At 97 restitutions spread evenly in ln e over the table's range (off its grid points, where
 * the cubic is worst) and near 1: tb__contact_damping_ratio is the plain bisection's answer bit
 * for bit, so runs are the ones before the table; the table's own estimate is within 1e-6 of
 * it, a tenth of the margin inside which the replay simulates (3.3e-7 measured over 600 points,
 * at low e where e(zeta) flattens). zeta falls as e rises (damping only takes energy). */
static void test_the_damping_ratio_is_the_bisection_s_bit_for_bit(void **state)
{
    (void)state;
    const double low = log(lowest());
    double worst = 0.0, previous = INFINITY;
    for (int k = 0; k < 100; ++k) {
        const double e = k < 97 ? exp(low * (1.0 - (k + 0.37) / 97.0)) : 1.0 - pow(10.0, 94 - k);
        const double zeta = tb__contact_damping_ratio(e), exact = bisection(e);
        assert_true(zeta == exact);
        assert_true(zeta < previous && zeta >= 0.0);
        previous = zeta;
        worst = fmax(worst, fabs(tb__contact_damping_ratio_estimate(e) - exact));
    }
    print_message("largest |table estimate - bisection| in zeta: %.3g\n", worst);
    assert_true(worst <= 1e-6);
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
        cmocka_unit_test(test_the_damping_ratio_is_the_bisection_s_bit_for_bit),
        cmocka_unit_test(test_the_table_s_push_duration_matches_the_simulated_impact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

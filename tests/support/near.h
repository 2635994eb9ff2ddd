/* assert_near(actual, expected, tolerance): |actual - expected| <= tolerance, reporting all
 * three on failure at the caller's line (CMocka 1.1.5 has no floating-point assertion).
 * Include after <cmocka.h>. NaN never passes. */
#ifndef TUMBLE_TEST_NEAR_H
#define TUMBLE_TEST_NEAR_H

#include <math.h>

static inline void tb_test_assert_near(double actual, double expected, double tolerance,
                                       const char *expression, const char *file, int line)
{
    if (!(fabs(actual - expected) <= tolerance)) {
        print_error("%s = %.17g, expected %.17g within %g (off by %.3g)\n", expression, actual,
                    expected, tolerance, fabs(actual - expected));
        _fail(file, line);
    }
}

#define assert_near(actual, expected, tolerance)                                                   \
    tb_test_assert_near((actual), (expected), (tolerance), #actual, __FILE__, __LINE__)

#endif

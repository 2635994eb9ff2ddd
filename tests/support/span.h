/* How long a physics test runs. The memcheck ctests run each suite again under valgrind, where a
 * step costs about 40 times the CPU; they set TUMBLE_TEST_SHORT=1 in the environment, and the
 * suites whose full span would cost tens of seconds there run the same physics over a shorter
 * span, over which their assertions hold as well (each caller says why). */
#ifndef TUMBLE_TEST_SPAN_H
#define TUMBLE_TEST_SPAN_H

#include <stdbool.h>

/* True when TUMBLE_TEST_SHORT is set to anything but "" or "0". */
bool tb_test_short(void);

/* `full`, or `short_span` when tb_test_short(). */
double tb_test_span(double full, double short_span);

#endif

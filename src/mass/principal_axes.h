/* Private: the only door to GSL. Set-up linear algebra on 3x3 inertia tensors. */
#ifndef TUMBLE_PRINCIPAL_AXES_H
#define TUMBLE_PRINCIPAL_AXES_H

#include "tumble/status.h"

/* Validates a row-major inertia tensor (finite, symmetric within 1e-9 relative, positive
 * definite, moments within [TB_MOMENT_MIN, TB_MOMENT_MAX], triangle inequality) and returns
 * its principal moments and the unit quaternion (|q| = 1 to round-off, a proper rotation)
 * taking principal-frame vectors to the tensor's frame. A tensor already diagonal (off-diagonal
 * entries below DBL_EPSILON^2 of the largest) keeps its axes (identity); otherwise moments are
 * ascending. Returns in bounded time for every input. what names the tensor in messages. */
tb_status tb__principal_axes(const double inertia[9], const char *what, double out_moments[3],
                             double out_rotation[4], tb_error *error);

#endif

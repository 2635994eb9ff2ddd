/* Private: the only door to GSL. Set-up linear algebra on 3x3 inertia tensors. */
#ifndef TUMBLE_PRINCIPAL_AXES_H
#define TUMBLE_PRINCIPAL_AXES_H

#include "tumble/status.h"

/* Validates a row-major inertia tensor (finite, symmetric within 1e-9 relative, positive
 * definite, triangle inequality) and returns its principal moments and the unit quaternion
 * taking principal-frame vectors to the tensor's frame. A tensor already diagonal keeps its
 * axes (identity); otherwise moments are ascending. what names the tensor in messages. */
tb_status tb__principal_axes(const double inertia[9], const char *what, double out_moments[3],
                             double out_rotation[4], tb_error *error);

#endif

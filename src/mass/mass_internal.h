/* Private helpers shared by the mass-property and scene sources. */
#ifndef TUMBLE_MASS_INTERNAL_H
#define TUMBLE_MASS_INTERNAL_H

#include "tumble/status.h"

#include <stdio.h>

/* value finite and > 0, else an error naming what. */
tb_status tb__check_positive(double value, const char *what, tb_error *error);

/* q finite with |q| within 1e-4 of 1, else an error naming what. */
tb_status tb__check_unit_quaternion(const double q[4], const char *what, tb_error *error);

/* I += m (|d|^2 Id - d d^T): the parallel-axis term of mass m at offset d. */
void tb__add_point_inertia(double I[9], double m, const double d[3]);

#endif

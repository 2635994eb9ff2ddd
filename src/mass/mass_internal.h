/* Private helpers shared by the mass-property and scene sources. */
#ifndef TUMBLE_MASS_INTERNAL_H
#define TUMBLE_MASS_INTERNAL_H

#include "tumble/mass.h"
#include "tumble/status.h"

#include <stdio.h>

/* value finite and > 0, else an error naming what. */
tb_status tb__check_positive(double value, const char *what, tb_error *error);

/* mass finite and in [TB_MASS_MIN, TB_MASS_MAX] kg, else an error naming what. */
tb_status tb__check_mass(double mass, const char *what, tb_error *error);

/* The mass from mode and value (a mass, or a density times volume, m^3), checked to lie in
 * [TB_MASS_MIN, TB_MASS_MAX]; errors name the mass or the density. */
tb_status tb__resolve_mass(tb_mass_mode mode, double value, double volume, double *mass,
                           tb_error *error);

/* q finite with |q| within 1e-4 of 1, else an error naming what. */
tb_status tb__check_unit_quaternion(const double q[4], const char *what, tb_error *error);

/* I += m (|d|^2 Id - d d^T): the parallel-axis term of mass m at offset d. */
void tb__add_point_inertia(double I[9], double m, const double d[3]);

#endif

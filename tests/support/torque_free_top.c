#include "torque_free_top.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_sf_ellint.h>
#include <gsl/gsl_sf_elljac.h>

#include <math.h>

int torque_free_top_init(torque_free_top *top, const double I[3], double w1, double w3)
{
    if (!(0 < I[0] && I[0] < I[1] && I[1] < I[2]) || !(w1 > 0 && w3 > 0)) {
        return -1;
    }
    /* 2E and L^2 from the initial body-frame angular velocity (w1, 0, w3). */
    const double two_E = I[0] * w1 * w1 + I[2] * w3 * w3;
    const double L2 = I[0] * I[0] * w1 * w1 + I[2] * I[2] * w3 * w3;
    const double I1 = I[0], I2 = I[1], I3 = I[2];
    if (L2 > two_E * I2) {
        /* L&L (37.10): Omega = (A1 cn, A2 sn, A3 dn). */
        top->near_axis = 3;
        top->amplitude[0] = sqrt((two_E * I3 - L2) / (I1 * (I3 - I1)));
        top->amplitude[1] = sqrt((two_E * I3 - L2) / (I2 * (I3 - I2)));
        top->amplitude[2] = sqrt((L2 - two_E * I1) / (I3 * (I3 - I1)));
        top->rate = sqrt((I3 - I2) * (L2 - two_E * I1) / (I1 * I2 * I3));
        top->m = (I2 - I1) * (two_E * I3 - L2) / ((I3 - I2) * (L2 - two_E * I1));
    } else if (L2 < two_E * I2) {
        /* The same with the roles of axes 1 and 3 exchanged: Omega = (A1 dn, A2 sn, A3 cn). */
        top->near_axis = 1;
        top->amplitude[0] = sqrt((two_E * I3 - L2) / (I1 * (I3 - I1)));
        top->amplitude[1] = sqrt((L2 - two_E * I1) / (I2 * (I2 - I1)));
        top->amplitude[2] = sqrt((L2 - two_E * I1) / (I3 * (I3 - I1)));
        top->rate = sqrt((I2 - I1) * (two_E * I3 - L2) / (I1 * I2 * I3));
        top->m = (I3 - I2) * (L2 - two_E * I1) / ((I2 - I1) * (two_E * I3 - L2));
    } else {
        return -1;
    }
    return 0;
}

void torque_free_top_omega(const torque_free_top *top, double t, double omega[3])
{
    double sn, cn, dn;
    gsl_sf_elljac_e(top->rate * t, top->m, &sn, &cn, &dn);
    if (top->near_axis == 3) {
        omega[0] = top->amplitude[0] * cn;
        omega[1] = top->amplitude[1] * sn;
        omega[2] = top->amplitude[2] * dn;
    } else {
        omega[0] = top->amplitude[0] * dn;
        omega[1] = top->amplitude[1] * sn;
        omega[2] = top->amplitude[2] * cn;
    }
}

double torque_free_top_period(const torque_free_top *top)
{
    /* GSL's complete elliptic integral takes the modulus k = sqrt(m). */
    return 4.0 * gsl_sf_ellint_Kcomp(sqrt(top->m), GSL_PREC_DOUBLE) / top->rate;
}

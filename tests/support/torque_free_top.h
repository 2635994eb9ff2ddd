/* The exact motion of a torque-free asymmetric rigid body (Euler's equations with
 * I1 < I2 < I3) in Jacobi elliptic functions, after Landau & Lifshitz, Mechanics, par. 37.
 * Independent of tumble: it uses only GSL's gsl_sf_elljac_e. */
#ifndef TUMBLE_TEST_TORQUE_FREE_TOP_H
#define TUMBLE_TEST_TORQUE_FREE_TOP_H

typedef struct torque_free_top {
    double amplitude[3]; /* of the (cn, sn, dn) or (dn, sn, cn) factors, rad/s */
    double rate;         /* tau = rate * t, 1/s */
    double m;            /* parameter k^2 of the elliptic functions */
    int near_axis;       /* 3: L^2 > 2 E I2 (rotation about the I3 axis); 1: L^2 < 2 E I2 */
} torque_free_top;

/* Sets up the solution whose body-frame angular velocity at t = 0 is
 * (omega1, 0, omega3) with omega1, omega3 > 0. Returns 0, or -1 if the moments are not
 * strictly ascending, the inputs are not positive, or L^2 = 2 E I2 (the separatrix). */
int torque_free_top_init(torque_free_top *top, const double moments[3], double omega1,
                         double omega3);

/* Body-frame angular velocity at time t, rad/s. */
void torque_free_top_omega(const torque_free_top *top, double t, double omega[3]);

/* The period of the body-frame angular velocity, 4 K(m) / rate (s). */
double torque_free_top_period(const torque_free_top *top);

#endif

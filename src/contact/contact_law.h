/* Private: the compliant normal contact law, shared by ground planes and contact between
 * bodies. A contact of effective mass m (kg) and natural rate omega (rad/s) pushes with
 *
 *     N = max(0, m omega (omega d + 2 zeta d' g)),   g = omega d / (omega d + beta |d'|)
 *
 * for penetration depth d >= 0 (m) and its rate d' (m/s, positive going in): a linear spring and
 * a dashpot that never pulls. Two properties decide the form:
 *   - N is homogeneous of degree 1 in (d, d'): an impact at speed lambda v is the one at v
 *     scaled by lambda in depth and rate on the same time scale, so the restitution does not
 *     depend on the impact speed (Hunt and Crossley's d^n (1 + a d') does);
 *   - the dashpot fades in as g rises from 0 at touchdown (beta = TB__CONTACT_DASHPOT_ONSET:
 *     half strength at d = beta |d'| / omega, a sixth of the deepest sinking or less), so N is
 *     continuous: the plain max(0, k d + c d') jumps to c v at touchdown, which a fixed step
 *     straddles with an error of first order in h omega (22 % in e at h omega = 0.4 for e = 0.2;
 *     with the fade 3 %, falling as h^2).
 * e(zeta) is computed at set-up from the dimensionless impact and inverted by bisection, so
 * the user's restitution is met. */
#ifndef TUMBLE_CONTACT_LAW_H
#define TUMBLE_CONTACT_LAW_H

#include <math.h>

#define TB__CONTACT_DASHPOT_ONSET 0.5

/* The damping ratio the law is capped at, with restitution 0.062: more damping would shorten
 * the explicit methods' step (the fast decay 2 zeta omega) for a bounce of 0.4 % of the drop
 * height or less. */
#define TB__CONTACT_MAX_DAMPING_RATIO 3.0

/* Restitution of the law at damping ratio zeta >= 0, in (0, 1] (to about 1e-7). */
double tb__contact_restitution(double zeta);

/* How long the law's force first acts through an impact (N > 0 from touchdown until the
 * surface or the dashpot first lets go), in units of 1 / omega, at damping ratio zeta >= 0:
 * about pi for zeta = 0, less with damping; the same at every impact speed (the law is
 * homogeneous of degree 1). */
double tb__contact_push_duration(double zeta);

/* The damping ratio whose restitution is e, for e in [0, 1]: 0 for e = 1,
 * TB__CONTACT_MAX_DAMPING_RATIO for e at or below that ratio's restitution. */
double tb__contact_damping_ratio(double restitution);

/* The normal force magnitude (N) of the law: 0 for depth <= 0 or when the dashpot would pull. */
static inline double tb__contact_normal_force(double mass, double omega, double zeta, double depth,
                                              double depth_rate)
{
    if (!(depth > 0.0)) {
        return 0.0;
    }
    const double spring = omega * depth;
    const double fade = spring / (spring + TB__CONTACT_DASHPOT_ONSET * fabs(depth_rate));
    const double force = mass * omega * (spring + 2.0 * zeta * depth_rate * fade);
    return force > 0.0 ? force : 0.0;
}

#endif

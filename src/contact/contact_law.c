/* The restitution of the clamped linear spring-dashpot and its inverse. In units where omega = 1
 * and the approach speed is 1 the depth obeys d'' + 2 zeta d' + d = 0 from d = 0, d' = 1, and the
 * contact ends at the first t > 0 where the force d + 2 zeta d' is zero; e = -d'(t). */
#include "contact/contact_law.h"

#include <math.h>

/* zeta < 1: d = e^(-zeta t) sin(s t) / s with s = sqrt(1 - zeta^2). The force is zero where
 * A sin(phi) + B cos(phi) = 0, phi = s t, A = (1 - 2 zeta^2) / s, B = 2 zeta: phi = atan2(B, -A),
 * in (0, pi]. */
static double underdamped(double zeta)
{
    const double s = sqrt(1.0 - zeta * zeta);
    const double phi = atan2(2.0 * zeta, -(1.0 - 2.0 * zeta * zeta) / s);
    return exp(-zeta * phi / s) * (zeta / s * sin(phi) - cos(phi));
}

/* zeta > 1: d = (e^(l1 t) - e^(l2 t)) / (2 r), l1,2 = -zeta +- r, r = sqrt(zeta^2 - 1). The force
 * e^(l1 t) (1 + 2 zeta l1) - e^(l2 t) (1 + 2 zeta l2) is zero at
 * t = ln((1 + 2 zeta l2) / (1 + 2 zeta l1)) / (2 r); both factors are negative. */
static double overdamped(double zeta)
{
    const double r = sqrt(zeta * zeta - 1.0), l1 = -zeta + r, l2 = -zeta - r;
    const double t = log((2.0 * zeta * zeta + 2.0 * zeta * r - 1.0) /
                         (2.0 * zeta * zeta - 2.0 * zeta * r - 1.0)) /
                     (2.0 * r);
    return -(l1 * exp(l1 * t) - l2 * exp(l2 * t)) / (2.0 * r);
}

double tb__contact_restitution(double zeta)
{
    /* near zeta = 1 both forms lose digits to the vanishing s or r; the critical case
     * d = t e^-t ends at t = 2 with e = e^-2, and e(zeta) is smooth through it */
    if (fabs(zeta - 1.0) < 1e-6) {
        return exp(-2.0);
    }
    return zeta < 1.0 ? underdamped(zeta) : overdamped(zeta);
}

double tb__contact_damping_ratio(double restitution)
{
    if (!(restitution < 1.0)) {
        return 0.0;
    }
    double low = 0.0, high = TB__CONTACT_MAX_DAMPING_RATIO;
    if (!(restitution > tb__contact_restitution(high))) {
        return high;
    }
    /* e(zeta) decreases strictly: keep e(low) > e >= e(high) */
    for (int k = 0; k < 200 && high - low > 1e-15; ++k) {
        const double mid = 0.5 * (low + high);
        if (tb__contact_restitution(mid) > restitution) {
            low = mid;
        } else {
            high = mid;
        }
    }
    return 0.5 * (low + high);
}

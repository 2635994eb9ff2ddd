/* The restitution of the contact law and its inverse. In units where omega = 1 and m = 1 an
 * impact at speed 1 is d'' = -N(d, d') from d = 0, d' = 1; the contact is over when d is back
 * at 0 (the force, clamped at 0, may have let go before: the speed is then constant), and
 * e = -d'. The law has no closed form; RK4 with the step below resolves it: the force has a
 * kink at touchdown and where the clamp lets go, so the error falls as h^2 (measured: 1e-7 at
 * this step against a step 4 times shorter). */
#include "contact/contact_law.h"

#include <stdbool.h>

#define TB__SETUP_STEP 2e-3
/* No impact lasts longer in units of 1 / omega: the slow overdamped mode at zeta = 3 decays at
 * 0.17, and the contact ends before d has decayed e^-3 */
#define TB__SETUP_DURATION 60.0

static void rates(double zeta, const double s[2], double out[2])
{
    out[0] = s[1];
    out[1] = -tb__contact_normal_force(1.0, 1.0, zeta, s[0], s[1]);
}

/* The dimensionless impact from d = 0, d' = 1 until it is out of the contact or, with
 * first_release, until the force first lets go (the dashpot may let go inside the surface and
 * the spring take hold again); returns the time. */
static double impact(double zeta, bool first_release, double s[2])
{
    double k[4][2], t[2], time = 0.0;
    const double h = TB__SETUP_STEP;
    for (; time < TB__SETUP_DURATION; time += h) {
        rates(zeta, s, k[0]);
        for (int stage = 1; stage < 4; ++stage) {
            const double c = stage == 3 ? h : 0.5 * h;
            t[0] = s[0] + c * k[stage - 1][0];
            t[1] = s[1] + c * k[stage - 1][1];
            rates(zeta, t, k[stage]);
        }
        for (int i = 0; i < 2; ++i) {
            s[i] += h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
        }
        if (s[0] <= 0.0 && s[1] < 0.0) {
            break; /* out of the contact, where no force acts */
        }
        if (first_release && !(tb__contact_normal_force(1.0, 1.0, zeta, s[0], s[1]) > 0.0)) {
            break;
        }
    }
    return time + h;
}

double tb__contact_restitution(double zeta)
{
    double s[2] = {0.0, 1.0};
    impact(zeta, false, s);
    return -s[1];
}

double tb__contact_push_duration(double zeta)
{
    double s[2] = {0.0, 1.0};
    return impact(zeta, true, s);
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
    /* e(zeta) decreases: keep e(low) > e >= e(high); 30 halvings leave 3e-9 in zeta */
    for (int k = 0; k < 30; ++k) {
        const double mid = 0.5 * (low + high);
        if (tb__contact_restitution(mid) > restitution) {
            low = mid;
        } else {
            high = mid;
        }
    }
    return 0.5 * (low + high);
}

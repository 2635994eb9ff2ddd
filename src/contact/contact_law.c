/* The restitution of the contact law and its inverse. In units where omega = 1 and m = 1 an
 * impact at speed 1 is d'' = -N(d, d') from d = 0, d' = 1; the contact is over when d is back
 * at 0 (the force, clamped at 0, may have let go before: the speed is then constant), and
 * e = -d'. The law has no closed form; RK4 with the step below resolves it: the force has a
 * kink at touchdown and where the clamp lets go, so the error falls as h^2 (measured: 1e-7 at
 * this step against a step 4 times shorter). */
#include "contact/contact_law.h"

#include <stdbool.h>

/* Restitutions in the tables of contact_law_table.h (generated from the simulation below by
 * scripts/contact_law_table.c; test_contact_law_table checks them against it). */
#define TB__LAW_TABLE_SIZE 257
#ifndef TB__LAW_TABLE_GENERATOR
#include "contact/contact_law_table.h"
#endif

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

#ifndef TB__LAW_TABLE_GENERATOR
/* A table's value at restitution e in [TB__LAW_LOWEST_RESTITUTION, 1]: the cubic in ln e
 * through the four nearest grid points (the outer ones at the ends). In ln e the damping ratio
 * is nearly linear (-ln e / pi for a light linear dashpot), where in e it turns steeply near the
 * lowest restitution. */
static double interpolate(const double table[TB__LAW_TABLE_SIZE], double e)
{
    const double lowest = log(TB__LAW_LOWEST_RESTITUTION);
    const double x = (log(e) - lowest) / (-lowest) * (TB__LAW_TABLE_SIZE - 1);
    int i = (int)floor(x) - 1;
    i = i < 0 ? 0 : i > TB__LAW_TABLE_SIZE - 4 ? TB__LAW_TABLE_SIZE - 4 : i;
    const double u = x - i; /* from grid point i, in [0, 3] */
    const double w[4] = {-(u - 1.0) * (u - 2.0) * (u - 3.0) / 6.0, u * (u - 2.0) * (u - 3.0) / 2.0,
                         -u * (u - 1.0) * (u - 3.0) / 2.0, u * (u - 1.0) * (u - 2.0) / 6.0};
    return w[0] * table[i] + w[1] * table[i + 1] + w[2] * table[i + 2] + w[3] * table[i + 3];
}

/* The bisection of e(zeta) = restitution over [0, TB__CONTACT_MAX_DAMPING_RATIO], 30 halvings
 * (3e-9 in zeta), replayed: a midpoint farther than TB__LAW_ZETA_MARGIN from the table's zeta
 * lies on the side the table says (its zeta is within 3.3e-7 of the bisection's, measured over
 * the range, test_contact_law_table), so only the last dozen halvings simulate an impact. The
 * answer is the full bisection's, bit for bit: runs do not move by the table's rounding (a
 * chaotic pile of dice does, and a 3e-8 change in zeta did). */
#define TB__LAW_ZETA_MARGIN 1e-5

double tb__contact_damping_ratio(double restitution)
{
    if (!(restitution < 1.0)) {
        return 0.0;
    }
    if (!(restitution > TB__LAW_LOWEST_RESTITUTION)) {
        return TB__CONTACT_MAX_DAMPING_RATIO;
    }
    const double guess = tb__contact_damping_ratio_estimate(restitution);
    double low = 0.0, high = TB__CONTACT_MAX_DAMPING_RATIO;
    for (int k = 0; k < 30; ++k) {
        const double mid = 0.5 * (low + high);
        /* e(zeta) falls: mid is below the root where e(mid) is above the restitution */
        const bool below = fabs(mid - guess) > TB__LAW_ZETA_MARGIN
                               ? mid < guess
                               : tb__contact_restitution(mid) > restitution;
        low = below ? mid : low;
        high = below ? high : mid;
    }
    return 0.5 * (low + high);
}

double tb__contact_damping_ratio_estimate(double restitution)
{
    const double e = fmax(TB__LAW_LOWEST_RESTITUTION, fmin(1.0, restitution));
    return interpolate(tb__law_zeta, e);
}

double tb__contact_push_duration_for(double restitution)
{
    const double e = fmax(TB__LAW_LOWEST_RESTITUTION, fmin(1.0, restitution));
    return interpolate(tb__law_push, e);
}
#endif

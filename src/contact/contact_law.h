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
 * e(zeta) is the dimensionless impact's, simulated (tb__contact_restitution), and inverted by
 * bisection so that the user's restitution is met; constant tables of it (contact_law_table.h)
 * decide the bisection's early halvings and give the push duration, so a set-up simulates a
 * dozen impacts, not 32. */
#ifndef TUMBLE_CONTACT_LAW_H
#define TUMBLE_CONTACT_LAW_H

#include <math.h>

#define TB__CONTACT_DASHPOT_ONSET 0.5

/* Rate (1/s) at which a lifted point's bristles relax (the stick-anchor friction of
 * ground planes and of contact between bodies): fast against motion, slow enough for
 * RK4 at 60 steps per second (h * rate = 1.7 < 2.78). */
#define TB__BRISTLE_RELEASE_RATE 100.0
/* Rate (1/s) at which a deflection beyond the static cone relaxes back to it, so that in a slide
 * at v the excess is v / rate and rate * excess is the slip speed; slow enough for RK4 at 240
 * steps per second (h * 400 = 1.7 < 2.78). The friction force is capped at mu N whatever the
 * excess, so the rate only sets how long a slide's excess takes to fade once the slide stops. */
#define TB__BRISTLE_MAX_RATE 400.0
/* Below this tangential speed (m/s) the memoryless friction between bodies (for a point without
 * a friction slot) fades linearly to zero: the regularisation. It creeps at about this speed
 * times load / (mu_s N), which must stay well below the Stribeck velocity: at 1 cm/s a box on a
 * box at 25 degrees (mu_s 0.6, mu_k 0.4) crept fast enough to lower mu to mu_k and slid away. */
#define TB__FRICTION_REGULARISATION 1e-3
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
 * TB__CONTACT_MAX_DAMPING_RATIO for e at or below that ratio's restitution; otherwise the
 * bisection of the simulated e(zeta) to 3e-9, with the halvings far from the table's estimate
 * decided by it (about a dozen impacts simulated instead of 31). */
double tb__contact_damping_ratio(double restitution);

/* The table's estimate of that damping ratio (contact_law_table.h, a cubic in ln e): within
 * 3.3e-7 of it, no impact simulated. */
double tb__contact_damping_ratio_estimate(double restitution);

/* tb__contact_push_duration at tb__contact_damping_ratio(restitution), from the same table. */
double tb__contact_push_duration_for(double restitution);

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

/* The law at one contact point (N) of stiffness k (N/m) whose dashpot pushes an effective mass
 * m (kg): tb__contact_normal_force at mass m and rate omega = sqrt(k / m), that is
 *
 *     N = max(0, k d + 2 zeta sqrt(k m) d' g),   g = d / (d + beta |d'| sqrt(m / k)),
 *
 * written so that m -> 0 (a point that carries no share of the load yet) is the spring alone,
 * with no overflow. With m the mass the point's motion along the normal really has, the point
 * is the law's oscillator and keeps its restitution (effect_ground.c, effect_contact.c). */
static inline double tb__contact_point_force(double stiffness, double mass, double zeta,
                                             double depth, double depth_rate)
{
    if (!(depth > 0.0)) {
        return 0.0;
    }
    const double fade =
        depth / (depth + TB__CONTACT_DASHPOT_ONSET * fabs(depth_rate) * sqrt(mass / stiffness));
    const double force =
        stiffness * depth + 2.0 * zeta * sqrt(stiffness * mass) * depth_rate * fade;
    return force > 0.0 ? force : 0.0;
}

/* The derivatives of tb__contact_point_force against the depth (N/m, out[0]) and its rate
 * (N s/m, out[1]), the effective mass m held fixed: with D = d + beta |d'| s, s = sqrt(m / k),
 * g = d / D and c = 2 zeta sqrt(k m),
 *     dN/dd = k + c d' beta |d'| s / D^2,   dN/dd' = c g^2
 * (d(d' g)/dd' = g - d beta s |d'| / D^2 = g^2); both 0 where the force is (no touch, or the
 * dashpot would pull). */
static inline void tb__contact_point_force_derivatives(double stiffness, double mass, double zeta,
                                                       double depth, double depth_rate,
                                                       double out[2])
{
    out[0] = out[1] = 0.0;
    if (!(tb__contact_point_force(stiffness, mass, zeta, depth, depth_rate) > 0.0)) {
        return;
    }
    const double s = sqrt(mass / stiffness);
    const double D = depth + TB__CONTACT_DASHPOT_ONSET * fabs(depth_rate) * s;
    const double c = 2.0 * zeta * sqrt(stiffness * mass), g = depth / D;
    out[0] =
        stiffness + c * depth_rate * TB__CONTACT_DASHPOT_ONSET * fabs(depth_rate) * s / (D * D);
    out[1] = c * g * g;
}

#endif

/* Private: the compliant normal contact law, shared by ground planes and contact between
 * bodies. A contact of effective mass m (kg) and natural rate omega (rad/s) pushes with
 *
 *     N = max(0, m (omega^2 d + 2 zeta omega d'))
 *
 * for penetration depth d >= 0 (m) and its rate d' (m/s, positive going in): a linear spring and
 * dashpot that never pulls. Its restitution does not depend on the impact speed, and with the
 * clamp (the contact ends when the force reaches zero, before d returns to 0) it has a closed
 * form e(zeta) (Schwager and Poschel, "Coefficient of restitution and linear-dashpot model
 * revisited", Granular Matter 9, 2007), which the set-up inverts so that the user's e is met. */
#ifndef TUMBLE_CONTACT_LAW_H
#define TUMBLE_CONTACT_LAW_H

/* The damping ratio the law is capped at: e(2) = 0.0478. A smaller restitution asks for more
 * damping, whose fast decay 2 zeta omega would shorten the explicit methods' step further for
 * a difference (a bounce of 0.2 % of the drop height or less) no one sees. */
#define TB__CONTACT_MAX_DAMPING_RATIO 2.0

/* Restitution of the clamped law at damping ratio zeta >= 0 (exact, in (0, 1]). */
double tb__contact_restitution(double zeta);

/* The damping ratio whose restitution is e (bisection on the closed form to round-off), for e in
 * [0, 1]: 0 for e = 1, TB__CONTACT_MAX_DAMPING_RATIO for e <= its restitution. */
double tb__contact_damping_ratio(double restitution);

/* The normal force magnitude (N) of the law: 0 for depth <= 0 or when the dashpot would pull. */
static inline double tb__contact_normal_force(double mass, double omega, double zeta, double depth,
                                              double depth_rate)
{
    if (!(depth > 0.0)) {
        return 0.0;
    }
    const double force = mass * omega * (omega * depth + 2.0 * zeta * depth_rate);
    return force > 0.0 ? force : 0.0;
}

#endif

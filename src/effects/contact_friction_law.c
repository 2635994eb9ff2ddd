/* The friction law at a touching point between bodies (contact_friction.h): the stick anchor of
 * a point that holds a slot, the memoryless regularised law of one that does not. */
#include "effects/contact_friction.h"

#include "math/tb_math.h"

#include <math.h>

/* mu at slip speed w: from mu_s at rest to mu_k (Stribeck, over stribeck_velocity). */
static double stribeck(const tb__contact_params *contact, double slip)
{
    const double ratio = slip / contact->stribeck_velocity;
    /* exp(-0) is 1 exactly: an anchor inside its cone (at rest, most of them) skips the call */
    return contact->kinetic_friction + (contact->static_friction - contact->kinetic_friction) *
                                           (ratio == 0.0 ? 1.0 : exp(-ratio * ratio));
}

/* The memoryless law: -mu(|v_t|) N v_t / sqrt(|v_t|^2 + v_reg^2), v_reg = slip_velocity. */
static void slip_friction(const tb__contact_params *contact, double N, const double v_t[3],
                          double friction[3])
{
    const double speed = tb__v3_norm(v_t);
    const double scale = stribeck(contact, speed) * N /
                         sqrt(speed * speed + contact->slip_velocity * contact->slip_velocity);
    tb__v3_set(friction, -scale * v_t[0], -scale * v_t[1], -scale * v_t[2]);
}

/* The stick anchor in world vectors (the ground's law, effect_ground.c bristles(), with z in 3D:
 * its part along n, which only the turning of n relative to A gives it, relaxes at the release
 * rate and pushes nothing). */
static void anchor_friction(const tb__contact_params *contact, double stiffness, double damping,
                            double N, const double n[3], const double v_t[3], const double z[3],
                            double dz[3], double friction[3])
{
    const double along = tb__v3_dot(z, n);
    double z_t[3], trial[3];
    for (int k = 0; k < 3; ++k) {
        z_t[k] = z[k] - along * n[k];
    }
    const double deflection = tb__v3_norm(z_t);
    const double cone = contact->static_friction * N / stiffness;
    const double excess = deflection > cone ? deflection - cone : 0.0;
    const double mu = stribeck(contact, TB__BRISTLE_MAX_RATE * excess);
    for (int k = 0; k < 3; ++k) {
        trial[k] = -(stiffness * z_t[k] + damping * v_t[k]);
        dz[k] = v_t[k] - TB__BRISTLE_RELEASE_RATE * along * n[k] -
                (excess > 0.0 ? TB__BRISTLE_MAX_RATE * excess * z_t[k] / deflection : 0.0);
    }
    const double magnitude = tb__v3_norm(trial);
    const double scale = magnitude > mu * N ? mu * N / magnitude : 1.0;
    tb__v3_set(friction, scale * trial[0], scale * trial[1], scale * trial[2]);
}

void tb__friction_force(const tb__contact_params *contact, double stiffness, double damping,
                        double N, const double n[3], const double v_t[3], const double q_a[4],
                        const double *z, double *dz, double friction[3])
{
    if (z == NULL) {
        slip_friction(contact, N, v_t, friction);
        return;
    }
    if (!(contact->static_friction > 0.0)) { /* frictionless: z relaxes (relax_all) */
        tb__v3_set(friction, 0.0, 0.0, 0.0);
        return;
    }
    double z_world[3], dz_world[3];
    tb__q_rotate(z_world, q_a, z);
    anchor_friction(contact, stiffness, damping, N, n, v_t, z_world, dz_world, friction);
    tb__q_rotate_inverse(dz, q_a, dz_world);
}

/* The contact's analytic rows of the scene Jacobian (tb__effect_ops.jacobian): one pass over the
 * touching pairs as apply_contact makes (effect_contact.c), each touching point's normal law and
 * friction differentiated at its own depth, rate, tangential velocity and anchor
 * (contact_law.h, friction_jacobian.h), chained to both bodies' states by
 * tb__jacobian_add_point. Held fixed (the approximations of scene/jacobian_rows.h and
 * friction_jacobian.h): the manifold's points and normal on the bodies, each point's effective
 * masses and share (so the stiffness and both dashpots), and which slot a point holds. The
 * anchor's turn with body A is in (tb__anchor_turn_rows). */
#include "effects/effect_contact.h"

#include "contact/contact_law.h"
#include "contact/contact_pairs.h"
#include "effects/contact_friction.h"
#include "effects/friction_jacobian.h"
#include "math/tb_math.h"

/* The friction law's constants of the contact. */
static tb__friction_law friction_law(const tb__contact_params *contact)
{
    return (tb__friction_law){contact->static_friction, contact->kinetic_friction,
                              contact->stribeck_velocity, contact->slip_velocity};
}

/* The point's friction (the anchor of slot, the memoryless law without one, none when
 * frictionless) and its normal law into p's local rows. */
static void friction_rows(const tb__effect *effect, const tb__pair_motion *m, const double n[3],
                          double N, const double dN[2], const double tangent[3], double stiffness,
                          double damping, size_t slot, const double *y, tb__point_jacobian *p)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    const tb__friction_law law = friction_law(contact);
    tb__friction_jacobian fr;
    const tb__friction_jacobian *friction = &fr;
    double T[3][3] = {{0.0}}, z_world[3] = {0.0, 0.0, 0.0};
    size_t count = 0;
    if (slot == TB__NO_SLOT) {
        tb__slip_jacobian(&law, N, tangent, &fr);
    } else if (contact->static_friction > 0.0) { /* z in A's frame: world z = R_a z */
        p->state_first = effect->state_offset + TB__FRICTION_SLOT_STATES * slot;
        double R[9];
        tb__q_to_matrix_any(R, m->body[0]->q);
        tb__q_rotate(z_world, m->body[0]->q, y + p->state_first);
        for (int a = 0; a < 9; ++a) {
            T[a / 3][a % 3] = R[a];
        }
        tb__anchor_jacobian(&law, stiffness, damping, N, n, tangent, z_world, &fr);
        count = TB__FRICTION_SLOT_STATES;
    } else {
        friction = NULL; /* frictionless: the held slot relaxes */
    }
    tb__contact_point_rows(n, dN[0], dN[1], friction, &T[0][0], count, p);
    if (count > 0) { /* the anchor turns with A */
        tb__anchor_turn_rows(&fr, &T[0][0], z_world, p);
    }
}

/* Point j of pair holding slot `slot` (TB__NO_SLOT: none), as point_load (effect_contact.c). */
static void point_rows(const tb__effect *effect, const tb_scene *scene,
                       const tb__pair_contact *pair, const tb__pair_motion *m,
                       const tb__contact_point *point, double share, size_t slot, const double *y,
                       tb__jacobian_rows *rows)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    const double *n = pair->manifold.normal;
    tb__point_jacobian p = {.body_a = pair->body_a, .body_b = pair->body_b};
    double v_a[3], v_b[3], relative[3], tangent[3];
    for (int k = 0; k < 3; ++k) {
        p.arm_a[k] = point->position[k] - m->body[0]->x[k];
        p.arm_b[k] = point->position[k] - m->body[1]->x[k];
    }
    tb__point_velocity(m->body[0], p.arm_a, v_a);
    tb__point_velocity(m->body[1], p.arm_b, v_b);
    for (int k = 0; k < 3; ++k) {
        relative[k] = v_b[k] - v_a[k];
    }
    const double approach = tb__v3_dot(relative, n);
    const double part = point->depth > 0.0 ? point->depth / m->load : 0.0;
    const double k_n = m->light * share * contact->omega * contact->omega, mass = m->normal * part;
    const double zeta = contact->damping_ratio;
    const double N = tb__contact_point_force(k_n, mass, zeta, point->depth, -approach);
    if (!(N > 0.0)) {
        return; /* no force: a slot held here relaxes (tb__friction_relax_jacobian) */
    }
    double dN[2];
    tb__contact_point_force_derivatives(k_n, mass, zeta, point->depth, -approach, dN);
    for (int k = 0; k < 3; ++k) {
        tangent[k] = relative[k] - approach * n[k];
    }
    const double stiffness = m->light * share * contact->gravity * contact->bristle_stiffness;
    const double damping = sqrt(stiffness * fmin(m->tangential * part, m->reduced * share));
    friction_rows(effect, m, n, N, dN, tangent, stiffness, damping, slot, y, &p);
    tb__jacobian_add_point(rows, scene, &p);
}

int tb__contact_jacobian(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                         tb__jacobian_rows *rows)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    tb__friction_relax_jacobian(contact->friction, scene, effect->state_offset, rows);
    tb__pair_contact batch[16];
    tb__contact_pairs_begin(contact->pairs, scene, t, y);
    size_t count, fresh = 0;
    while ((count = tb__contact_pairs_next(contact->pairs, scene, y, batch, 16)) > 0) {
        for (size_t k = 0; k < count; ++k) {
            const tb__pair_contact *pair = &batch[k];
            tb__pair_motion m;
            tb__contact_pair_motion(scene, pair, &m);
            size_t slots[TB__MANIFOLD_POINTS];
            tb__friction_match(contact->friction, pair, m.body[0], &fresh, slots);
            const double share = 1.0 / (double)pair->manifold.count;
            for (int j = 0; j < pair->manifold.count; ++j) {
                point_rows(effect, scene, pair, &m, &pair->manifold.points[j], share, slots[j], y,
                           rows);
            }
        }
    }
    return 0;
}

/* Private: the contact effect's parameters (effect_contact.c), read by its own files only
 * (effect_contact_*.c, contact_events.h, contact_friction.h). */
#ifndef TUMBLE_EFFECT_CONTACT_H
#define TUMBLE_EFFECT_CONTACT_H

#include "scene/scene_internal.h"

/* Contact between bodies (effect_contact.c): the pair finder and the law's constants. */
typedef struct tb__contact_params {
    struct tb__contact_pairs *pairs; /* owned; contact/contact_pairs.h */
    size_t *bodies;                  /* owned: the ids it acts on */
    size_t body_count;
    bool every_body;             /* made without a list (tb_contact_info) */
    double omega, damping_ratio; /* rad/s, from penetration and restitution */
    double static_friction, kinetic_friction, stribeck_velocity, gravity;
    double push_duration; /* s: the shortest time an impact's force acts, over every pair */
    struct tb__contact_pairs *lookahead; /* owned: pairs within TB__EVENT_LOOKAHEAD, for the
                                            events and step limits (effect_contact_events.c) */
    double bristle_stiffness;            /* friction spring per unit weight, as ground's, 1/m */
    double slip_velocity; /* m/s: v_reg of the memoryless law a point without a slot gets */
    struct tb__friction_pool *friction; /* owned; effects/contact_friction.h */
    struct tb__pass_memo *memo;         /* owned: the step boundary's pass (contact_pass_memo.h) */
    double *speeds; /* owned: the wake links' speed bounds by body id, up to the largest listed
                       (effect_contact_events.c) */
} tb__contact_params;

/* A pair's two bodies as one point of its manifold sees them (effect_contact.c). */
typedef struct tb__pair_motion {
    /* the derivative's (tb__derivative_motion) */
    const tb__motion *body[2];
    double light;   /* kg: the lighter mass */
    double reduced; /* kg: the reduced mass */
    double load;    /* m: the sum of the touching points' depths (their spring forces' weights) */
    double normal;  /* kg: the effective mass at the centre of pressure along the normal */
    double tangential; /* kg: the same for the lightest direction across it */
} tb__pair_motion;

struct tb__pair_contact;

/* The pair's motion and the effective masses of its touching points (effect_contact.c). */
void tb__contact_pair_motion(const tb_scene *scene, const struct tb__pair_contact *pair,
                             tb__pair_motion *m);

/* The contact's analytic Jacobian rows (effect_contact_jacobian.c, tb__effect_ops.jacobian). */
struct tb__jacobian_rows;
int tb__contact_jacobian(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                         struct tb__jacobian_rows *rows);

/* A contact effect's parameters. */
static inline tb__contact_params *tb__contact_of(const tb__effect *effect)
{
    return effect->params;
}

#endif

/* Private: a ground plane's parameters (effect_ground.c), read by its own files only
 * (effect_ground.c, its events in effect_contact_events.c, its read-out in
 * effect_contact_info.c). */
#ifndef TUMBLE_EFFECT_GROUND_H
#define TUMBLE_EFFECT_GROUND_H

#include "scene/scene_internal.h"

typedef struct tb__ground_params {
    double normal[3], tangent[2][3]; /* orthonormal, right-handed, world */
    double offset;                   /* the plane normal . x = offset, m */
    double gravity, penetration;
    double omega;         /* sqrt(gravity / penetration), rad/s */
    double damping_ratio; /* from the restitution (contact/contact_law.h) */
    double static_friction, kinetic_friction, stribeck_velocity;
    double bristle_stiffness; /* friction spring per unit weight: s0 = mu_s / presliding, 1/m */
    /* The bodies it meets through their shapes (no contact points), their friction pool:
     * owned, effects/ground_shapes.h */
    struct tb__ground_shapes *shapes;
} tb__ground_params;

/* A ground plane's parameters. */
static inline tb__ground_params *tb__ground_of(const tb__effect *effect)
{
    return effect->params;
}

#endif

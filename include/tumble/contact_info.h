/* What collides with what, read back from a scene: its contact effects (which bodies, which
 * material), its ground planes, each body's contact points, and the pairs touching at a state.
 * What `tumble check` reports; nothing here changes the scene. Units SI, vectors world frame. */
#ifndef TUMBLE_CONTACT_INFO_H
#define TUMBLE_CONTACT_INFO_H

#include "tumble/export.h"

#include "tumble/scene.h"
#include "tumble/status.h"

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One effect of contact between bodies (tb_scene_add_contact). */
typedef struct tb_contact_info {
    size_t effect;        /* its index among the scene's effects, in the order added */
    bool every_body;      /* added without a list: every body the scene had then */
    size_t body_count;    /* bodies it acts on (listed ones have shapes; every body: any) */
    const size_t *bodies; /* body_count ids: the scene's copy, valid until the scene changes */
    double restitution;   /* the e its law meets (the one asked; 0.062 for any e at or below) */
    double static_friction, kinetic_friction; /* mu_s, mu_k */
    double penetration;                       /* m */
    double gravity;                           /* m/s^2 */
    double stribeck_velocity;                 /* m/s */
} tb_contact_info;

/* One ground plane (tb_scene_add_ground): it touches the contact points of every body. */
typedef struct tb_ground_info {
    size_t effect;    /* its index among the scene's effects */
    double normal[3]; /* unit, out of the ground */
    double offset;    /* the plane normal . x = offset, m */
    double restitution, static_friction, kinetic_friction, penetration, gravity;
} tb_ground_info;

/* How many effects of each kind the scene has; the k-th (0 .. count - 1, in the order added)
 * into *out. TB_STATUS_OUT_OF_RANGE for k past the count. */
TB_API size_t tb_scene_contact_count(const tb_scene *scene);
TB_API tb_status tb_scene_get_contact(const tb_scene *scene, size_t k, tb_contact_info *out);
TB_API size_t tb_scene_ground_count(const tb_scene *scene);
TB_API tb_status tb_scene_get_ground(const tb_scene *scene, size_t k, tb_ground_info *out);

/* How many contact points body id has for ground planes (tb_scene_set_contact_points). */
TB_API tb_status tb_scene_body_contact_point_count(const tb_scene *scene, size_t id,
                                                   size_t *out_count);

/* A pair touching at a state: two bodies of a contact effect whose shapes overlap or lie within
 * the effect's 1 mm margin, or a body whose contact point dips into a ground plane. */
typedef struct tb_contact_touch {
    size_t effect;         /* the effect's index among the scene's effects */
    size_t body_a, body_b; /* body ids (body_a < body_b); body_b TB_WORLD for a ground plane */
    double depth;          /* m: the deepest point's overlap; <= 0: a gap of -depth */
    int points; /* points of the pair's manifold (bodies of several pieces: of every touching
                   piece pair's, one touch for the body pair), or the body's points below */
} tb_contact_touch;

/* The pairs touching at state y (the scene's state array, e.g. tb_scene_states_const), every
 * contact effect's then every ground plane's; the first capacity of them into out (may be
 * NULL when capacity is 0) and their number into *out_count. It uses the pair finder's scratch
 * (the derivative's): TB_STATUS_BUSY while an integrator steps the scene, and not from two
 * threads at once on one scene. */
TB_API tb_status tb_scene_contact_touching(const tb_scene *scene, const double *y,
                                           tb_contact_touch *out, size_t capacity,
                                           size_t *out_count);

#ifdef __cplusplus
}
#endif

#endif

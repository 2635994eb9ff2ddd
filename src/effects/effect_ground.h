/* Private: a ground plane's parameters (effect_ground.c), read by its own files only
 * (effect_ground.c, its checks in effect_ground_check.c, its events in effect_contact_events.c,
 * its read-out in effect_contact_info.c). */
#ifndef TUMBLE_EFFECT_GROUND_H
#define TUMBLE_EFFECT_GROUND_H

#include "scene/scene_internal.h"

typedef struct tb__ground_params {
    double normal[3], tangent[2][3]; /* orthonormal, right-handed, world */
    double offset;                   /* the plane normal . x = offset, m */
    double gravity, penetration;
    double omega;         /* sqrt(gravity / penetration), rad/s */
    double damping_ratio; /* from the restitution (contact/contact_law.h) */
    double push_units;    /* how long an impact's force acts, in units of 1 / omega */
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

/* The end of the run of scene->contacts starting at first that belong to one body: a body's
 * points are contiguous, so its motion and load are read once for them all. */
static inline size_t tb__ground_run_end(const tb_scene *scene, size_t first)
{
    size_t end = first + 1;
    while (end < scene->contact_count && scene->contacts[end].body == scene->contacts[first].body) {
        ++end;
    }
    return end;
}

/* Where a point is: its depth (m, negative above the plane) and its centre's lever arm (world). */
typedef struct tb__point_place {
    double depth, arm[3];
} tb__point_place;

/* What a body's touching points share: the weights w_j = share_j d_j of their spring forces
 * (k_j = M share_j omega^2) and the effective masses at their centre of pressure. */
typedef struct tb__body_load {
    double total;      /* sum of w_j, m */
    double normal;     /* kg: 1 / (1/M + (r x n) . I^-1 (r x n)) at the centre of pressure r */
    double tangential; /* kg: the same for the lightest direction in the plane */
} tb__body_load;

/* How far contact point c's sphere dips below the plane (m, negative above it); its lever arm
 * from the centre of mass into arm (effect_ground.c). */
double tb__ground_point_depth(const tb__ground_params *ground, const tb__contact *c,
                              const tb__motion *motion, double arm[3]);
/* The load of the body's points [first, end) at motion, each point's place into kept (NULL:
 * not kept) (effect_ground.c). */
void tb__ground_body_load(const tb__ground_params *ground, const tb_scene *scene, size_t first,
                          size_t end, const tb__motion *motion, tb__point_place *kept,
                          tb__body_load *out);
/* True when every point of the body's [first, end) is surely above the plane (effect_ground.c). */
bool tb__ground_body_clear(const tb__ground_params *ground, const tb_scene *scene, size_t first,
                           size_t end, const tb__motion *motion);

/* The check_start row (effect_ground_check.c): refuses a state with a contact point starting
 * deeper than TB__START_DEPTH_PENETRATIONS penetrations in the plane or reaching so far from its
 * body's centre of mass that its depth's rounding exceeds the penetration, or a shape the plane
 * meets starting too deep (effect_ground_shapes.c); the detail names the body. */
tb_status tb__ground_check_start(const tb__effect *effect, const tb_scene *scene, const double *y,
                                 char *detail);
/* The check_points row: tb__ground_check_start for body id's points, now contacts[first ..],
 * alone, and for its shape, which the plane meets again when its points are gone (with its size,
 * as tb__ground_check_shape). The other bodies' points and shapes are as they were: O(points)
 * for the flags of bodies with points, not the depth of every point at every call. */
tb_status tb__ground_check_points(const tb__effect *effect, const tb_scene *scene, const double *y,
                                  size_t id, size_t first, char *detail);

/* The ground's analytic Jacobian rows (effect_ground_jacobian.c, tb__effect_ops.jacobian): its
 * points' (effect_ground.c) and its shapes' (effect_ground_shapes.c). */
struct tb__jacobian_rows;
int tb__ground_jacobian(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                        struct tb__jacobian_rows *rows);
void tb__ground_shapes_jacobian(const tb__effect *effect, const tb_scene *scene, double t,
                                const double *y, struct tb__jacobian_rows *rows);

#endif

/* Private: the narrow phase. For two shapes at their poses (collision_shape.h: shape-frame
 * origin + shape -> world quaternion), whether they touch, and where.
 *
 * Result (a manifold): normal is the world unit normal from A to B; each point has
 *   depth    (p_A - p_B) . normal, m: > 0 overlapping (penetration), < 0 apart by -depth;
 *            only points with depth > -margin are reported, so a pair is seen before it
 *            touches;
 *   position (p_A + p_B) / 2, world, m: halfway between the deepest point p_A of A along
 *            normal and the deepest point p_B of B along -normal, so p_A = position +
 *            depth/2 normal and p_B = position - depth/2 normal.
 * Sphere, capsule and box pairs and every shape against a plane have closed forms whose depth
 * is continuous in the poses (except where the normal itself jumps: concentric spheres, a
 * box's centre crossing into another's); a box resting flat on a box gets the 4 corners of
 * their overlap. Other pairs (cylinder, ellipsoid, convex, points) take their normal from
 * libccd's MPR (ccd_wrap.c) for the normal and the overlap; where either shape's support
 * feature along the normal is a face (a box's, a hull's, a cylinder's end, a point set's), the
 * other's feature is clipped to it and gives up to 4 points, fixed in the bodies and entering at
 * the margin (narrow_general.c), otherwise MPR's one. Swapping A and B negates the normal and keeps
 * the depths exactly. docs/contact.md has each pair's method. Nothing here allocates. */
#ifndef TUMBLE_NARROW_PHASE_H
#define TUMBLE_NARROW_PHASE_H

#include "contact/collision_shape.h"

#define TB__MANIFOLD_POINTS 4

typedef struct tb__contact_point {
    double position[3]; /* world, m */
    double depth;       /* m, > 0 when overlapping */
} tb__contact_point;

typedef struct tb__contact_manifold {
    double normal[3]; /* world, unit, from A to B */
    int count;        /* 0 .. TB__MANIFOLD_POINTS */
    tb__contact_point points[TB__MANIFOLD_POINTS];
} tb__contact_manifold;

/* The deepest point of a manifold of at least one point (the first of equal depths): where a
 * pair's gap, hits and events are measured. */
static inline const tb__contact_point *tb__manifold_deepest(const tb__contact_manifold *manifold)
{
    const tb__contact_point *deepest = &manifold->points[0];
    for (int j = 1; j < manifold->count; ++j) {
        deepest = manifold->points[j].depth > deepest->depth ? &manifold->points[j] : deepest;
    }
    return deepest;
}

/* Fills out and returns its point count (0: farther apart than margin, out->count 0).
 * margin >= 0, m. */
int tb__collide(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE], double margin,
                tb__contact_manifold *out);

/* A box's frame at a pose: its axes in the world (axis[i]: shape axis i), |a_k . a_l|, and how
 * far they are from an orthonormal right-handed frame (the sum of |a_k . a_l - delta_kl| plus
 * round-off; infinite when left-handed), which bounds the box pair's shortcuts (narrow_box.c).
 * The pair finder works it out once per body and pass instead of once per pair. */
typedef struct tb__box_frame {
    double axis[3][3];
    double gram[3][3];
    double defect;
} tb__box_frame;

void tb__box_frame_at(const double pose[TB__POSE_SIZE], tb__box_frame *out);

/* tb__collide with each shape's box frame at its pose (NULL: none given; read only when the
 * shape is a box): the same result, bit for bit, without working the frames out per pair. */
int tb__collide_framed(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                       const tb__box_frame *frame_a, const tb__collision_shape *b,
                       const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                       double margin, tb__contact_manifold *out);

/* A floor under the gap of two boxes at their poses, frames given (tb__box_frame_at; NULL:
 * worked out here): under minus the deepest point's depth of tb__collide_framed's manifold with
 * any margin (+infinity when it has no point). Every point of a box pair's manifold lies no
 * deeper than minus the separation along the separating axis test's winning axis, which is at
 * least the largest separation along the six face axes; the floor is that largest one less a
 * slack a thousand times the round-off and the frames' defect (their sum's floor, 1e-15) times
 * the poses' scale (narrow_box.c). It is not the gap: the gap comes from the clipped points, by
 * other arithmetic and, where the deepest corner is clipped off, another number.
 * -infinity when the poses or frames are not finite or a frame is left-handed. */
double tb__box_box_gap_floor(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                             const tb__box_frame *frame_a, const tb__collision_shape *b,
                             const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b);

/* tb__collide_framed for a pass that needs a pair only where its gap may be at most level (m):
 * two boxes whose gap floor is above level get no point (the floor comes from the face
 * separations the test computes first, so a pair that is needed costs no more); every other
 * pair, and every pair with level +infinity, the same result bit for bit. */
int tb__collide_below(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                      const tb__box_frame *frame_a, const tb__collision_shape *b,
                      const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                      double level, double margin, tb__contact_manifold *out);

/* Shape b against the plane normal . x = offset (normal unit, world, pointing out of the
 * solid half-space, which plays A): out->normal is the plane's normal; the points are the
 * shape's lowest ones (up to 4: a box's corners, a cylinder's rim, a hull's vertices, spread
 * over its lowest face), position halfway between the shape's point and the plane. */
int tb__collide_plane(const double normal[3], double offset, const tb__collision_shape *b,
                      const double pose_b[TB__POSE_SIZE], double margin, tb__contact_manifold *out);

#endif

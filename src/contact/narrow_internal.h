/* Private to the narrow-phase sources: the pair routines and the helpers they share. */
#ifndef TUMBLE_NARROW_INTERNAL_H
#define TUMBLE_NARROW_INTERNAL_H

#include "contact/narrow_phase.h"

#include <stdbool.h>

/* Candidate points before the manifold is filled (a clipped face gives up to 8). A list starts
 * with count = 0 alone: the points past count are never read, and zeroing them all (`= {0}`,
 * half a kilobyte) was a fifth of a sphere pair's cost and a sixth of a box pair's. */
#define TB__CANDIDATES_MAX 16

typedef struct tb__candidates {
    int count;
    tb__contact_point points[TB__CANDIDATES_MAX];
} tb__candidates;

/* Appends the point of depth `depth` whose A side is p_a (position p_a - depth/2 n) if
 * depth > -margin and there is room. */
void tb__candidate_add(tb__candidates *c, const double n[3], const double p_a[3], double depth,
                       double margin);

/* Up to TB__MANIFOLD_POINTS of the candidates into out (normal n): all when they fit, else
 * the deepest, the one farthest from it, and the two spanning the largest triangles with them
 * on either side. Returns out->count. */
int tb__reduce_candidates(const tb__candidates *c, const double n[3], tb__contact_manifold *out);

/* A point of depth `depth` on the line between two sphere centres: the core of every
 * sphere-swept pair. c_a, c_b centres, r_a, r_b radii; fallback is the normal when the centres
 * coincide. */
int tb__spheres(const double c_a[3], double r_a, const double c_b[3], double r_b,
                const double fallback[3], double margin, tb__contact_manifold *out);

/* Closest points of segments [p0, p1] and [q0, q1]: parameters s, t in [0, 1]. */
void tb__segments_closest(const double p0[3], const double p1[3], const double q0[3],
                          const double q1[3], double *out_s, double *out_t);

/* A capsule's segment ends at pose (world). */
void tb__capsule_ends(const tb__collision_shape *capsule, const double pose[TB__POSE_SIZE],
                      double out_p0[3], double out_p1[3]);

/* A cylinder's 8 rim points (world): 4 on each end circle, 90 degrees apart, starting from
 * the circle's farthest point along the world direction d (shape x when d is along the axis,
 * where every rim point is as far). */
void tb__cylinder_rim_points(const tb__collision_shape *cylinder, const double pose[TB__POSE_SIZE],
                             const double d[3], double out[8][3]);

/* Sphere (c, r) against the box as a candidate, and that candidate's normal. */
void tb__box_sphere_candidate(const tb__collision_shape *box, const double pose[TB__POSE_SIZE],
                              const double c[3], double r, double margin, tb__candidates *out,
                              double n[3]);

/* A shape's support feature along unit d (narrow_features.c): its points within band (m) of
 * its farthest point along d, fixed in the body where the shape has corners, vertices, spheres
 * or rim points (a cylinder: 8 on each end circle, at fixed angles; when fewer than 3 are in the
 * band, the farthest point of each end circle), world. A face when 3 or more lie in one plane
 * whose normal is within about 8 degrees of d; else at most 2 (a segment), else the support
 * point alone. */
#define TB__FEATURE_MAX 16

typedef struct tb__feature {
    int count;
    double points[TB__FEATURE_MAX][3];
    bool planar;      /* 3 or more points lie in one plane (normal, offset; facing d or not) */
    bool face;        /* ... and it faces d within about 8 degrees: a face */
    double normal[3]; /* face: its unit normal, towards d */
    double offset;    /* face: normal . x on the plane, m */
} tb__feature;

void tb__support_feature(const tb__collision_shape *s, const double pose[TB__POSE_SIZE],
                         const double d[3], double band, tb__feature *out);

/* Shapes without a closed form against each other, capsules and boxes (narrow_general.c):
 * MPR's normal, then a face's clipped points, or MPR's point. */
int tb__general_collide(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                        const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                        double margin, tb__contact_manifold *out);

/* The pressed part of a clipped face (narrow_general.c): poly (count points of the incident
 * feature, in order around the face when 3 or more) below the reference face's plane
 * m . x = offset (m its unit normal towards the other body; origin on it; u, v unit, spanning it,
 * fixed in the reference body), as 4 points of the rule that integrates a linear depth over
 * the part that presses and its first moments (1 point for 1). Normal from A to B (m when the
 * face is A's). Returns out->count: 0 when no point is deeper than -margin. */
int tb__pressed_face(double poly[][3], int count, const double origin[3], const double m[3],
                     double offset, const double u[3], const double v[3], bool ref_is_a,
                     double margin, tb__contact_manifold *out);

/* Box pairs (narrow_box.c); A is the box. */
int tb__box_sphere(const tb__collision_shape *box, const double pose_box[TB__POSE_SIZE],
                   const double center[3], double radius, double margin, tb__contact_manifold *out);
int tb__box_capsule(const tb__collision_shape *box, const double pose_box[TB__POSE_SIZE],
                    const tb__collision_shape *capsule, const double pose_capsule[TB__POSE_SIZE],
                    double margin, tb__contact_manifold *out);
int tb__box_box(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE], double margin,
                tb__contact_manifold *out);
/* tb__box_box with each box's frame at its pose (tb__box_frame_at; NULL: worked out here). */
int tb__box_box_framed(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                       const tb__box_frame *frame_a, const tb__collision_shape *b,
                       const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                       double margin, tb__contact_manifold *out);
/* tb__box_box_framed, or no point when the pair's gap floor (tb__box_box_gap_floor) is above
 * level (m; INFINITY: never): the floor comes from the face separations the test computes
 * anyway, so a pair the caller needs costs no more. */
int tb__box_box_below(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                      const tb__box_frame *frame_a, const tb__collision_shape *b,
                      const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                      double level, double margin, tb__contact_manifold *out);

#endif

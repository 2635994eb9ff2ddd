/* Private: a body's collision shape as the broad and narrow phases read it (made from a
 * tb_shape by tb_scene_set_body_shape, collision_shape.c). Everything is in the body's shape
 * frame; a pose places it in the world. */
#ifndef TUMBLE_COLLISION_SHAPE_H
#define TUMBLE_COLLISION_SHAPE_H

#include "tumble/shape.h"

#include <stddef.h>

/* A pose: the world position of the shape origin (m), then the shape -> world unit quaternion
 * (w, x, y, z): pose[0..3) and pose[3..7). tb_scene_body_shape_pose gives them; so does
 * tb__shape_pose below without the checks. */
#define TB__POSE_SIZE 7

typedef struct tb__collision_shape {
    tb_shape_type type;
    double radius;      /* sphere, capsule, cylinder, m */
    double half_length; /* capsule: half its segment; cylinder: half its height; along z, m */
    double half[3];     /* box: half edge lengths; ellipsoid: semi-axes, m */
    /* convex: the hull's vertices; points: the spheres' centres (3 * vertex_count, m) and
     * radii (vertex_count, m; NULL for a convex shape). Both point into this allocation. */
    size_t vertex_count;
    double *vertices;
    double *radii;
    double local_min[3], local_max[3]; /* bounds in the shape frame, m */
    /* compound (TB_SHAPE_COMPOUND): its pieces, each a convex shape of the other types and its
     * pose in this shape's frame, all in this allocation; 0 and NULL for the other types */
    size_t piece_count;
    const struct tb__shape_piece *pieces;
    double data[]; /* vertices, then radii; compound: the pieces, then their shapes */
} tb__collision_shape;

typedef struct tb__shape_piece {
    const tb__collision_shape *shape;
    double pose[TB__POSE_SIZE]; /* the piece's frame in the compound's shape frame */
} tb__shape_piece;

/* A shape made from a checked tb_shape in one allocation (free() releases it); NULL with the
 * detail (TB_DETAIL_SIZE bytes) written on a refusal or when memory runs out, *out_status
 * saying which. Computes a convex shape's hull. */
tb__collision_shape *tb__collision_shape_make(const tb_shape *shape, char *detail,
                                              tb_status *out_status);

/* A body's shape made from checked-here pieces (tb_shape_piece, count >= 1) in one allocation
 * (free() releases it): one piece at the identity pose is that piece's plain shape, anything
 * else a compound. NULL with detail and *out_status as tb__collision_shape_make, the detail
 * naming the piece ("pieces[k].field") when count > 1. */
tb__collision_shape *tb__collision_shape_make_pieces(const tb_shape_piece *pieces, size_t count,
                                                     char *detail, tb_status *out_status);

/* The pieces a body's shape is made of: a compound's, else 1 (the shape itself). */
size_t tb__collision_shape_piece_count(const tb__collision_shape *shape);
/* Piece k of shape placed at pose (the body's shape pose): the piece and its world pose. A plain
 * shape's only piece is itself at pose (copied bit for bit). */
const tb__collision_shape *tb__collision_shape_piece(const tb__collision_shape *shape, size_t k,
                                                     const double pose[TB__POSE_SIZE],
                                                     double out_pose[TB__POSE_SIZE]);

/* World axis-aligned bounds of the shape at pose, m (closed forms per type; conservative for
 * convex, points and compound shapes: their shape-frame box, rotated). */
void tb__collision_shape_bounds(const tb__collision_shape *shape, const double pose[TB__POSE_SIZE],
                                double out_min[3], double out_max[3]);

/* The shape's point farthest along the world direction d (any length > 0) at pose: the
 * support function libccd needs, closed form per type. */
void tb__collision_shape_support(const tb__collision_shape *shape, const double pose[TB__POSE_SIZE],
                                 const double d[3], double out[3]);

#endif

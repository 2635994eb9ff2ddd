/* Collision shapes: the geometry a body touches other bodies with. A shape is described in the
 * body's shape frame (the frame of tb_body_def.orientation, the frame mass properties are given
 * in); it does not change the body's mass properties, which stay as given when the body was
 * added. Sizes follow the tb_mass_from_* constructors, so the same numbers make both. Units m. */
#ifndef TUMBLE_SHAPE_H
#define TUMBLE_SHAPE_H

#include "tumble/export.h"

#include "tumble/scene.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum tb_shape_type {
    TB_SHAPE_NONE = 0,  /* no shape: the body touches nothing */
    TB_SHAPE_SPHERE,    /* radius, centred at the shape origin */
    TB_SHAPE_BOX,       /* size (full edge lengths along shape x, y, z), centred */
    TB_SHAPE_CAPSULE,   /* radius, length: the segment between the hemisphere centres, along z
                           (total length length + 2 radius), centred */
    TB_SHAPE_CYLINDER,  /* radius, length (total, along z), centred */
    TB_SHAPE_ELLIPSOID, /* semi_axes along x, y, z, centred */
    TB_SHAPE_CONVEX,    /* the convex hull of vertices (a mesh's vertices: a non-convex mesh
                           collides as its convex hull), computed when the shape is set; with
                           triangles, a mesh: it collides as its hull and is drawn as itself */
    TB_SHAPE_POINTS,    /* spheres at vertices with radii (NULL: all 0); the shape is the
                           convex hull of the spheres */
    TB_SHAPE_COMPOUND   /* read-out only (tb_scene_body_shape_type): a body of several pieces or
                           of one piece off the shape origin (tb_scene_set_body_pieces) */
} tb_shape_type;

/* Fill with tb_shape_default(), set type and the fields that type reads; the others are
 * ignored. Limits: every size finite, > 0 (radii of points >= 0) and at most 1e100 m;
 * vertex_count <= 1 000 000. */
typedef struct tb_shape {
    tb_shape_type type;
    double radius;          /* sphere, capsule, cylinder, m */
    double length;          /* capsule, cylinder, m (see above) */
    double size[3];         /* box, m */
    double semi_axes[3];    /* ellipsoid, m */
    const double *vertices; /* convex, points: vertices[3 * vertex_count], shape frame, m */
    size_t vertex_count;    /* convex: >= 4, not all in one plane; points: >= 1 */
    const double *radii;    /* points: radii[vertex_count], m, >= 0; NULL: all 0 */
    /* convex, optional: the mesh's triangles[3 * triangle_count], indices into vertices
     * (counter-clockwise seen from outside); the scene keeps them with all the vertices as the
     * piece's visual mesh (tb_scene_set_body_visual_mesh), which writers draw instead of the
     * hull. triangle_count 0 (the default): drawn as the hull. At most 4 000 000. */
    const unsigned *triangles;
    size_t triangle_count;
} tb_shape;

/* A zeroed shape of type TB_SHAPE_NONE. */
TB_API tb_shape tb_shape_default(void);

/* Gives body id a collision shape (the data is copied; a convex shape keeps only its hull's
 * vertices, and its triangles, if any, as the visual mesh), replacing the one it had and the
 * body's visual meshes; NULL or TB_SHAPE_NONE removes it. Refused with a detail
 * naming the field: a bad id (TB_STATUS_OUT_OF_RANGE), removing the shape of a body a contact
 * effect lists (TB_STATUS_INVALID_ARGUMENT naming the body and the effect: it would touch
 * nothing), NULL vertices (TB_STATUS_NULL_POINTER), a
 * non-finite number (TB_STATUS_NOT_FINITE), a size out of its range, an unknown type, too few
 * vertices or a flat convex set (TB_STATUS_INVALID_ARGUMENT), triangles as
 * tb_scene_set_body_visual_mesh refuses them; TB_STATUS_BUSY while an
 * integrator steps the scene. A refused call changes nothing. Effects that read shapes see the
 * change at their next derivative; CVODE restarts its history. The body wakes, and the next
 * advance, step or reset checks the state as a start (a shape grown deep into another body is
 * refused there, INVALID_ARGUMENT naming the pair, as a body moved there is). */
TB_API tb_status tb_scene_set_body_shape(tb_scene *scene, size_t id, const tb_shape *shape);

/* A convex piece of a body: a shape placed in the body's shape frame (the frame of
 * tb_body_def.orientation) by the position of the piece's own origin (m) and the rotation from
 * the piece's frame to the body's shape frame (unit quaternion w, x, y, z, |q| = 1 within 1e-4;
 * it is normalised). tb_shape_piece_default(): no shape, at the shape origin, not rotated. */
typedef struct tb_shape_piece {
    tb_shape shape;
    double position[3];
    double orientation[4];
} tb_shape_piece;

TB_API tb_shape_piece tb_shape_piece_default(void);

/* Gives body id a shape of count >= 1 convex pieces (copied, as tb_scene_set_body_shape copies
 * one; a convex piece with triangles is drawn with them), replacing the one it had and the
 * body's visual meshes. The body collides piece by piece: each piece of one body meets
 * each piece of another through the pair's own narrow phase (a manifold per touching piece
 * pair); pieces of one body never meet each other. Mass properties are the caller's
 * (tb_mass_combine combines the pieces'). One piece at the identity pose is the plain shape, bit
 * for bit. Refused as tb_scene_set_body_shape is, the detail naming the piece
 * ("pieces[2].radius: ..."), and: pieces NULL (TB_STATUS_NULL_POINTER), count 0 or above
 * 1 000 000, a piece of type TB_SHAPE_NONE or a bad orientation (TB_STATUS_INVALID_ARGUMENT), a
 * non-finite or farther than 1e100 m position (TB_STATUS_NOT_FINITE / INVALID_ARGUMENT). A
 * refused call changes nothing. */
TB_API tb_status tb_scene_set_body_pieces(tb_scene *scene, size_t id, const tb_shape_piece *pieces,
                                          size_t count);

/* How many pieces body id's shape has: 0 without a shape, 1 for tb_scene_set_body_shape's. */
TB_API tb_status tb_scene_body_piece_count(const tb_scene *scene, size_t id, size_t *out_count);

/* Piece k (< the piece count) of body id, as the scene keeps it: out_piece->shape is the shape
 * (a convex piece's vertices are its hull's; vertices and radii point into the scene and stay
 * valid until the body's shape is set again or the scene is destroyed), position and
 * orientation place it in the body's shape frame as tb_scene_set_body_pieces describes
 * (orientation unit). What writers draw. TB_STATUS_OUT_OF_RANGE for a bad id or k. */
TB_API tb_status tb_scene_body_piece(const tb_scene *scene, size_t id, size_t k,
                                     tb_shape_piece *out_piece);

/* Body id's shape type (TB_SHAPE_NONE when it has none, TB_SHAPE_COMPOUND for pieces). */
TB_API tb_status tb_scene_body_shape_type(const tb_scene *scene, size_t id,
                                          tb_shape_type *out_type);

/* Body id's shape's axis-aligned bounding box in the world at state y (its own scene's size),
 * m: what the broad phase sees before its margin is added. TB_STATUS_INVALID_ARGUMENT when
 * the body has no shape. */
TB_API tb_status tb_scene_body_shape_bounds(const tb_scene *scene, const double *y, size_t id,
                                            double out_min[3], double out_max[3]);

/* A triangle mesh to draw a piece with: vertices[3 * vertex_count] in the piece's frame (m),
 * triangles[3 * triangle_count] indices into them, counter-clockwise seen from outside. */
typedef struct tb_visual_mesh {
    const double *vertices;
    size_t vertex_count;
    const unsigned *triangles;
    size_t triangle_count;
} tb_visual_mesh;

/* Gives piece k of body id a visual mesh (copied): what writers (glTF, USD) draw for the piece
 * instead of its collision shape. It changes no motion: the piece still collides as its shape.
 * k < the body's piece count, or k = 0 for a body without a shape (drawn as the mesh instead of
 * its inertia ellipsoid). vertex_count and triangle_count both 0 (vertices and triangles may be
 * NULL) remove it. Setting the body's shape again (tb_scene_set_body_shape, _pieces) replaces
 * its visual meshes. Refused with a detail naming the input: a bad id or k
 * (TB_STATUS_OUT_OF_RANGE), vertices or triangles NULL with a count (TB_STATUS_NULL_POINTER), a
 * non-finite coordinate (TB_STATUS_NOT_FINITE), a coordinate beyond 1e100 m, vertex_count not in
 * [3, 1 000 000], triangle_count not in [1, 4 000 000] or an index >= vertex_count
 * (TB_STATUS_INVALID_ARGUMENT). A refused call changes nothing. */
TB_API tb_status tb_scene_set_body_visual_mesh(tb_scene *scene, size_t id, size_t k,
                                               const double *vertices, size_t vertex_count,
                                               const unsigned *triangles, size_t triangle_count);

/* Piece k's visual mesh (k as above), pointing into the scene (valid until it is set again or
 * the scene is destroyed); all zeros when the piece has none (it is drawn as its shape).
 * TB_STATUS_OUT_OF_RANGE for a bad id or k. */
TB_API tb_status tb_scene_body_visual_mesh(const tb_scene *scene, size_t id, size_t k,
                                           tb_visual_mesh *out_mesh);

#ifdef __cplusplus
}
#endif

#endif

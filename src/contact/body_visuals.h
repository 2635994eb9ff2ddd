/* Private: the scene's visual meshes, what writers draw for a body's pieces instead of their
 * collision shapes (body_visuals.c). A mesh shape collides as its hull and is drawn as itself. */
#ifndef TUMBLE_BODY_VISUALS_H
#define TUMBLE_BODY_VISUALS_H

#include "scene/scene_internal.h"
#include "tumble/shape.h"

/* One mesh in one allocation (free() releases it): the header, the vertices, the triangles. */
typedef struct tb__visual_mesh {
    size_t vertex_count, triangle_count;
    unsigned *triangles; /* [3 * triangle_count], after the vertices */
    double vertices[];   /* [3 * vertex_count], the piece's frame, m */
} tb__visual_mesh;

/* The visual meshes that count pieces carry (a convex piece's triangles), checked and copied
 * into *out (NULL when no piece carries any); the detail names the piece ("pieces[2].triangles")
 * when count > 1. *out is freed by tb__body_visuals_free. */
tb_status tb__body_visuals_of_pieces(const tb_shape_piece *pieces, size_t count, char *detail,
                                     tb__body_visuals **out);
void tb__body_visuals_free(tb__body_visuals *visuals);

/* Room for every body's visuals slot (new ones NULL); nothing changes on failure. */
tb_status tb__scene_reserve_visuals(tb_scene *scene);
/* Body id's visuals become visuals (which may be NULL), the old ones freed; room reserved. */
void tb__scene_swap_visuals(tb_scene *scene, size_t id, tb__body_visuals *visuals);

#endif

/* Writers: what the bodies and grounds look like, from the scene alone: each body's pieces as
 * the scene keeps them (tb_scene_body_piece), each drawn with its visual mesh where it has one
 * (tb_scene_body_visual_mesh: a mesh shape's own triangles), and the ground planes
 * (tb_scene_get_ground), so that a scene built through the C API is drawn as one loaded from a
 * file. */
#include "export/writer_internal.h"

#include "contact/convex_hull.h"
#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"
#include "tumble/contact_info.h"
#include "tumble/shape.h"

#include <stdlib.h>
#include <string.h>

/* A convex piece drawn as its hull: its vertices and the hull's triangles. */
static tb_status hull_look(const tb_shape *shape, tb__shape *s, tb_error *error)
{
    const size_t n = shape->vertex_count;
    unsigned char *on_hull = malloc(n > 0 ? n : 1);
    s->vertices = tb__malloc_array(n > 0 ? n : 1, 3 * sizeof(double));
    uint32_t *triangles = NULL;
    size_t count = 0;
    char detail[TB_DETAIL_SIZE] = "";
    tb_status status =
        on_hull != NULL && s->vertices != NULL ? TB_STATUS_OK : TB_STATUS_OUT_OF_MEMORY;
    if (status == TB_STATUS_OK) {
        memcpy(s->vertices, shape->vertices, 3 * n * sizeof(double));
        s->vertex_count = n;
        status = tb__convex_hull_triangles(s->vertices, n, on_hull, &triangles, &count, detail);
    }
    s->triangles =
        status == TB_STATUS_OK ? tb__malloc_array(3 * count + 1, sizeof(unsigned)) : NULL;
    for (size_t k = 0; s->triangles != NULL && k < 3 * count; ++k) {
        s->triangles[k] = (unsigned)triangles[k];
    }
    s->triangle_count = s->triangles != NULL ? count : 0;
    free(on_hull);
    free(triangles);
    if (status == TB_STATUS_OK && s->triangles == NULL) {
        status = TB_STATUS_OUT_OF_MEMORY;
    }
    return status == TB_STATUS_OK
               ? status
               : tb__set_error(error, status, "writer: a hull of %zu vertices%s%s", n,
                               detail[0] ? ": " : "", detail);
}

/* Piece p of the scene as the tessellator and the USD writer take it. */
static tb_status piece_look(const tb_shape_piece *p, tb__shape *s, tb_error *error)
{
    const tb_shape *shape = &p->shape;
    memcpy(s->position, p->position, sizeof s->position);
    memcpy(s->orientation, p->orientation, sizeof s->orientation);
    switch (shape->type) {
    case TB_SHAPE_BOX:
        s->kind = TB__SHAPE_BOX;
        memcpy(s->size, shape->size, sizeof s->size);
        return TB_STATUS_OK;
    case TB_SHAPE_ELLIPSOID:
        s->kind = TB__SHAPE_ELLIPSOID;
        memcpy(s->size, shape->semi_axes, sizeof s->size);
        return TB_STATUS_OK;
    case TB_SHAPE_SPHERE:
    case TB_SHAPE_CYLINDER:
    case TB_SHAPE_CAPSULE:
        s->kind = shape->type == TB_SHAPE_SPHERE     ? TB__SHAPE_SPHERE
                  : shape->type == TB_SHAPE_CYLINDER ? TB__SHAPE_CYLINDER
                                                     : TB__SHAPE_CAPSULE;
        tb__v3_set(s->size, shape->radius, shape->length, 0.0);
        return TB_STATUS_OK;
    case TB_SHAPE_CONVEX:
        s->kind = TB__SHAPE_MESH;
        return hull_look(shape, s, error);
    default: /* points */
        s->kind = TB__SHAPE_POINTS;
        s->vertices = tb__malloc_array(shape->vertex_count + 1, 3 * sizeof(double));
        if (s->vertices == NULL) {
            return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: %zu points",
                                 shape->vertex_count);
        }
        memcpy(s->vertices, shape->vertices, 3 * shape->vertex_count * sizeof(double));
        s->vertex_count = shape->vertex_count;
        return TB_STATUS_OK;
    }
}

/* A piece drawn with its visual mesh, at the piece's pose. */
static tb_status visual_look(const tb_shape_piece *p, const tb_visual_mesh *visual, tb__shape *s,
                             tb_error *error)
{
    memcpy(s->position, p->position, sizeof s->position);
    memcpy(s->orientation, p->orientation, sizeof s->orientation);
    s->kind = TB__SHAPE_MESH;
    s->vertices = tb__malloc_array(visual->vertex_count, 3 * sizeof(double));
    s->triangles = tb__malloc_array(visual->triangle_count, 3 * sizeof(unsigned));
    if (s->vertices == NULL || s->triangles == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: a mesh of %zu vertices",
                             visual->vertex_count);
    }
    memcpy(s->vertices, visual->vertices, 3 * visual->vertex_count * sizeof(double));
    memcpy(s->triangles, visual->triangles, 3 * visual->triangle_count * sizeof(unsigned));
    s->vertex_count = visual->vertex_count;
    s->triangle_count = visual->triangle_count;
    return TB_STATUS_OK;
}

/* Body id's pieces (each its visual mesh, or its shape), or its inertia ellipsoid (or the
 * visual mesh of a body without a shape). */
static tb_status body_look(const tb_scene *scene, size_t id, tb__look *look, tb_error *error)
{
    size_t count = 0;
    tb_scene_get_mass(scene, id, &look->mass);
    tb_scene_body_piece_count(scene, id, &count);
    look->pieces = calloc(count > 0 ? count : 1, sizeof *look->pieces);
    if (look->pieces == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: %zu pieces", count);
    }
    look->piece_count = count > 0 ? count : 1;
    for (size_t k = 0; k < look->piece_count; ++k) {
        look->pieces[k].kind = TB__SHAPE_INERTIA;
        look->pieces[k].mass = look->mass;
        look->pieces[k].orientation[0] = 1.0;
    }
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < look->piece_count && status == TB_STATUS_OK; ++k) {
        tb_shape_piece piece = tb_shape_piece_default();
        tb_visual_mesh visual;
        if (k < count) {
            tb_scene_body_piece(scene, id, k, &piece);
        }
        tb_scene_body_visual_mesh(scene, id, k, &visual);
        if (visual.triangle_count > 0) {
            status = visual_look(&piece, &visual, &look->pieces[k], error);
        } else if (k < count) {
            status = piece_look(&piece, &look->pieces[k], error);
        }
    }
    return status;
}

static tb_status ground_looks(const tb_scene *scene, tb__looks *looks, tb_error *error)
{
    const size_t count = tb_scene_ground_count(scene);
    looks->grounds = tb__malloc_array(count + 1, sizeof *looks->grounds);
    if (looks->grounds == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: %zu ground planes", count);
    }
    for (size_t k = 0; k < count; ++k) {
        tb_ground_info info;
        tb_scene_get_ground(scene, k, &info);
        memcpy(looks->grounds[k].normal, info.normal, sizeof info.normal);
        looks->grounds[k].offset = info.offset;
    }
    looks->ground_count = count;
    return TB_STATUS_OK;
}

tb_status tb__looks_load(tb__looks *looks, const tb_scene *scene, tb_error *error)
{
    const size_t n = tb_scene_body_count(scene);
    memset(looks, 0, sizeof *looks);
    looks->bodies = calloc(n > 0 ? n : 1, sizeof *looks->bodies);
    if (looks->bodies == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: shapes of %zu bodies", n);
    }
    tb_status status = TB_STATUS_OK;
    for (size_t id = 0; id < n && status == TB_STATUS_OK; ++id) {
        status = body_look(scene, id, &looks->bodies[id], error);
    }
    if (status == TB_STATUS_OK) {
        status = ground_looks(scene, looks, error);
    }
    if (status == TB_STATUS_OK) {
        status = tb__looks_joints(looks, scene, error);
    }
    return status;
}

void tb__looks_free(tb__looks *looks, size_t body_count)
{
    for (size_t id = 0; looks->bodies != NULL && id < body_count; ++id) {
        const tb__look *look = &looks->bodies[id];
        for (size_t k = 0; look->pieces != NULL && k < look->piece_count; ++k) {
            free(look->pieces[k].vertices);
            free(look->pieces[k].triangles);
        }
        free(look->pieces);
    }
    free(looks->bodies);
    free(looks->grounds);
    free(looks->joints);
    memset(looks, 0, sizeof *looks);
}

/* The vertices [first, mesh's count) moved from a piece's frame into the body's: p -> R p + t,
 * n -> R n (floats, as glTF holds them). */
static void place(tb__mesh *mesh, size_t first, const tb__shape *piece)
{
    for (size_t v = first; v < mesh->vertex_count; ++v) {
        float *p = mesh->positions + 3 * v, *n = mesh->normals + 3 * v;
        const double local_p[3] = {p[0], p[1], p[2]}, local_n[3] = {n[0], n[1], n[2]};
        double world_p[3], world_n[3];
        tb__q_rotate(world_p, piece->orientation, local_p);
        tb__q_rotate(world_n, piece->orientation, local_n);
        for (int i = 0; i < 3; ++i) {
            p[i] = (float)(world_p[i] + piece->position[i]);
            n[i] = (float)world_n[i];
        }
    }
}

static bool at_origin(const tb__shape *s)
{
    return s->position[0] == 0.0 && s->position[1] == 0.0 && s->position[2] == 0.0 &&
           s->orientation[0] == 1.0 && s->orientation[1] == 0.0 && s->orientation[2] == 0.0 &&
           s->orientation[3] == 0.0;
}

void tb__mesh_of_body(tb__mesh *mesh, const tb__look *look)
{
    for (size_t k = 0; k < look->piece_count; ++k) {
        const size_t first = mesh->vertex_count;
        tb__mesh_of_shape(mesh, &look->pieces[k]);
        if (!mesh->failed && !at_origin(&look->pieces[k])) {
            place(mesh, first, &look->pieces[k]);
        }
    }
}

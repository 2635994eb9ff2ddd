/* The scene's visual meshes: per body, one triangle mesh per piece at most, in the piece's
 * frame; set with the shape (a convex piece's triangles) or on their own, and read by the
 * writers, which draw them instead of the pieces' collision shapes. */
#include "contact/body_visuals.h"

#include "contact/collision_shape.h"
#include "contact/contact_pairs.h"
#include "core/detail.h"
#include "core/validate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define VERTEX_COUNT_MAX 1000000 /* as a shape's */
#define TRIANGLE_COUNT_MAX 4000000
#define COORDINATE_MAX_M 1e100 /* as a shape's sizes: squares stay finite */

static tb_status check_counts(const double *vertices, size_t vertex_count,
                              const unsigned *triangles, size_t triangle_count, char *detail)
{
    if (vertices == NULL || triangles == NULL) {
        return tb__set_detail(detail, TB_STATUS_NULL_POINTER, "%s is NULL",
                              vertices == NULL ? "vertices" : "triangles");
    }
    if (vertex_count < 3 || vertex_count > VERTEX_COUNT_MAX) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "vertex_count: must be in [3, %d], got %zu", VERTEX_COUNT_MAX,
                              vertex_count);
    }
    if (triangle_count < 1 || triangle_count > TRIANGLE_COUNT_MAX) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "triangle_count: must be in [1, %d], got %zu", TRIANGLE_COUNT_MAX,
                              triangle_count);
    }
    return TB_STATUS_OK;
}

/* Finite coordinates within 1e100 m, and indices below vertex_count. */
static tb_status check_mesh(const double *vertices, size_t vertex_count, const unsigned *triangles,
                            size_t triangle_count, char *detail)
{
    tb_status status = check_counts(vertices, vertex_count, triangles, triangle_count, detail);
    for (size_t i = 0; i < 3 * vertex_count && status == TB_STATUS_OK; ++i) {
        const double c = vertices[i];
        if (!isfinite(c) || fabs(c) > COORDINATE_MAX_M) {
            status = tb__set_detail(
                detail, isfinite(c) ? TB_STATUS_INVALID_ARGUMENT : TB_STATUS_NOT_FINITE,
                "vertices[%zu]: must be finite and within 1e100 m, got %g", i, c);
        }
    }
    for (size_t i = 0; i < 3 * triangle_count && status == TB_STATUS_OK; ++i) {
        if (triangles[i] >= vertex_count) {
            status = tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                                    "triangles[%zu]: %u is not a vertex (%zu vertices)", i,
                                    triangles[i], vertex_count);
        }
    }
    return status;
}

/* A checked copy in one allocation (the limits keep its size far from overflow). */
static tb__visual_mesh *make_mesh(const double *vertices, size_t vertex_count,
                                  const unsigned *triangles, size_t triangle_count, char *detail,
                                  tb_status *out_status)
{
    *out_status = check_mesh(vertices, vertex_count, triangles, triangle_count, detail);
    if (*out_status != TB_STATUS_OK) {
        return NULL;
    }
    const size_t vertex_bytes = 3 * vertex_count * sizeof(double);
    tb__visual_mesh *mesh =
        malloc(sizeof *mesh + vertex_bytes + 3 * triangle_count * sizeof(unsigned));
    if (mesh == NULL) {
        *out_status = tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY,
                                     "a visual mesh of %zu vertices", vertex_count);
        return NULL;
    }
    mesh->vertex_count = vertex_count;
    mesh->triangle_count = triangle_count;
    memcpy(mesh->vertices, vertices, vertex_bytes);
    mesh->triangles = (unsigned *)(void *)((char *)mesh->vertices + vertex_bytes);
    memcpy(mesh->triangles, triangles, 3 * triangle_count * sizeof(unsigned));
    return mesh;
}

void tb__body_visuals_free(tb__body_visuals *visuals)
{
    for (size_t k = 0; visuals != NULL && k < visuals->count; ++k) {
        free(visuals->meshes[k]);
    }
    free(visuals);
}

/* count empty slots */
static tb__body_visuals *new_visuals(size_t count)
{
    size_t bytes = 0;
    if (!tb__size_product(count, sizeof(tb__visual_mesh *), &bytes) ||
        bytes > (size_t)-1 - sizeof(tb__body_visuals)) {
        return NULL;
    }
    tb__body_visuals *visuals = calloc(1, sizeof *visuals + bytes);
    if (visuals != NULL) {
        visuals->count = count;
    }
    return visuals;
}

static bool carries_mesh(const tb_shape *shape)
{
    return shape->type == TB_SHAPE_CONVEX && shape->triangle_count > 0;
}

tb_status tb__body_visuals_of_pieces(const tb_shape_piece *pieces, size_t count, char *detail,
                                     tb__body_visuals **out)
{
    *out = NULL;
    size_t carried = 0;
    for (size_t k = 0; k < count; ++k) {
        carried += carries_mesh(&pieces[k].shape);
    }
    tb__body_visuals *visuals = carried > 0 ? new_visuals(count) : NULL;
    if (carried > 0 && visuals == NULL) {
        return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "visual meshes of %zu pieces",
                              count);
    }
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < count && carried > 0 && status == TB_STATUS_OK; ++k) {
        const tb_shape *shape = &pieces[k].shape;
        if (carries_mesh(shape)) {
            visuals->meshes[k] = make_mesh(shape->vertices, shape->vertex_count, shape->triangles,
                                           shape->triangle_count, detail, &status);
        }
        if (status != TB_STATUS_OK && count > 1 && detail != NULL) {
            char message[TB_DETAIL_SIZE];
            snprintf(message, sizeof message, "%s", detail);
            tb__set_detail(detail, status, "pieces[%zu].%s", k, message);
        }
    }
    if (status != TB_STATUS_OK) {
        tb__body_visuals_free(visuals);
        return status;
    }
    *out = visuals;
    return TB_STATUS_OK;
}

tb_status tb__scene_reserve_visuals(tb_scene *scene)
{
    const size_t count = scene->body_count;
    if (count <= scene->visual_capacity) {
        return TB_STATUS_OK;
    }
    tb__body_visuals **visuals = tb__realloc_array(scene->visuals, count, sizeof *visuals);
    if (visuals == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "visual meshes of %zu bodies", count);
    }
    for (size_t i = scene->visual_capacity; i < count; ++i) {
        visuals[i] = NULL;
    }
    scene->visuals = visuals;
    scene->visual_capacity = count;
    return TB_STATUS_OK;
}

void tb__scene_swap_visuals(tb_scene *scene, size_t id, tb__body_visuals *visuals)
{
    tb__body_visuals_free(scene->visuals[id]);
    scene->visuals[id] = visuals;
}

/* Body id's visual slots: one per piece, one for a body without a shape. */
static size_t slot_count(const tb_scene *scene, size_t id)
{
    const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
    return shape != NULL ? tb__collision_shape_piece_count(shape) : 1;
}

static tb_status check_slot(const tb_scene *scene, size_t id, size_t k)
{
    tb_status status = tb__scene_check_id(scene, id, "id");
    const size_t count = status == TB_STATUS_OK ? slot_count(scene, id) : 0;
    if (status == TB_STATUS_OK && k >= count) {
        status = tb__scene_fail((tb_scene *)scene, TB_STATUS_OUT_OF_RANGE,
                                "k: %zu is not a piece of body %zu (it has %zu)", k, id, count);
    }
    return status;
}

/* Slot k of body id takes mesh (NULL: none); its slots are made first if it had none. */
static tb_status place_mesh(tb_scene *scene, size_t id, size_t k, tb__visual_mesh *mesh)
{
    tb_status status = tb__scene_reserve_visuals(scene);
    tb__body_visuals *visuals = status == TB_STATUS_OK ? scene->visuals[id] : NULL;
    if (status == TB_STATUS_OK && visuals == NULL && mesh != NULL) {
        visuals = new_visuals(slot_count(scene, id));
        status = visuals != NULL ? TB_STATUS_OK
                                 : tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY,
                                                  "visual meshes of body %zu", id);
        scene->visuals[id] = visuals;
    }
    if (status != TB_STATUS_OK) {
        free(mesh);
        return status;
    }
    if (visuals != NULL) {
        free(visuals->meshes[k]);
        visuals->meshes[k] = mesh;
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_set_body_visual_mesh(tb_scene *scene, size_t id, size_t k,
                                        const double *vertices, size_t vertex_count,
                                        const unsigned *triangles, size_t triangle_count)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = check_slot(scene, id, k);
    tb__visual_mesh *mesh = NULL;
    if (status == TB_STATUS_OK && (vertex_count != 0 || triangle_count != 0)) {
        mesh = make_mesh(vertices, vertex_count, triangles, triangle_count, scene->detail, &status);
    }
    return status == TB_STATUS_OK ? place_mesh(scene, id, k, mesh) : status;
}

tb_status tb_scene_body_visual_mesh(const tb_scene *scene, size_t id, size_t k,
                                    tb_visual_mesh *out_mesh)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_mesh == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_mesh is NULL");
    }
    tb_status status = check_slot(scene, id, k);
    if (status == TB_STATUS_OK) {
        const tb__body_visuals *visuals = id < scene->visual_capacity ? scene->visuals[id] : NULL;
        const tb__visual_mesh *mesh = visuals != NULL ? visuals->meshes[k] : NULL;
        memset(out_mesh, 0, sizeof *out_mesh);
        if (mesh != NULL) {
            out_mesh->vertices = mesh->vertices;
            out_mesh->vertex_count = mesh->vertex_count;
            out_mesh->triangles = mesh->triangles;
            out_mesh->triangle_count = mesh->triangle_count;
        }
    }
    return status;
}

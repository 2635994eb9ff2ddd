/* The scene's collision shapes: one per body (a plain shape or a compound of convex pieces),
 * set, read and placed at a state. */
#include "contact/body_visuals.h"
#include "contact/contact_pairs.h"

#include "core/validate.h"
#include "math/tb_math.h"
#include "scene/scene_internal.h"

#include <stdlib.h>
#include <string.h>

tb_shape tb_shape_default(void)
{
    tb_shape shape;
    memset(&shape, 0, sizeof shape);
    shape.type = TB_SHAPE_NONE;
    return shape;
}

/* Room for body_count shape slots, new ones empty; nothing changes on failure. */
static tb_status reserve_shapes(tb_scene *scene)
{
    const size_t count = scene->body_count;
    if (count <= scene->shape_capacity) {
        return TB_STATUS_OK;
    }
    tb__collision_shape **shapes = tb__realloc_array(scene->shapes, count, sizeof *shapes);
    if (shapes == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "shapes for %zu bodies", count);
    }
    for (size_t i = scene->shape_capacity; i < count; ++i) {
        shapes[i] = NULL;
    }
    scene->shapes = shapes;
    scene->shape_capacity = count;
    return TB_STATUS_OK;
}

/* Body id's shape becomes made (which may be NULL: none) and its visual meshes visuals (NULL:
 * none) when status, the setter's checks so far, is OK; both are freed when the call is
 * refused. */
static tb_status replace_shape(tb_scene *scene, size_t id, tb__collision_shape *made,
                               tb__body_visuals *visuals, tb_status status)
{
    if (status == TB_STATUS_OK) {
        status = reserve_shapes(scene);
    }
    if (status == TB_STATUS_OK) {
        status = tb__scene_reserve_visuals(scene);
    }
    if (status != TB_STATUS_OK) {
        free(made);
        tb__body_visuals_free(visuals);
        return status;
    }
    tb__collision_shape *old = scene->shapes[id];
    scene->shapes[id] = made;
    status = tb__scene_shapes_changed(scene, id); /* a ground plane's friction slots for it */
    if (status != TB_STATUS_OK) {
        scene->shapes[id] = old; /* the effects keep room for the shape: no harm */
        free(made);
        tb__body_visuals_free(visuals);
        return status;
    }
    free(old);
    tb__scene_swap_visuals(scene, id, visuals);
    ++scene->effects_generation;              /* contact effects' right-hand side changed */
    scene->set_since = "bodies' shapes were"; /* the next advance checks it as a start */
    tb__scene_wake_body(scene, id); /* asleep, its pairs would be skipped: by that check too */
    return TB_STATUS_OK;
}

/* The shape and the visual meshes of count pieces, made; *made NULL on a refusal. */
static tb_status make_pieces(tb_scene *scene, const tb_shape_piece *pieces, size_t count,
                             tb__collision_shape **made, tb__body_visuals **visuals)
{
    tb_status status = TB_STATUS_OK;
    *made = tb__collision_shape_make_pieces(pieces, count, scene->detail, &status);
    if (status == TB_STATUS_OK) {
        status = tb__body_visuals_of_pieces(pieces, count, scene->detail, visuals);
    }
    if (status != TB_STATUS_OK) {
        free(*made);
        *made = NULL;
    }
    return status;
}

tb_status tb_scene_set_body_shape(tb_scene *scene, size_t id, const tb_shape *shape)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_idle(scene, "tb_scene_set_body_shape");
    }
    tb__collision_shape *made = NULL;
    tb__body_visuals *visuals = NULL;
    if (status == TB_STATUS_OK && shape != NULL && shape->type != TB_SHAPE_NONE) {
        tb_shape_piece piece = tb_shape_piece_default();
        piece.shape = *shape; /* one piece at the identity pose is the plain shape */
        status = make_pieces(scene, &piece, 1, &made, &visuals);
    }
    return replace_shape(scene, id, made, visuals, status);
}

tb_status tb_scene_set_body_pieces(tb_scene *scene, size_t id, const tb_shape_piece *pieces,
                                   size_t count)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        status = tb__scene_check_idle(scene, "tb_scene_set_body_pieces");
    }
    tb__collision_shape *made = NULL;
    tb__body_visuals *visuals = NULL;
    if (status == TB_STATUS_OK) {
        status = make_pieces(scene, pieces, count, &made, &visuals);
    }
    return replace_shape(scene, id, made, visuals, status);
}

const tb__collision_shape *tb__scene_body_collision_shape(const tb_scene *scene, size_t id)
{
    return id < scene->shape_capacity ? scene->shapes[id] : NULL;
}

tb_status tb_scene_body_shape_type(const tb_scene *scene, size_t id, tb_shape_type *out_type)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_type == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_type is NULL");
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
        *out_type = shape != NULL ? shape->type : TB_SHAPE_NONE;
    }
    return status;
}

tb_status tb_scene_body_piece_count(const tb_scene *scene, size_t id, size_t *out_count)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_count == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_count is NULL");
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
        *out_count = shape != NULL ? tb__collision_shape_piece_count(shape) : 0;
    }
    return status;
}

/* The public description of a made shape (sizes back from half sizes). */
static tb_shape public_shape(const tb__collision_shape *c)
{
    tb_shape shape = tb_shape_default();
    shape.type = c->type;
    shape.radius = c->radius;
    shape.length = 2.0 * c->half_length;
    for (int k = 0; k < 3; ++k) {
        shape.size[k] = c->type == TB_SHAPE_BOX ? 2.0 * c->half[k] : 0.0;
        shape.semi_axes[k] = c->type == TB_SHAPE_ELLIPSOID ? c->half[k] : 0.0;
    }
    shape.vertices = c->vertices;
    shape.vertex_count = c->vertex_count;
    shape.radii = c->radii;
    return shape;
}

tb_status tb_scene_body_piece(const tb_scene *scene, size_t id, size_t k, tb_shape_piece *out_piece)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_piece == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_piece is NULL");
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    const tb__collision_shape *shape =
        status == TB_STATUS_OK ? tb__scene_body_collision_shape(scene, id) : NULL;
    const size_t count = shape != NULL ? tb__collision_shape_piece_count(shape) : 0;
    if (status == TB_STATUS_OK && k >= count) {
        status = tb__scene_fail((tb_scene *)scene, TB_STATUS_OUT_OF_RANGE,
                                "k: %zu is not a piece of body %zu (it has %zu)", k, id, count);
    }
    if (status == TB_STATUS_OK) {
        static const double identity[TB__POSE_SIZE] = {0, 0, 0, 1, 0, 0, 0};
        double pose[TB__POSE_SIZE];
        out_piece->shape = public_shape(tb__collision_shape_piece(shape, k, identity, pose));
        memcpy(out_piece->position, pose, sizeof out_piece->position);
        memcpy(out_piece->orientation, pose + 3, sizeof out_piece->orientation);
    }
    return status;
}

void tb__shape_pose(const tb_scene *scene, double t, const double *y, size_t id,
                    double out_pose[TB__POSE_SIZE])
{
    const tb_mass_properties *props = &scene->mass_props[id];
    const double *r = props->rotation;
    const double principal_from_shape[4] = {r[0], -r[1], -r[2], -r[3]};
    double x[3], q[4], offset[3];
    tb__body_pose_at(scene, t, y, id, x, q);
    tb__q_mul(out_pose + 3, q, principal_from_shape); /* shape -> principal -> world */
    tb__q_rotate(offset, out_pose + 3, props->center);
    tb__v3_set(out_pose, x[0] - offset[0], x[1] - offset[1], x[2] - offset[2]);
}

tb_status tb_scene_body_shape_bounds(const tb_scene *scene, const double *y, size_t id,
                                     double out_min[3], double out_max[3])
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (y == NULL || out_min == NULL || out_max == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "%s is NULL",
                              y == NULL         ? "y"
                              : out_min == NULL ? "out_min"
                                                : "out_max");
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    const tb__collision_shape *shape =
        status == TB_STATUS_OK ? tb__scene_body_collision_shape(scene, id) : NULL;
    if (status == TB_STATUS_OK && shape == NULL) {
        status = tb__scene_fail((tb_scene *)scene, TB_STATUS_INVALID_ARGUMENT,
                                "body %zu (%s) has no shape", id, scene->names[id]);
    }
    if (status == TB_STATUS_OK) {
        double pose[TB__POSE_SIZE];
        tb__shape_pose(scene, scene->time, y, id, pose);
        tb__collision_shape_bounds(shape, pose, out_min, out_max);
    }
    return status;
}

/* Compound shapes: a body's convex pieces, each a collision shape with its pose in the body's
 * shape frame, kept in one allocation; and the pieces of any shape placed at a pose. */
#include "contact/collision_shape.h"

#include "core/detail.h"
#include "core/validate.h"
#include "mass/mass_internal.h"
#include "math/tb_math.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PIECE_COUNT_MAX 1000000
#define POSITION_MAX_M 1e100 /* as a shape's sizes: squares stay finite */

tb_shape_piece tb_shape_piece_default(void)
{
    tb_shape_piece piece;
    memset(&piece, 0, sizeof piece);
    piece.shape = tb_shape_default();
    piece.orientation[0] = 1.0;
    return piece;
}

/* "pieces[k]." before the detail a check left (only when the body has several pieces). */
static tb_status name_piece(char *detail, tb_status status, size_t k, size_t count)
{
    if (status != TB_STATUS_OK && count > 1 && detail != NULL) {
        char message[TB_DETAIL_SIZE];
        snprintf(message, sizeof message, "%s", detail);
        tb__set_detail(detail, status, "pieces[%zu].%s", k, message);
    }
    return status;
}

static tb_status check_pose(const tb_shape_piece *piece, char *detail)
{
    for (int i = 0; i < 3; ++i) {
        const double p = piece->position[i];
        if (!isfinite(p) || fabs(p) > POSITION_MAX_M) {
            return tb__set_detail(detail,
                                  isfinite(p) ? TB_STATUS_INVALID_ARGUMENT : TB_STATUS_NOT_FINITE,
                                  "position[%d]: must be finite and within 1e100 m, got %g", i, p);
        }
    }
    tb_error error;
    const tb_status status = tb__check_unit_quaternion(piece->orientation, "orientation", &error);
    return status == TB_STATUS_OK ? status : tb__set_detail(detail, status, "%s", error.message);
}

static bool identity_pose(const tb_shape_piece *piece)
{
    return piece->position[0] == 0.0 && piece->position[1] == 0.0 && piece->position[2] == 0.0 &&
           piece->orientation[0] == 1.0 && piece->orientation[1] == 0.0 &&
           piece->orientation[2] == 0.0 && piece->orientation[3] == 0.0;
}

/* Bytes of a made shape: its header and its vertices (and radii). */
static size_t shape_bytes(const tb__collision_shape *s)
{
    return sizeof *s + s->vertex_count * (s->radii != NULL ? 4 : 3) * sizeof(double);
}

/* The pieces' shapes, made one by one into made[count] (NULL on a refusal); *total their bytes. */
static tb_status make_each(const tb_shape_piece *pieces, size_t count, tb__collision_shape **made,
                           size_t *total, char *detail)
{
    tb_status status = TB_STATUS_OK;
    *total = 0;
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        status = check_pose(&pieces[k], detail);
        if (status == TB_STATUS_OK && pieces[k].shape.type == TB_SHAPE_NONE) {
            status = tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                                    "shape.type: a piece must have a shape, got TB_SHAPE_NONE");
        }
        if (status == TB_STATUS_OK) {
            made[k] = tb__collision_shape_make(&pieces[k].shape, detail, &status);
        }
        if (status == TB_STATUS_OK && *total > (size_t)-1 / 2 - shape_bytes(made[k])) {
            status = tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "%zu pieces", count);
        }
        *total += status == TB_STATUS_OK ? shape_bytes(made[k]) : 0;
        name_piece(detail, status, k, count);
    }
    return status;
}

/* The compound's local bounds: the union of its pieces' boxes in its frame. */
static void compound_bounds(tb__collision_shape *c)
{
    for (int i = 0; i < 3; ++i) {
        c->local_min[i] = INFINITY;
        c->local_max[i] = -INFINITY;
    }
    for (size_t k = 0; k < c->piece_count; ++k) {
        double low[3], high[3];
        tb__collision_shape_bounds(c->pieces[k].shape, c->pieces[k].pose, low, high);
        for (int i = 0; i < 3; ++i) {
            c->local_min[i] = fmin(c->local_min[i], low[i]);
            c->local_max[i] = fmax(c->local_max[i], high[i]);
        }
    }
}

/* One block: the header, the piece table, then each piece's shape moved in (its vertices and
 * radii re-pointed to their new place). */
static tb__collision_shape *assemble(const tb_shape_piece *pieces, tb__collision_shape **made,
                                     size_t count, size_t shape_total)
{
    size_t table = 0;
    if (!tb__size_product(count, sizeof(tb__shape_piece), &table) ||
        table > (size_t)-1 / 2 - shape_total) {
        return NULL;
    }
    tb__collision_shape *c = calloc(1, sizeof *c + table + shape_total);
    if (c == NULL) {
        return NULL;
    }
    c->type = TB_SHAPE_COMPOUND;
    c->piece_count = count;
    tb__shape_piece *table_entries = (tb__shape_piece *)(void *)c->data;
    char *place = (char *)c->data + table;
    for (size_t k = 0; k < count; ++k) {
        const size_t bytes = shape_bytes(made[k]);
        tb__collision_shape *moved = (tb__collision_shape *)(void *)place;
        memcpy(moved, made[k], bytes);
        moved->vertices = made[k]->vertices != NULL ? moved->data : NULL;
        moved->radii = made[k]->radii != NULL ? moved->data + 3 * moved->vertex_count : NULL;
        table_entries[k].shape = moved;
        memcpy(table_entries[k].pose, pieces[k].position, 3 * sizeof(double));
        const double norm = tb__q_norm(pieces[k].orientation);
        for (int i = 0; i < 4; ++i) {
            table_entries[k].pose[3 + i] = pieces[k].orientation[i] / norm;
        }
        place += bytes;
    }
    c->pieces = table_entries;
    compound_bounds(c);
    return c;
}

tb__collision_shape *tb__collision_shape_make_pieces(const tb_shape_piece *pieces, size_t count,
                                                     char *detail, tb_status *out_status)
{
    if (pieces == NULL) {
        *out_status = tb__set_detail(detail, TB_STATUS_NULL_POINTER, "pieces is NULL");
        return NULL;
    }
    if (count == 0 || count > PIECE_COUNT_MAX) {
        *out_status = tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                                     "count: must be in [1, %d], got %zu", PIECE_COUNT_MAX, count);
        return NULL;
    }
    tb__collision_shape **made = calloc(count, sizeof *made);
    if (made == NULL) {
        *out_status = tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "%zu pieces", count);
        return NULL;
    }
    size_t total = 0;
    *out_status = make_each(pieces, count, made, &total, detail);
    tb__collision_shape *c = NULL;
    if (*out_status == TB_STATUS_OK && count == 1 && identity_pose(&pieces[0])) {
        c = made[0]; /* the plain shape */
        made[0] = NULL;
    } else if (*out_status == TB_STATUS_OK) {
        c = assemble(pieces, made, count, total);
        *out_status = c != NULL
                          ? TB_STATUS_OK
                          : tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "%zu pieces", count);
    }
    for (size_t k = 0; k < count; ++k) {
        free(made[k]);
    }
    free(made);
    return c;
}

size_t tb__collision_shape_piece_count(const tb__collision_shape *shape)
{
    return shape->type == TB_SHAPE_COMPOUND ? shape->piece_count : 1;
}

const tb__collision_shape *tb__collision_shape_piece(const tb__collision_shape *shape, size_t k,
                                                     const double pose[TB__POSE_SIZE],
                                                     double out_pose[TB__POSE_SIZE])
{
    if (shape->type != TB_SHAPE_COMPOUND) {
        memcpy(out_pose, pose, TB__POSE_SIZE * sizeof(double));
        return shape;
    }
    const tb__shape_piece *piece = &shape->pieces[k];
    double offset[3];
    tb__q_rotate(offset, pose + 3, piece->pose);
    tb__v3_set(out_pose, pose[0] + offset[0], pose[1] + offset[1], pose[2] + offset[2]);
    tb__q_mul(out_pose + 3, pose + 3, piece->pose + 3); /* piece -> body shape -> world */
    return piece->shape;
}

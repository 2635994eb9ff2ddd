/* Scene files: a body's "shape" given as a list of convex pieces, each a shape object with an
 * optional "position" and "orientation" in the body's shape frame. The body's mass properties
 * combine the pieces' (one density for all; a given mass is shared by volume), and its contact
 * points are the pieces' own, carried into the body's frame. */
#include "io/scene_file_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The pieces' parts for tb_mass_combine and their contact points, gathered as they load. */
typedef struct pieces_build {
    tb_mass_part *parts;
    tb_contact_point *points;
    size_t point_count, support;
} pieces_build;

/* "position" and "orientation" of piece at item into out (defaults: origin, identity). */
static tb_status piece_pose(tb__loader *ld, const json_t *piece, const char *item,
                            tb_shape_piece *out)
{
    tb_status status = tb__json_vector(ld, piece, item, "position", 3, false, out->position);
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, piece, item, "orientation", 4, false, out->orientation);
    }
    const double norm = tb__q_norm(out->orientation);
    if (status == TB_STATUS_OK && fabs(norm - 1.0) > 1e-4) {
        status = tb__load_fail(
            ld, TB_STATUS_BAD_SCENE, item,
            "orientation: must be a unit quaternion (w, x, y, z) to 1e-4, got |q| = %g", norm);
    }
    for (int k = 0; k < 4 && status == TB_STATUS_OK; ++k) {
        out->orientation[k] /= norm;
    }
    return status;
}

/* The piece's contact points carried into the body's frame and appended to p. */
static tb_status add_points(tb__loader *ld, const char *item, const tb__body_build *piece,
                            const tb_shape_piece *pose, pieces_build *p)
{
    const tb_contact_point *own =
        piece->contacts.many ? piece->contacts.many : piece->contacts.points;
    const size_t n = piece->contacts.count;
    tb_contact_point *grown = NULL;
    if (p->point_count <= (size_t)-1 / 2 - n) {
        grown = tb__realloc_array(p->points, p->point_count + n + 1, sizeof *grown);
    }
    if (grown == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, item, "%zu contact points", n);
    }
    p->points = grown;
    for (size_t k = 0; k < n; ++k) {
        tb_contact_point *to = &p->points[p->point_count + k];
        tb__q_rotate(to->position, pose->orientation, own[k].position);
        tb__v3_axpy(to->position, 1.0, pose->position);
        to->radius = own[k].radius;
    }
    p->point_count += n;
    p->support = piece->contacts.support > p->support ? piece->contacts.support : p->support;
    return TB_STATUS_OK;
}

/* Piece k at item: its shape, pose, mass properties at density (kg/m^3) and points. */
static tb_status load_piece(tb__loader *ld, const json_t *piece, const char *item, double density,
                            size_t k, tb__body_build *b, pieces_build *p)
{
    const char *type = NULL;
    tb_status status = tb__load_shape_object(ld, piece, item, true, &type); /* not points */
    tb_shape_piece *out = &b->pieces[k];
    *out = tb_shape_piece_default();
    if (status == TB_STATUS_OK) {
        status = piece_pose(ld, piece, item, out);
    }
    tb__body_build one;
    memset(&one, 0, sizeof one);
    one.shape = tb_shape_default();
    one.piece = true;
    if (status == TB_STATUS_OK) {
        status = tb__load_shape_mass(ld, piece, item, item, type, TB_MASS_DENSITY, density, &one);
    }
    b->piece_vertices[k] = one.shape_vertices; /* freed with the body */
    b->piece_triangles[k] = one.shape_triangles;
    out->shape = one.shape;
    if (status == TB_STATUS_OK) {
        status = add_points(ld, item, &one, out, p);
    }
    p->parts[k].props = one.def.mass;
    memcpy(p->parts[k].position, out->position, sizeof out->position);
    memcpy(p->parts[k].orientation, out->orientation, sizeof out->orientation);
    free(one.contacts.many);
    return status;
}

/* The pieces' combination; a given mass M scales the combination at density 1: mass and
 * moments by M / m (the centre and the principal axes do not change with a common density). */
static tb_status combine(tb__loader *ld, const char *path, const pieces_build *p, size_t count,
                         tb_mass_mode mode, double value, tb_mass_properties *out)
{
    tb_error error;
    tb__clear_error(&error);
    tb_status status = tb_mass_combine(p->parts, count, out, &error);
    if (status == TB_STATUS_OK && mode == TB_MASS_GIVEN) {
        const double scale = value / out->mass;
        out->mass = value;
        for (int k = 0; k < 3; ++k) {
            out->moments[k] *= scale;
        }
        status = tb_mass_validate(out, &error);
    }
    return tb__mass_result(ld, status, path, &error);
}

tb_status tb__load_pieces(tb__loader *ld, const json_t *body, const char *path, tb__body_build *b)
{
    const json_t *list = json_object_get(body, "shape");
    const size_t count = json_array_size(list);
    if (count == 0) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "shape: a list of pieces must not be empty");
    }
    tb_mass_mode mode = TB_MASS_GIVEN;
    double value = 0.0;
    tb_status status = tb__load_body_mass_mode(ld, body, path, b, &mode, &value);
    if (status != TB_STATUS_OK) {
        return status;
    }
    pieces_build p = {tb__malloc_array(count, sizeof *p.parts), NULL, 0, 0};
    b->pieces = tb__malloc_array(count, sizeof *b->pieces);
    b->piece_vertices = calloc(count, sizeof *b->piece_vertices);
    b->piece_triangles = calloc(count, sizeof *b->piece_triangles);
    if (p.parts == NULL || b->pieces == NULL || b->piece_vertices == NULL ||
        b->piece_triangles == NULL) {
        free(p.parts);
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "%zu pieces", count);
    }
    b->piece_count = count;
    const double density = mode == TB_MASS_DENSITY ? value : 1.0;
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        char item[160];
        tb__path_index(item, sizeof item, path, "shape", k);
        status = load_piece(ld, json_array_get(list, k), item, density, k, b, &p);
    }
    if (status == TB_STATUS_OK) {
        status = combine(ld, path, &p, count, mode, value, &b->def.mass);
    }
    free(b->contacts.many);
    b->contacts.many = p.points;
    b->contacts.count = p.point_count;
    b->contacts.support = p.support;
    free(p.parts);
    return status;
}

void tb__free_pieces(tb__body_build *b)
{
    for (size_t k = 0; k < b->piece_count; ++k) {
        free(b->piece_vertices != NULL ? b->piece_vertices[k] : NULL);
        free(b->piece_triangles != NULL ? b->piece_triangles[k] : NULL);
    }
    free(b->piece_vertices);
    free(b->piece_triangles);
    free(b->pieces);
}

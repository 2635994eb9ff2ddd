/* Convex hull vertices by incremental construction (the beneath-beyond method, as in
 * O'Rourke, Computational Geometry in C, ch. 4): start from a tetrahedron of extreme points;
 * for each point outside the current hull, delete the faces it sees and join their horizon
 * edges to it. Faces keep outward unit normals; "sees" means more than eps above the plane. */
#include "contact/convex_hull.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

typedef struct face {
    size_t v[3];   /* counter-clockwise seen from outside */
    double n[3];   /* outward unit normal */
    double offset; /* n . x on the plane */
} face;

typedef struct hull {
    const double *p;
    double eps;
    face *faces;
    size_t face_count, face_capacity;
    size_t (*edges)[2]; /* the seen faces' edges, scratch */
    size_t edge_capacity;
} hull;

static const double *point(const hull *h, size_t i)
{
    return h->p + 3 * i;
}

static double height(const hull *h, const face *f, size_t i)
{
    return tb__v3_dot(f->n, point(h, i)) - f->offset;
}

/* The plane through a, b, c; false if they are (nearly) collinear. */
static bool make_face(const hull *h, size_t a, size_t b, size_t c, face *out)
{
    double ab[3], ac[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = point(h, b)[k] - point(h, a)[k];
        ac[k] = point(h, c)[k] - point(h, a)[k];
    }
    tb__v3_cross(out->n, ab, ac);
    const double length = tb__v3_norm(out->n);
    if (!(length > 0.0)) {
        return false;
    }
    tb__v3_set(out->n, out->n[0] / length, out->n[1] / length, out->n[2] / length);
    out->offset = tb__v3_dot(out->n, point(h, a));
    out->v[0] = a;
    out->v[1] = b;
    out->v[2] = c;
    return true;
}

static bool push_face(hull *h, size_t a, size_t b, size_t c)
{
    if (h->face_count == h->face_capacity) {
        const size_t capacity = 2 * h->face_capacity + 16;
        face *faces = realloc(h->faces, capacity * sizeof *faces);
        if (faces == NULL) {
            return false;
        }
        h->faces = faces;
        h->face_capacity = capacity;
    }
    face *f = &h->faces[h->face_count];
    if (make_face(h, a, b, c, f)) {
        ++h->face_count;
    }
    return true; /* a sliver face (collinear corners) is dropped: its neighbours cover it */
}

static double distance_to_line(const hull *h, size_t a, size_t b, size_t i)
{
    double ab[3], ai[3], c[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = point(h, b)[k] - point(h, a)[k];
        ai[k] = point(h, i)[k] - point(h, a)[k];
    }
    tb__v3_cross(c, ab, ai);
    const double length = tb__v3_norm(ab);
    return length > 0.0 ? tb__v3_norm(c) / length : 0.0;
}

/* The index maximising score over all points. */
static size_t farthest(const hull *h, size_t count,
                       double (*score)(const hull *, const size_t *, size_t), const size_t *seed,
                       double *out_score)
{
    size_t best = 0;
    double best_score = -1.0;
    for (size_t i = 0; i < count; ++i) {
        const double s = score(h, seed, i);
        if (s > best_score) {
            best_score = s;
            best = i;
        }
    }
    *out_score = best_score;
    return best;
}

static double score_distance(const hull *h, const size_t *seed, size_t i)
{
    double d[3];
    for (int k = 0; k < 3; ++k) {
        d[k] = point(h, i)[k] - point(h, seed[0])[k];
    }
    return tb__v3_norm(d);
}

static double score_line(const hull *h, const size_t *seed, size_t i)
{
    return distance_to_line(h, seed[0], seed[1], i);
}

static double score_plane(const hull *h, const size_t *seed, size_t i)
{
    face f;
    return make_face(h, seed[0], seed[1], seed[2], &f) ? fabs(height(h, &f, i)) : 0.0;
}

/* Four points spanning the most volume we can find cheaply; false when the set is flat. */
static tb_status start_tetrahedron(hull *h, size_t count, size_t out[4], char *detail)
{
    double s;
    out[0] = 0;
    out[0] = farthest(h, count, score_distance, out, &s); /* an extreme point */
    out[1] = farthest(h, count, score_distance, out, &s);
    if (!(s > h->eps)) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "vertices: all at one point (a convex shape needs volume)");
    }
    out[2] = farthest(h, count, score_line, out, &s);
    if (!(s > h->eps)) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "vertices: all on one line (a convex shape needs volume)");
    }
    out[3] = farthest(h, count, score_plane, out, &s);
    if (!(s > h->eps)) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "vertices: all in one plane (a convex shape needs volume)");
    }
    return TB_STATUS_OK;
}

static bool start_faces(hull *h, const size_t t[4])
{
    face f;
    make_face(h, t[0], t[1], t[2], &f);
    const bool flip = height(h, &f, t[3]) > 0.0; /* t[3] must lie below face 012 */
    const size_t a = t[0], b = flip ? t[2] : t[1], c = flip ? t[1] : t[2], d = t[3];
    return push_face(h, a, b, c) && push_face(h, a, d, b) && push_face(h, b, d, c) &&
           push_face(h, c, d, a);
}

static bool has_edge(const hull *h, size_t edge_count, size_t from, size_t to)
{
    for (size_t e = 0; e < edge_count; ++e) {
        if (h->edges[e][0] == from && h->edges[e][1] == to) {
            return true;
        }
    }
    return false;
}

/* The edges of the faces i sees, which are then removed; false when memory runs out. */
static bool collect_seen_edges(hull *h, size_t i, size_t *out_edge_count)
{
    size_t edge_count = 0, kept = 0;
    for (size_t f = 0; f < h->face_count; ++f) {
        if (height(h, &h->faces[f], i) <= h->eps) {
            h->faces[kept++] = h->faces[f];
            continue;
        }
        if (edge_count + 3 > h->edge_capacity) {
            const size_t capacity = 2 * h->edge_capacity + 48;
            size_t(*edges)[2] = realloc(h->edges, capacity * sizeof *edges);
            if (edges == NULL) {
                return false;
            }
            h->edges = edges;
            h->edge_capacity = capacity;
        }
        for (int k = 0; k < 3; ++k) {
            h->edges[edge_count][0] = h->faces[f].v[k];
            h->edges[edge_count++][1] = h->faces[f].v[(k + 1) % 3];
        }
    }
    h->face_count = kept;
    *out_edge_count = edge_count;
    return true;
}

/* Adds point i if it lies outside: the horizon edges (seen on one side only) fan to i. */
static bool add_point(hull *h, size_t i)
{
    size_t edge_count = 0;
    if (!collect_seen_edges(h, i, &edge_count)) {
        return false;
    }
    for (size_t e = 0; e < edge_count; ++e) {
        const size_t from = h->edges[e][0], to = h->edges[e][1];
        if (!has_edge(h, edge_count, to, from) && !push_face(h, from, to, i)) {
            return false;
        }
    }
    return true;
}

static double extent(const double *points, size_t count)
{
    double largest = 0.0;
    for (int k = 0; k < 3 && count > 0; ++k) {
        double low = points[k], high = points[k];
        for (size_t i = 1; i < count; ++i) {
            low = fmin(low, points[3 * i + k]);
            high = fmax(high, points[3 * i + k]);
        }
        largest = fmax(largest, high - low);
    }
    return largest;
}

/* points scaled by the power of two nearest 1 / their extent, exactly (no bits lost): the hull's
 * cross products of differences are then near 1 for any size the shapes allow (1e100 m cubed
 * overflows, 1e-160 m squared underflows), and the hull of the copy is the scaled hull. */
static double *scaled_copy(const double *points, size_t count)
{
    int exponent = 0;
    frexp(extent(points, count), &exponent);
    double *copy = count <= ((size_t)-1) / (3 * sizeof(double))
                       ? malloc((count > 0 ? 3 * count : 1) * sizeof(double))
                       : NULL;
    for (size_t i = 0; copy != NULL && i < 3 * count; ++i) {
        copy[i] = ldexp(points[i], -exponent);
    }
    return copy;
}

tb_status tb__convex_hull(const double *points, size_t count, unsigned char *on_hull, char *detail)
{
    double *scaled = scaled_copy(points, count);
    if (scaled == NULL) {
        return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "convex hull of %zu vertices",
                              count);
    }
    hull h = {.p = scaled, .eps = 1e-10 * extent(scaled, count)};
    size_t t[4] = {0, 0, 0, 0};
    tb_status status = count >= 4 ? start_tetrahedron(&h, count, t, detail)
                                  : tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                                                   "vertex_count: a convex shape needs at least "
                                                   "4 vertices, got %zu",
                                                   count);
    bool ok = status != TB_STATUS_OK || start_faces(&h, t);
    for (size_t i = 0; i < count && ok && status == TB_STATUS_OK; ++i) {
        ok = add_point(&h, i);
    }
    if (!ok) {
        status =
            tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "convex hull of %zu vertices", count);
    }
    if (status == TB_STATUS_OK) {
        memset(on_hull, 0, count);
        for (size_t f = 0; f < h.face_count; ++f) {
            for (int k = 0; k < 3; ++k) {
                on_hull[h.faces[f].v[k]] = 1;
            }
        }
    }
    free(h.faces);
    free(h.edges);
    free(scaled);
    return status;
}

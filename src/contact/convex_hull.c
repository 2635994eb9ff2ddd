/* Convex hull vertices by quickhull (Barber, Dobkin and Huhdanpaa, "The Quickhull Algorithm for
 * Convex Hulls", ACM TOMS 22(4), 1996): start from a tetrahedron of extreme points and give each
 * other point to one face it lies above (the face's outside set); then, while a face has an
 * outside set, take its farthest point, find the faces it sees by walking from that face across
 * neighbours, replace them by a fan from their horizon to the point, and hand their outside
 * points to the new faces (a point above none of them is inside for good). Each point is
 * tested against the faces of the cones that cover it, so the work is O(n log n) expected for
 * points in general position (O(n r) for r hull vertices at worst), not O(n F) as when every
 * point is tested against every face. Faces keep outward unit normals and their three
 * neighbours; "sees" means more than eps above the plane. A dead face's slot is reused. */
#include "contact/convex_hull.h"
#include "contact/hull_points.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define NONE UINT32_MAX

typedef struct face {
    double n[3];       /* outward unit normal */
    double offset;     /* n . x on the plane */
    uint32_t v[3];     /* counter-clockwise seen from outside */
    uint32_t next[3];  /* the face across edge v[k] -> v[k + 1] */
    uint32_t outside;  /* first point of its outside set (linked by hull.link), NONE */
    uint32_t farthest; /* the outside point farthest above it, NONE */
    uint32_t mark;     /* the search that found it visible */
    bool alive;
} face;

/* A horizon edge a -> b of the visible region, with the face beyond it. */
typedef struct rim {
    uint32_t a, b, beyond;
} rim;

/* A growable array of elements of `size` bytes. */
typedef struct list {
    void *data;
    size_t count, capacity;
} list;

typedef struct hull {
    const double *p;
    double eps;
    list faces;       /* face */
    list free_faces;  /* uint32_t: dead slots */
    list pending;     /* uint32_t: faces that were given outside points */
    list visible;     /* uint32_t: the current search's visible faces */
    list horizon;     /* rim */
    list cone;        /* face: the new faces before they are placed */
    uint32_t *link;   /* per point: the next point of the same outside set */
    uint32_t *rim_of; /* per point: the horizon edge starting at it (valid when rim_mark) */
    uint32_t *rim_mark;
    uint32_t search;
} hull;

static bool reserve(list *l, size_t size, size_t count)
{
    if (count <= l->capacity) {
        return true;
    }
    const size_t capacity = count > 2 * l->capacity + 16 ? count : 2 * l->capacity + 16;
    void *data = capacity <= SIZE_MAX / size ? realloc(l->data, capacity * size) : NULL;
    if (data == NULL) {
        return false;
    }
    l->data = data;
    l->capacity = capacity;
    return true;
}

static bool push_index(list *l, uint32_t value)
{
    if (!reserve(l, sizeof value, l->count + 1)) {
        return false;
    }
    ((uint32_t *)l->data)[l->count++] = value;
    return true;
}

static face *faces(const hull *h)
{
    return h->faces.data;
}

static const double *point(const hull *h, uint32_t i)
{
    return h->p + 3 * (size_t)i;
}

static double height(const hull *h, const face *f, uint32_t i)
{
    return tb__v3_dot(f->n, point(h, i)) - f->offset;
}

/* The plane through a, b, c; false if they are (nearly) collinear. */
static bool make_face(const hull *h, uint32_t a, uint32_t b, uint32_t c, face *out)
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
    const uint32_t v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
        out->v[k] = v[k];
        out->next[k] = NONE;
    }
    out->outside = out->farthest = NONE;
    out->mark = 0;
    out->alive = true;
    return true;
}

/* A slot for a new face (a dead one if any); NONE when memory runs out. */
static uint32_t new_slot(hull *h)
{
    if (h->free_faces.count > 0) {
        return ((uint32_t *)h->free_faces.data)[--h->free_faces.count];
    }
    if (!reserve(&h->faces, sizeof(face), h->faces.count + 1)) {
        return NONE;
    }
    return (uint32_t)h->faces.count++;
}

/* Gives point i to face f's outside set if it lies above f. */
static bool give(hull *h, uint32_t f, uint32_t i)
{
    face *x = &faces(h)[f];
    const double above = height(h, x, i);
    if (!(above > h->eps)) {
        return false;
    }
    h->link[i] = x->outside;
    x->outside = i;
    if (x->farthest == NONE || above > height(h, x, x->farthest)) {
        x->farthest = i;
    }
    return true;
}

static double distance_to_line(const hull *h, uint32_t a, uint32_t b, uint32_t i)
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

static double score_distance(const hull *h, const uint32_t *seed, uint32_t i)
{
    double d[3];
    for (int k = 0; k < 3; ++k) {
        d[k] = point(h, i)[k] - point(h, seed[0])[k];
    }
    return tb__v3_norm(d);
}

static double score_line(const hull *h, const uint32_t *seed, uint32_t i)
{
    return distance_to_line(h, seed[0], seed[1], i);
}

static double score_plane(const hull *h, const uint32_t *seed, uint32_t i)
{
    face f;
    return make_face(h, seed[0], seed[1], seed[2], &f) ? fabs(height(h, &f, i)) : 0.0;
}

/* The index maximising score over all points. */
static uint32_t farthest(const hull *h, size_t count,
                         double (*score)(const hull *, const uint32_t *, uint32_t),
                         const uint32_t *seed, double *out_score)
{
    uint32_t best = 0;
    double best_score = -1.0;
    for (uint32_t i = 0; i < count; ++i) {
        const double s = score(h, seed, i);
        if (s > best_score) {
            best_score = s;
            best = i;
        }
    }
    *out_score = best_score;
    return best;
}

/* Four points spanning the most volume we can find cheaply; refused when the set is flat. */
static tb_status start_tetrahedron(hull *h, size_t count, uint32_t out[4], char *detail)
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

/* The edge index k of face f that runs from a to b, or 3. */
static int edge_from(const face *f, uint32_t a, uint32_t b)
{
    for (int k = 0; k < 3; ++k) {
        if (f->v[k] == a && f->v[(k + 1) % 3] == b) {
            return k;
        }
    }
    return 3;
}

/* The tetrahedron's four faces, their neighbours, and every other point given to the first
 * face it lies above. */
static bool start_faces(hull *h, size_t count, const uint32_t t[4])
{
    face f;
    make_face(h, t[0], t[1], t[2], &f);
    const bool flip = height(h, &f, t[3]) > 0.0; /* t[3] must lie below face 012 */
    const uint32_t a = t[0], b = flip ? t[2] : t[1], c = flip ? t[1] : t[2], d = t[3];
    const uint32_t corners[4][3] = {{a, b, c}, {a, d, b}, {b, d, c}, {c, d, a}};
    if (!reserve(&h->faces, sizeof(face), 4)) {
        return false;
    }
    h->faces.count = 4;
    for (int j = 0; j < 4; ++j) {
        make_face(h, corners[j][0], corners[j][1], corners[j][2], &faces(h)[j]);
    }
    for (int j = 0; j < 4; ++j) {
        face *x = &faces(h)[j];
        for (int k = 0; k < 3; ++k) {
            for (uint32_t other = 0; other < 4; ++other) {
                if (edge_from(&faces(h)[other], x->v[(k + 1) % 3], x->v[k]) < 3) {
                    x->next[k] = other;
                }
            }
        }
    }
    for (uint32_t i = 0; i < count; ++i) {
        for (uint32_t j = 0; j < 4 && i != a && i != b && i != c && i != d; ++j) {
            if (give(h, j, i)) {
                break;
            }
        }
    }
    for (uint32_t j = 0; j < 4; ++j) {
        if (faces(h)[j].outside != NONE && !push_index(&h->pending, j)) {
            return false;
        }
    }
    return true;
}

/* The faces p sees, found by walking from f0 (which it sees) across neighbours, into visible;
 * the edges between a seen face and an unseen one into horizon. */
static bool find_visible(hull *h, uint32_t f0, uint32_t p)
{
    h->visible.count = h->horizon.count = 0;
    faces(h)[f0].mark = ++h->search;
    if (!push_index(&h->visible, f0)) {
        return false;
    }
    for (size_t j = 0; j < h->visible.count; ++j) {
        const face *g = &faces(h)[((uint32_t *)h->visible.data)[j]];
        for (int k = 0; k < 3; ++k) {
            face *beyond = &faces(h)[g->next[k]];
            if (beyond->mark == h->search) {
                continue;
            }
            if (height(h, beyond, p) > h->eps) {
                beyond->mark = h->search;
                if (!push_index(&h->visible, g->next[k])) {
                    return false;
                }
                continue;
            }
            if (!reserve(&h->horizon, sizeof(rim), h->horizon.count + 1)) {
                return false;
            }
            ((rim *)h->horizon.data)[h->horizon.count++] =
                (rim){g->v[k], g->v[(k + 1) % 3], g->next[k]};
        }
    }
    return true;
}

/* True when the horizon is one loop (each of its vertices starts one edge and ends one), and
 * the new faces, one per horizon edge to p, are all planes: then they go into h->cone. Rounding
 * can make the seen region touch itself at a vertex; the point is then left out (it lies within
 * rounding of the hull). */
static bool plan_cone(hull *h, uint32_t p, bool *out_of_memory)
{
    const rim *edges = h->horizon.data;
    const size_t count = h->horizon.count;
    for (size_t e = 0; e < count; ++e) {
        if (h->rim_mark[edges[e].a] == h->search) {
            return false;
        }
        h->rim_mark[edges[e].a] = h->search;
        h->rim_of[edges[e].a] = (uint32_t)e;
    }
    for (size_t e = 0; e < count; ++e) {
        if (h->rim_mark[edges[e].b] != h->search) {
            return false;
        }
    }
    if (count < 3 || !reserve(&h->cone, sizeof(face), count)) {
        *out_of_memory = count >= 3;
        return false;
    }
    for (size_t e = 0; e < count; ++e) {
        if (!make_face(h, edges[e].a, edges[e].b, p, &((face *)h->cone.data)[e])) {
            return false;
        }
    }
    h->cone.count = count;
    return true;
}

/* Places the planned faces in slots (their ids replace the cone's marks) and joins them to the
 * faces beyond the horizon and to each other. */
static bool place_cone(hull *h)
{
    face *cone = h->cone.data;
    const rim *edges = h->horizon.data;
    for (size_t e = 0; e < h->cone.count; ++e) {
        const uint32_t slot = new_slot(h);
        if (slot == NONE) {
            return false;
        }
        cone[e].mark = slot;
    }
    for (size_t e = 0; e < h->cone.count; ++e) {
        face *x = &faces(h)[cone[e].mark];
        *x = cone[e];
        x->mark = 0;
    }
    for (size_t e = 0; e < h->cone.count; ++e) { /* all placed first: links go both ways */
        face *x = &faces(h)[cone[e].mark];
        x->next[0] = edges[e].beyond;
        face *beyond = &faces(h)[edges[e].beyond];
        beyond->next[edge_from(beyond, edges[e].b, edges[e].a)] = cone[e].mark;
        const uint32_t after = cone[h->rim_of[edges[e].b]].mark; /* b -> c -> p */
        x->next[1] = after;
        faces(h)[after].next[2] = cone[e].mark;
    }
    return true;
}

/* The seen faces' outside points (but p) go to the first new face they lie above; the seen
 * faces die, and the new faces with points wait their turn. */
static bool hand_over(hull *h, uint32_t p)
{
    const face *cone = h->cone.data;
    for (size_t j = 0; j < h->visible.count; ++j) {
        const uint32_t f = ((uint32_t *)h->visible.data)[j];
        uint32_t i = faces(h)[f].outside;
        while (i != NONE) {
            const uint32_t next = h->link[i];
            for (size_t e = 0; e < h->cone.count && i != p; ++e) {
                if (give(h, cone[e].mark, i)) {
                    break;
                }
            }
            i = next;
        }
        faces(h)[f].alive = false;
        faces(h)[f].outside = faces(h)[f].farthest = NONE;
        if (!push_index(&h->free_faces, f)) {
            return false;
        }
    }
    for (size_t e = 0; e < h->cone.count; ++e) {
        if (faces(h)[cone[e].mark].outside != NONE && !push_index(&h->pending, cone[e].mark)) {
            return false;
        }
    }
    return true;
}

/* Takes p out of face f's outside set (it is left out of the hull). */
static void leave_out(hull *h, uint32_t f, uint32_t p)
{
    face *x = &faces(h)[f];
    uint32_t *at = &x->outside;
    while (*at != p) {
        at = &h->link[*at];
    }
    *at = h->link[p];
    x->farthest = NONE;
    for (uint32_t i = x->outside; i != NONE; i = h->link[i]) {
        if (x->farthest == NONE || height(h, x, i) > height(h, x, x->farthest)) {
            x->farthest = i;
        }
    }
}

/* Quickhull's loop: each pass takes one point out of the outside sets, so there are at most as
 * many passes as points; false when memory runs out. */
static bool grow(hull *h)
{
    while (h->pending.count > 0) {
        const uint32_t f = ((uint32_t *)h->pending.data)[--h->pending.count];
        if (!faces(h)[f].alive || faces(h)[f].outside == NONE) {
            continue;
        }
        const uint32_t p = faces(h)[f].farthest;
        bool out_of_memory = false;
        if (!find_visible(h, f, p)) {
            return false;
        }
        if (!plan_cone(h, p, &out_of_memory)) {
            if (out_of_memory) {
                return false;
            }
            leave_out(h, f, p);
            if (faces(h)[f].outside != NONE && !push_index(&h->pending, f)) {
                return false;
            }
            continue;
        }
        if (!place_cone(h) || !hand_over(h, p)) {
            return false;
        }
    }
    return true;
}

static void release(hull *h, double *scaled, uint32_t *order)
{
    free(order);
    list *lists[] = {&h->faces, &h->free_faces, &h->pending, &h->visible, &h->horizon, &h->cone};
    for (size_t k = 0; k < sizeof lists / sizeof lists[0]; ++k) {
        free(lists[k]->data);
    }
    free(h->link);
    free(h->rim_of);
    free(h->rim_mark);
    free(scaled);
}

/* The live faces' corners (input indices), three per face, into a new array (NULL when memory
 * runs out). */
static uint32_t *triangles(const hull *h, const uint32_t *order, size_t *out_count)
{
    size_t count = 0;
    for (size_t f = 0; f < h->faces.count; ++f) {
        count += faces(h)[f].alive;
    }
    uint32_t *out = malloc((count > 0 ? 3 * count : 1) * sizeof *out);
    for (size_t f = 0, w = 0; out != NULL && f < h->faces.count; ++f) {
        if (faces(h)[f].alive) {
            for (int k = 0; k < 3; ++k) {
                out[3 * w + (size_t)k] = order[faces(h)[f].v[k]];
            }
            ++w;
        }
    }
    *out_count = count;
    return out;
}

static tb_status build(hull *h, size_t count, char *detail)
{
    if (count < 4) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "vertex_count: a convex shape needs at least 4 vertices, got %zu",
                              count);
    }
    uint32_t t[4] = {0, 0, 0, 0};
    const tb_status status = start_tetrahedron(h, count, t, detail);
    if (status != TB_STATUS_OK) {
        return status;
    }
    h->link = malloc(count * sizeof *h->link);
    h->rim_of = malloc(count * sizeof *h->rim_of);
    h->rim_mark = calloc(count, sizeof *h->rim_mark);
    if (h->link == NULL || h->rim_of == NULL || h->rim_mark == NULL || !start_faces(h, count, t) ||
        !grow(h)) {
        return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "convex hull of %zu vertices",
                              count);
    }
    return TB_STATUS_OK;
}

tb_status tb__convex_hull_triangles(const double *points, size_t count, unsigned char *on_hull,
                                    uint32_t **out_triangles, size_t *out_count, char *detail)
{
    uint32_t *order = NULL;
    double *scaled = tb__hull_points(points, count, &order);
    if (scaled == NULL) {
        return count > TB__HULL_MAX_POINTS
                   ? tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                                    "vertex_count: at most 2^30 points for a convex hull, got %zu",
                                    count)
                   : tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "convex hull of %zu vertices",
                                    count);
    }
    hull h = {.p = scaled, .eps = 1e-10 * tb__hull_extent(scaled, count)};
    tb_status status = build(&h, count, detail);
    if (status == TB_STATUS_OK && out_triangles != NULL) {
        *out_triangles = triangles(&h, order, out_count);
        status = *out_triangles != NULL ? TB_STATUS_OK
                                        : tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY,
                                                         "convex hull of %zu vertices", count);
    }
    if (status == TB_STATUS_OK) {
        memset(on_hull, 0, count);
        for (size_t f = 0; f < h.faces.count; ++f) {
            for (int k = 0; k < 3 && faces(&h)[f].alive; ++k) {
                on_hull[order[faces(&h)[f].v[k]]] = 1;
            }
        }
    }
    release(&h, scaled, order);
    return status;
}

tb_status tb__convex_hull(const double *points, size_t count, unsigned char *on_hull, char *detail)
{
    return tb__convex_hull_triangles(points, count, on_hull, NULL, NULL, detail);
}

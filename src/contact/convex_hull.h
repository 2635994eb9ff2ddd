/* Private: the vertices of the convex hull of a point set (set-up only; allocates). */
#ifndef TUMBLE_CONVEX_HULL_H
#define TUMBLE_CONVEX_HULL_H

#include "tumble/status.h"

#include <stddef.h>
#include <stdint.h>

/* Marks in on_hull[count] (true/false) the points that are vertices of the convex hull of
 * points[3 * count], by quickhull (each point outside the hull so far replaces the faces it sees
 * by a fan from their horizon; O(n log n) expected). A point within 1e-10 of the set's extent of
 * the hull is treated as inside, so near-duplicates and points on faces are dropped: the hull
 * kept differs from the exact one by at most that much. TB_STATUS_INVALID_ARGUMENT (detail
 * names why, TB_DETAIL_SIZE bytes) when the points span no volume (all on a plane, a line or
 * one spot); TB_STATUS_OUT_OF_MEMORY. */
tb_status tb__convex_hull(const double *points, size_t count, unsigned char *on_hull, char *detail);

/* As tb__convex_hull, and the hull's triangles (three indices into points each, counter-clockwise
 * seen from outside) in a new array *out_triangles (3 * *out_count; the caller frees it). */
tb_status tb__convex_hull_triangles(const double *points, size_t count, unsigned char *on_hull,
                                    uint32_t **out_triangles, size_t *out_count, char *detail);

#endif

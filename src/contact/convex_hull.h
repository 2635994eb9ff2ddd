/* Private: the vertices of the convex hull of a point set (set-up only; allocates). */
#ifndef TUMBLE_CONVEX_HULL_H
#define TUMBLE_CONVEX_HULL_H

#include "tumble/status.h"

#include <stddef.h>

/* Marks in on_hull[count] (true/false) the points that are vertices of the convex hull of
 * points[3 * count], by incremental construction (each point outside the hull so far replaces
 * the faces it sees by a fan from their horizon). A point within 1e-10 of the set's extent of
 * the hull is treated as inside, so near-duplicates and points on faces are dropped: the hull
 * kept differs from the exact one by at most that much. TB_STATUS_INVALID_ARGUMENT (detail
 * names why, TB_DETAIL_SIZE bytes) when the points span no volume (all on a plane, a line or
 * one spot); TB_STATUS_OUT_OF_MEMORY. */
tb_status tb__convex_hull(const double *points, size_t count, unsigned char *on_hull, char *detail);

#endif

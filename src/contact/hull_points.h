/* Private: the convex hull's working copy of its points (hull_points.c, for convex_hull.c). */
#ifndef TUMBLE_HULL_POINTS_H
#define TUMBLE_HULL_POINTS_H

#include <stddef.h>
#include <stdint.h>

/* The most points a hull takes: every index (points, faces: at most 2 n) fits 32 bits. */
#define TB__HULL_MAX_POINTS ((size_t)1 << 30)

/* The largest of the points' extents along x, y and z (0 for no points). */
double tb__hull_extent(const double *points, size_t count);

/* A new copy of points[3 * count] scaled by the power of two nearest 1 / their extent, exactly,
 * in Morton order, with (*order)[j] the input index of copy point j (a new array); NULL (and
 * *order NULL) when memory runs out or count is above TB__HULL_MAX_POINTS. The caller frees
 * both. */
double *tb__hull_points(const double *points, size_t count, uint32_t **order);

#endif

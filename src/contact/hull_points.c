/* The convex hull's working copy of its points (convex_hull.c): scaled by an exact power of two
 * (F19) and sorted along a Morton curve. */
#include "contact/hull_points.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

double tb__hull_extent(const double *points, size_t count)
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

/* 21 bits of a coordinate in [0, 1] spread to every third bit of a Morton code. */
static uint64_t spread(double unit)
{
    uint64_t x = (uint64_t)(fmin(fmax(unit, 0.0), 1.0) * 2097151.0);
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    return (x | x << 2) & 0x1249249249249249ULL;
}

/* x 2^-exponent, rounded as ldexp rounds it: the product with factor = 2^-exponent where that is
 * a normal number (both are the exact value correctly rounded; ldexp per coordinate was a fifth
 * of the hull's time), else ldexp. */
static double scale(double x, int exponent, double factor)
{
    return isnormal(factor) ? x * factor : ldexp(x, -exponent);
}

typedef struct keyed {
    uint64_t key;
    uint32_t index;
} keyed;

static int by_key(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    return x->key < y->key   ? -1
           : x->key > y->key ? 1
                             : (x->index > y->index) - (x->index < y->index);
}

/* points scaled by the power of two nearest 1 / their extent, exactly (no bits lost): the hull's
 * cross products of differences are then near 1 for any size the shapes allow (1e100 m cubed
 * overflows, 1e-160 m squared underflows), and the hull of the copy is the scaled hull. The
 * copy is in Morton order (order[j]: the input index of copy point j), so that the points of
 * one face's outside set lie near each other in memory: in input order the walks over the
 * outside sets missed the cache at nearly every point (3 times slower on a shuffled sphere). */
double *tb__hull_points(const double *points, size_t count, uint32_t **order)
{
    int exponent = 0;
    frexp(tb__hull_extent(points, count), &exponent);
    const bool fits = count <= SIZE_MAX / (3 * sizeof(double)) && count <= TB__HULL_MAX_POINTS;
    double *copy = fits ? malloc((count > 0 ? 3 * count : 1) * sizeof(double)) : NULL;
    keyed *keys = fits ? malloc((count > 0 ? count : 1) * sizeof *keys) : NULL;
    *order = fits ? malloc((count > 0 ? count : 1) * sizeof **order) : NULL;
    if (copy == NULL || keys == NULL || *order == NULL) {
        free(copy), free(keys), free(*order);
        *order = NULL;
        return NULL;
    }
    const double factor = ldexp(1.0, -exponent);
    double low[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < 3 && count > 0; ++k) {
        low[k] = points[k];
        for (size_t i = 1; i < count; ++i) {
            low[k] = fmin(low[k], points[3 * i + k]);
        }
    }
    for (size_t i = 0; i < count; ++i) {
        keys[i].index = (uint32_t)i;
        keys[i].key = 0;
        for (int k = 0; k < 3; ++k) { /* (x - low) / extent, within [0, 2) after the scaling */
            keys[i].key |= spread(0.5 * scale(points[3 * i + k] - low[k], exponent, factor)) << k;
        }
    }
    qsort(keys, count, sizeof *keys, by_key);
    for (size_t j = 0; j < count; ++j) {
        (*order)[j] = keys[j].index;
        for (int k = 0; k < 3; ++k) {
            copy[3 * j + k] = scale(points[3 * (size_t)keys[j].index + k], exponent, factor);
        }
    }
    free(keys);
    return copy;
}

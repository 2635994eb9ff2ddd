/* Private: general convex-convex contact through libccd (only ccd_wrap.c includes its
 * headers). Shapes are given to libccd by their support functions (collision_shape.h). */
#ifndef TUMBLE_CCD_WRAP_H
#define TUMBLE_CCD_WRAP_H

#include "contact/narrow_phase.h"

typedef enum tb__ccd_method {
    TB__CCD_MPR, /* Minkowski portal refinement: allocates nothing; the narrow phase's choice */
    TB__CCD_EPA  /* GJK + EPA: the least penetration, but libccd allocates its polytope
                    (returns -1 when that fails); for cross-checks outside the derivative */
} tb__ccd_method;

/* One contact point for a and b at their poses, as tb__collide reports it (shapes grown by
 * margin find pairs within margin); returns the count (0 or 1), or -1 if libccd failed or did
 * not finish within a budget of support evaluations (a cycling portal: callers then report no
 * contact). */
int tb__ccd_collide(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                    const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE], double margin,
                    tb__ccd_method method, tb__contact_manifold *out);

#endif

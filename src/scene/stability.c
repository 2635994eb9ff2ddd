/* How fast a scene's stiffest mode is, and so the largest stable fixed step. An estimate from
 * each effect's own stiffness: springs from k and c with the inverse mass at their ends,
 * ground contact from its documented sqrt(g / penetration) rocking and bristle modes. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdio.h>

/* |h lambda| at which one step amplifies the mode by 1%: the root of |R(h lambda)| = 1.01 on
 * the imaginary axis for Euler (1 + z^2) and midpoint (1 + z^4 / 4); RK4's whole stability
 * interval on the real axis (2.785, with 2.828 on the imaginary axis). */
static double step_limit(tb_method method)
{
    switch (method) {
    case TB_METHOD_EULER:
        return 0.14;
    case TB_METHOD_MIDPOINT:
        return 0.53;
    case TB_METHOD_RK4:
        return 2.78;
    default:
        return INFINITY;
    }
}

/* 1/m + |r|^2 / I_min: the largest inverse mass a force at offset r can meet. */
static double inverse_mass_at(const tb_scene *scene, size_t body, const double r[3])
{
    if (body == TB_WORLD) {
        return 0.0;
    }
    const tb__body *b = &scene->bodies[body];
    const double largest_inverse =
        fmax(b->inv_moments[0], fmax(b->inv_moments[1], b->inv_moments[2]));
    return b->inv_mass + tb__v3_dot(r, r) * largest_inverse;
}

/* A damped spring's fastest rate: omega when underdamped, about c w when overdamped. */
static double spring_rate(double k, double c, double w)
{
    return fmax(sqrt(k * w), c * w);
}

static double ground_rate(const tb__effect *e)
{
    const double omega = sqrt(e->param[1] / e->param[2]); /* sqrt(g / penetration) */
    /* A flat body rocking on its corners is sqrt(3) stiffer and sqrt(3) more damped than it
     * bounces; overdamped, its fast root is omega (zeta + sqrt(zeta^2 - 1)). */
    const double rocking = sqrt(3.0) * omega, zeta = sqrt(3.0) * e->param[3];
    const double normal = rocking * (zeta > 1.0 ? zeta + sqrt(zeta * zeta - 1.0) : 1.0);
    const double bristles = sqrt(3.0 * e->param[1] * e->param[7]); /* yaw: sqrt(3 g s0) */
    return fmax(normal, bristles);
}

tb_status tb_scene_max_stable_step(const tb_scene *scene, tb_method method, double *out_dt,
                                   char *out_which)
{
    if (scene == NULL || out_dt == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    double fastest = 0.0;
    size_t which = 0;
    for (size_t k = 0; k < scene->effect_count; ++k) {
        const tb__effect *e = &scene->effects[k];
        double rate = 0.0;
        if (e->kind == TB__SPRING) {
            const double w = inverse_mass_at(scene, e->body, e->point) +
                             inverse_mass_at(scene, e->other, e->other_point);
            rate = spring_rate(e->param[0], e->param[1], w);
        } else if (e->kind == TB__GROUND && scene->contact_count > 0) {
            rate = ground_rate(e);
        }
        if (rate > fastest) {
            fastest = rate;
            which = k;
        }
    }
    *out_dt = fastest > 0.0 ? step_limit(method) / fastest : INFINITY;
    if (out_which != NULL) {
        snprintf(out_which, TB_DETAIL_SIZE, "effect %zu (a %s, rate %.3g 1/s)", which,
                 scene->effect_count > 0 && scene->effects[which].kind == TB__SPRING ? "spring"
                                                                                     : "ground",
                 fastest);
    }
    return TB_STATUS_OK;
}

/* The lane forms (lanes.h) of the per-body effects that act on every body, compiled once per
 * vector path with TB_LANES_TARGET naming it: gravity and drag. Each lane's operations are those
 * of apply_gravity() (effect_loads.c) and drag_body() (effect_drag.c), in the same order. */
#include "effects/effect_lanes.h"

#include "effects/effect_drag.h"
#include "effects/effect_loads.h"

#include "math/tb_math.h"

#ifndef TB_LANES_TARGET
#error "effect_lanes.c is compiled once per vector path, with TB_LANES_TARGET set"
#endif

/* F_i += M_i g */
void TB__LANES_NAME(tb__gravity_lanes)(const tb__effect *effect, const tb__lanes *lanes)
{
    const size_t n = lanes->lanes;
    const double *g = tb__gravity_of(effect)->g;
    const double *restrict mass = lanes->constants + TB__LANE_MASS * n;
    for (size_t k = 0; k < 3; ++k) {
        double *restrict dP = lanes->dydt + (TB_STATE_P + k) * n;
        const double gk = g[k];
        TB__LANES_LOOP
        for (size_t j = 0; j < n; ++j) {
            dP[j] += mass[j] * gk;
        }
    }
}

/* a += -(b + c |v|) v for n vectors v and a (three rows each, v's `stride` apart, a's n) */
static void add_drag(double *restrict a, const double *restrict v, size_t stride, size_t n,
                     double b, double c)
{
    TB__LANES_LOOP
    for (size_t j = 0; j < n; ++j) {
        const double v0 = v[j], v1 = v[stride + j], v2 = v[2 * stride + j];
        const double scale = -(b + c * sqrt(v0 * v0 + v1 * v1 + v2 * v2));
        a[j] += scale * v0;
        a[n + j] += scale * v1;
        a[2 * n + j] += scale * v2;
    }
}

/* F = -(b + c |v|) v, v = P/M (the kinematics' dx/dt); tau = -(b_w + c_w |omega|) omega */
void TB__LANES_NAME(tb__drag_lanes)(const tb__effect *effect, const tb__lanes *lanes)
{
    const tb__drag_params *drag = effect->params;
    const size_t n = lanes->lanes;
    add_drag(lanes->dydt + TB_STATE_P * n, lanes->dydt + TB_STATE_X * n, n, n, drag->linear,
             drag->quadratic);
    if (drag->angular != 0.0 || drag->angular_quadratic != 0.0) {
        add_drag(lanes->dydt + TB_STATE_L * n, lanes->omega[0], TB__LANES, n, drag->angular,
                 drag->angular_quadratic);
    }
}

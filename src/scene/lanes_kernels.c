/* The rigid-body derivative and the renormalisation in lane layout (lanes.h), compiled once per
 * vector path with TB_LANES_TARGET naming it. Each lane's operations are those of kinematics(),
 * angular_velocity() and normalize() in derivative.c, in the same order, so that the lanes give
 * the bits the body-by-body path gives (test_vector_paths). */
#include "scene/lanes.h"

#include "math/tb_math.h"

#include <float.h>

#ifndef TB_LANES_TARGET
#error "lanes_kernels.c is compiled once per vector path, with TB_LANES_TARGET set"
#endif

/* omega = R I_body^-1 R^T L, R the rotation of q/|q| without a square root; see
 * angular_velocity() in derivative.c, whose operations these are. */
static void angular_velocities(tb__lanes *lanes)
{
    const size_t n = lanes->lanes;
    const double *restrict y = lanes->y;
    const double *restrict qw = y + TB_STATE_Q * n, *restrict qx = qw + n, *restrict qy = qx + n,
                           *restrict qz = qy + n;
    const double *restrict L0 = y + TB_STATE_L * n, *restrict L1 = L0 + n, *restrict L2 = L1 + n;
    double *restrict o0 = lanes->omega[0], *restrict o1 = lanes->omega[1],
                     *restrict o2 = lanes->omega[2];
    const double *restrict i0 = lanes->constants + TB__LANE_INV_MOMENTS * n, *restrict i1 = i0 + n,
                           *restrict i2 = i1 + n;
    TB__LANES_LOOP
    for (size_t j = 0; j < n; ++j) {
        const double w = qw[j], x = qx[j], yy = qy[j], z = qz[j];
        const double s = 2.0 / (w * w + x * x + yy * yy + z * z);
        const double R0 = 1 - s * (yy * yy + z * z), R1 = s * (x * yy - w * z),
                     R2 = s * (x * z + w * yy), R3 = s * (x * yy + w * z),
                     R4 = 1 - s * (x * x + z * z), R5 = s * (yy * z - w * x),
                     R6 = s * (x * z - w * yy), R7 = s * (yy * z + w * x),
                     R8 = 1 - s * (x * x + yy * yy);
        const double b0 = (R0 * L0[j] + R3 * L1[j] + R6 * L2[j]) * i0[j];
        const double b1 = (R1 * L0[j] + R4 * L1[j] + R7 * L2[j]) * i1[j];
        const double b2 = (R2 * L0[j] + R5 * L1[j] + R8 * L2[j]) * i2[j];
        o0[j] = R0 * b0 + R1 * b1 + R2 * b2;
        o1[j] = R3 * b0 + R4 * b1 + R5 * b2;
        o2[j] = R6 * b0 + R7 * b1 + R8 * b2;
    }
}

/* dx = P/M, dq = 1/2 (0, omega) (x) q, dP = dL = 0 (kinematics() in derivative.c). */
static void kinematics(tb__lanes *lanes)
{
    angular_velocities(lanes);
    const size_t n = lanes->lanes;
    const double *restrict y = lanes->y;
    double *restrict d = lanes->dydt;
    const double *restrict inv_mass = lanes->constants + TB__LANE_INV_MASS * n;
    for (size_t k = 0; k < 3; ++k) {
        const double *restrict P = y + (TB_STATE_P + k) * n;
        double *restrict dx = d + (TB_STATE_X + k) * n;
        TB__LANES_LOOP
        for (size_t j = 0; j < n; ++j) {
            dx[j] = P[j] * inv_mass[j];
        }
    }
    const double *restrict q0 = y + TB_STATE_Q * n, *restrict q1 = q0 + n, *restrict q2 = q1 + n,
                           *restrict q3 = q2 + n;
    const double *restrict o0 = lanes->omega[0], *restrict o1 = lanes->omega[1],
                           *restrict o2 = lanes->omega[2];
    double *restrict d0 = d + TB_STATE_Q * n, *restrict d1 = d0 + n, *restrict d2 = d1 + n,
                     *restrict d3 = d2 + n;
    TB__LANES_LOOP
    for (size_t j = 0; j < n; ++j) {
        d0[j] = 0.5 * (-o0[j] * q1[j] - o1[j] * q2[j] - o2[j] * q3[j]);
        d1[j] = 0.5 * (o0[j] * q0[j] + o1[j] * q3[j] - o2[j] * q2[j]);
        d2[j] = 0.5 * (-o0[j] * q3[j] + o1[j] * q0[j] + o2[j] * q1[j]);
        d3[j] = 0.5 * (o0[j] * q2[j] - o1[j] * q1[j] + o2[j] * q0[j]);
    }
    double *restrict momenta = d + TB_STATE_P * n;
    TB__LANES_LOOP
    for (size_t j = 0; j < 6 * n; ++j) {
        momenta[j] = 0.0;
    }
}

/* An effect without a lane form, on lane j: its body's states gathered into the 13-doubles
 * layout, apply_bodies on that one body, the derivative scattered back. */
static int apply_on_lane(const tb__effect *effect, double t, const tb__lanes *lanes, size_t j)
{
    const size_t n = lanes->lanes;
    double s[TB_STATE_SIZE], d[TB_STATE_SIZE];
    for (size_t c = 0; c < TB_STATE_SIZE; ++c) {
        s[c] = lanes->y[c * n + j];
        d[c] = lanes->dydt[c * n + j];
    }
    const int rc = effect->ops->apply_bodies(effect, lanes->scene, t, s, d, lanes->first + j, 1);
    for (size_t c = 0; c < TB_STATE_SIZE; ++c) {
        lanes->dydt[c * n + j] = d[c];
    }
    return rc;
}

/* An effect on every body: its lane form, or lane by lane. */
static int apply_on_all(const tb__effect *effect, double t, const tb__lanes *lanes)
{
    if (effect->ops->lanes != NULL) {
        effect->ops->lanes->TB_LANES_TARGET(effect, lanes);
        return 0;
    }
    for (size_t j = 0; j < lanes->count; ++j) {
        const int rc = apply_on_lane(effect, t, lanes, j);
        if (rc != 0) {
            return rc;
        }
    }
    return 0;
}

/* The per-body effects in the order apply_per_body_effects() in derivative.c applies them. */
static int apply_effects(const tb__lanes *lanes, double t)
{
    const tb_scene *scene = lanes->scene;
    const size_t *order = scene->effect_order;
    for (size_t k = 0; k < scene->all_body_effect_count; ++k) {
        const int rc = apply_on_all(&scene->effects[order[k]], t, lanes);
        if (rc != 0) {
            return rc;
        }
    }
    size_t begin, end;
    tb__scene_single_body_effects(scene, lanes->first, lanes->count, &begin, &end);
    for (size_t k = begin; k < end; ++k) {
        const tb__effect *effect = &scene->effects[order[k]];
        const int rc = apply_on_lane(effect, t, lanes, effect->slot - lanes->first);
        if (rc != 0) {
            return rc;
        }
    }
    return 0;
}

static int derivative(double t, const double *y, double *dydt, size_t first, size_t count,
                      void *ctx)
{
    const tb_scene *scene = ctx;
    /* an effect coupling bodies added after the system was made */
    if (scene == NULL || !tb__scene_separable(scene)) {
        return -1;
    }
    tb__lanes lanes;
    lanes.scene = scene;
    lanes.y = y;
    lanes.dydt = dydt;
    lanes.first = first;
    lanes.count = count;
    lanes.lanes = tb__lanes_for(scene->slot_count);
    /* chunks are whole lane groups from body 0 */
    lanes.constants = scene->lane_constants + TB__LANE_CONSTANTS * first;
    kinematics(&lanes);
    return apply_effects(&lanes, t);
}

/* q <- q / |q| (normalize() in derivative.c): 1 if some real lane's |q| is zero or not finite,
 * the drift of the lanes before it noted as that function notes it. */
static int normalize(double t, double *y, size_t first, size_t count, void *ctx)
{
    (void)t;
    (void)first;
    tb_scene *scene = ctx;
    if (scene == NULL) {
        return -1;
    }
    const size_t n = tb__lanes_for(scene->slot_count);
    double *restrict q0 = y + TB_STATE_Q * n, *restrict q1 = q0 + n, *restrict q2 = q1 + n,
                     *restrict q3 = q2 + n;
    double norm[TB__LANES];
    int bad = 0;
    TB__LANES_LOOP
    for (size_t j = 0; j < n; ++j) {
        norm[j] = sqrt(q0[j] * q0[j] + q1[j] * q1[j] + q2[j] * q2[j] + q3[j] * q3[j]);
    }
    for (size_t j = 0; j < n; ++j) {
        bad |= !(norm[j] > 0) | !(norm[j] <= DBL_MAX);
    }
    size_t good = count;
    for (size_t j = 0; bad && j < count; ++j) {
        if (!(norm[j] > 0) || !(norm[j] <= DBL_MAX)) {
            good = j;
            break;
        }
    }
    double drift = 0.0;
    for (size_t j = 0; j < good; ++j) {
        const double off = fabs(norm[j] - 1.0); /* finite: fmax's value without its call */
        drift = off > drift ? off : drift;
    }
    tb__scene_note_drift(scene, drift);
    if (good < count) {
        return 1;
    }
    TB__LANES_LOOP
    for (size_t j = 0; j < n; ++j) {
        const double inverse = 1.0 / norm[j];
        q0[j] *= inverse;
        q1[j] *= inverse;
        q2[j] *= inverse;
        q3[j] *= inverse;
    }
    return 0;
}

const tb__lanes_kernels TB__LANES_NAME(tb__lanes_kernels) = {derivative, normalize};

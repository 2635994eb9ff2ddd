/* Private: how an effect writes its analytic rows of the scene Jacobian (tb__effect_ops.jacobian,
 * filled by scene_jacobian_values.c on the pattern of scene_jacobian.c).
 *
 * A contact point couples body a and body b through a force f (N, world) on b at the point and
 * -f on a, and may own states s (a friction anchor, up to 3 doubles of y). The effect states its
 * law's local derivatives against
 *   u: the relative displacement of the two bodies' material points at the point (p_b - p_a),
 *   w: their relative velocity (v_b - v_a at the point),
 *   s: the point's own states,
 * and tb__jacobian_add_point chains them to both bodies' states (x, q, P, L) with the point taken
 * as fixed on each body:
 *   du = dx_b - r_b x dtheta_b - (the same for a),   dtheta = G dq (scene_jacobian.h),
 *   dw = dP_b / M_b - r_b x d omega_b - omega_b x (r_b x dtheta_b) - (the same for a),
 *   d omega = W dL + (d omega / dq) dq,   W = R I^-1 R^T,
 * and adds df into b's dP rows, r_b x df into its dL rows, the opposite into a's. Neglected (the
 * second-order geometric terms): the arms' own change in the torque (dr x f, of relative size
 * |f| / (k |r|), the spring's deflection over the arm), the turning of the normal with the
 * bodies (of relative size |f| / (k |r|) and |w| / (omega |r|) against the spring's k |r|), and
 * the manifold points' sliding over the faces. A body
 * without a state (TB_WORLD, static, keyframed) gets no rows or columns; an entry the pattern does
 * not hold (a pair that came into reach inside a step) is left out, as the quotients leave it. */
#ifndef TUMBLE_JACOBIAN_ROWS_H
#define TUMBLE_JACOBIAN_ROWS_H

#include "scene/scene_internal.h"

typedef struct tb__jacobian_rows tb__jacobian_rows; /* scene_jacobian.h */

/* One point's local derivatives (matrices row-major, [row][column]). */
typedef struct tb__point_jacobian {
    size_t body_a, body_b;     /* ids; a body without a state is skipped */
    double arm_a[3], arm_b[3]; /* m, world: the point from each centre of mass */
    double force_u[3][3];      /* d f / d u, N/m */
    double force_w[3][3];      /* d f / d w, N s/m */
    size_t state_first;        /* index in y of the point's first own state */
    size_t state_count;        /* 0 to 3 */
    double force_s[3][3];      /* d f_i / d s_k: [i][k] */
    /* the own states' rates: d sdot_k / d (u, w, s), [k][i]. The point's rows of s replace
     * whatever was written there before (a slot's relaxation), as its derivative does. */
    double rate_u[3][3], rate_w[3][3], rate_s[3][3];
    /* d f / d theta_a and d sdot / d theta_a ([k][i]): body a's turn (world, rad), where the
     * point's states are in a's frame (an anchor between bodies); zero otherwise */
    double force_turn_a[3][3], rate_turn_a[3][3];
} tb__point_jacobian;

/* Adds point p's rows (and sets its states' rows), as described above. */
void tb__jacobian_add_point(tb__jacobian_rows *rows, const tb_scene *scene,
                            const tb__point_jacobian *p);

/* Sets the diagonal entries of y's components [first, first + count) to value (a relaxing
 * anchor's -rate), their rows otherwise left as they are. */
void tb__jacobian_set_diagonal(tb__jacobian_rows *rows, size_t first, size_t count, double value);

#endif

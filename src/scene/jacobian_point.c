/* A contact point's analytic rows of the scene Jacobian: its law's local derivatives chained to
 * both bodies' states (jacobian_rows.h has the formulas and what they neglect). */
#include "scene/jacobian_rows.h"

#include "scene/scene_jacobian.h"

#include <string.h>

size_t tb__jacobian_find_columns(const tb__jacobian_room *j, size_t v, size_t u)
{
    size_t low = j->adjacent_start[v], high = j->adjacent_start[v + 1];
    while (low < high) {
        const size_t middle = low + (high - low) / 2;
        if (j->adjacent[middle] < u) {
            low = middle + 1;
        } else {
            high = middle;
        }
    }
    return low < j->adjacent_start[v + 1] && j->adjacent[low] == u ? j->column_offset[low]
                                                                   : (size_t)-1;
}

/* Row r's entries (r a component of node v). */
static double *row_of(const tb__jacobian_room *j, double *values, size_t v, size_t r)
{
    return values + j->row_base[v] + (r - j->node_start[v]) * j->row_length[v];
}

/* [a]x b for the 3 x columns matrix b: out = a x (each column of b). */
static void cross_rows(const double a[3], const double *b, size_t columns, double *out)
{
    for (size_t c = 0; c < columns; ++c) {
        const double b0 = b[c], b1 = b[columns + c], b2 = b[2 * columns + c];
        out[c] = a[1] * b2 - a[2] * b1;
        out[columns + c] = a[2] * b0 - a[0] * b2;
        out[2 * columns + c] = a[0] * b1 - a[1] * b0;
    }
}

/* One body's side of the point: its node (the slot, (size_t)-1 without a state) and du/dy_s,
 * dw/dy_s (3 x 13, signed: + for b, - for a). */
typedef struct tb__point_side {
    size_t node;
    double du[3][TB_STATE_SIZE], dw[3][TB_STATE_SIZE];
    double G[3][4]; /* dtheta = G dq */
} tb__point_side;

static void point_side(const tb_scene *scene, const double *y, size_t id, const double arm[3],
                       double sign, tb__point_side *out)
{
    const size_t slot = id < scene->body_count ? tb__body_slot(scene, id) : TB_NO_SLOT;
    out->node = slot == TB_NO_SLOT ? (size_t)-1 : slot;
    if (slot == TB_NO_SLOT) {
        return;
    }
    const tb__body *body = &scene->bodies[slot];
    double omega[3], W[3][3], G[3][4], d_omega[3][4], rG[3][4], wrG[3][4], rW[3][3], rdw[3][4];
    tb__jacobian_rotation(body, y + TB_STATE_SIZE * slot, omega, W, G, d_omega);
    memcpy(out->G, G, sizeof G);
    cross_rows(arm, &G[0][0], 4, &rG[0][0]);        /* r x dtheta per dq */
    cross_rows(omega, &rG[0][0], 4, &wrG[0][0]);    /* omega x (r x dtheta) */
    cross_rows(arm, &d_omega[0][0], 4, &rdw[0][0]); /* r x d omega per dq */
    cross_rows(arm, &W[0][0], 3, &rW[0][0]);        /* r x d omega per dL */
    memset(out->du, 0, sizeof out->du);
    memset(out->dw, 0, sizeof out->dw);
    for (int i = 0; i < 3; ++i) {
        out->du[i][TB_STATE_X + i] = sign;
        out->dw[i][TB_STATE_P + i] = sign * body->inv_mass;
        for (int k = 0; k < 4; ++k) {
            out->du[i][TB_STATE_Q + k] = -sign * rG[i][k];
            out->dw[i][TB_STATE_Q + k] = -sign * (rdw[i][k] + wrG[i][k]);
        }
        for (int k = 0; k < 3; ++k) {
            out->dw[i][TB_STATE_L + k] = -sign * rW[i][k];
        }
    }
}

/* out (3 x 13) = A du + B dw of a side. */
static void chain(const double A[3][3], const double B[3][3], const tb__point_side *side,
                  double out[3][TB_STATE_SIZE])
{
    for (int i = 0; i < 3; ++i) {
        for (int c = 0; c < TB_STATE_SIZE; ++c) {
            out[i][c] = A[i][0] * side->du[0][c] + A[i][1] * side->du[1][c] +
                        A[i][2] * side->du[2][c] + B[i][0] * side->dw[0][c] +
                        B[i][1] * side->dw[1][c] + B[i][2] * side->dw[2][c];
        }
    }
}

/* out's q columns += turn G: a derivative against body a's turn. */
static void add_turn(const double turn[3][3], const tb__point_side *side,
                     double out[3][TB_STATE_SIZE])
{
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 4; ++k) {
            out[i][TB_STATE_Q + k] += turn[i][0] * side->G[0][k] + turn[i][1] * side->G[1][k] +
                                      turn[i][2] * side->G[2][k];
        }
    }
}

/* Adds block (3 x count, leading dimension stride) into rows [first, first + 3) of node v at
 * column node u (offset within u's columns), when the pattern holds them. */
static void add_block(tb__jacobian_rows *rows, size_t v, size_t first, size_t u, size_t offset,
                      const double *block, size_t count, size_t stride)
{
    const tb__jacobian_room *j = rows->room;
    const size_t columns =
        v == (size_t)-1 || u == (size_t)-1 ? (size_t)-1 : tb__jacobian_find_columns(j, v, u);
    if (columns == (size_t)-1) {
        return;
    }
    for (size_t i = 0; i < 3; ++i) {
        double *row = row_of(j, rows->values, v, first + i) + columns + offset;
        for (size_t c = 0; c < count; ++c) {
            row[c] += block[i * stride + c];
        }
    }
}

/* The loads' rows of side r (sign: + for b, - for a) against the columns of both sides and of
 * the point's states: dP += sign df, dL += sign arm x df. */
static void load_rows(tb__jacobian_rows *rows, const tb__point_jacobian *p,
                      const tb__point_side sides[2], double force[2][3][TB_STATE_SIZE], int r,
                      size_t state_node, size_t state_offset)
{
    const size_t v = sides[r].node;
    if (v == (size_t)-1) {
        return;
    }
    const double sign = r == 1 ? 1.0 : -1.0, *arm = r == 1 ? p->arm_b : p->arm_a;
    const size_t first = TB_STATE_SIZE * v;
    for (int c = 0; c < 2; ++c) {
        double f[3][TB_STATE_SIZE], torque[3][TB_STATE_SIZE];
        for (int i = 0; i < 3; ++i) {
            for (int k = 0; k < TB_STATE_SIZE; ++k) {
                f[i][k] = sign * force[c][i][k];
            }
        }
        cross_rows(arm, &f[0][0], TB_STATE_SIZE, &torque[0][0]);
        add_block(rows, v, first + TB_STATE_P, sides[c].node, 0, &f[0][0], TB_STATE_SIZE,
                  TB_STATE_SIZE);
        add_block(rows, v, first + TB_STATE_L, sides[c].node, 0, &torque[0][0], TB_STATE_SIZE,
                  TB_STATE_SIZE);
    }
    if (p->state_count > 0) {
        double f[3][3] = {{0.0}}, torque[3][3];
        for (int i = 0; i < 3; ++i) {
            for (size_t k = 0; k < p->state_count; ++k) {
                f[i][k] = sign * p->force_s[i][k];
            }
        }
        cross_rows(arm, &f[0][0], 3, &torque[0][0]);
        add_block(rows, v, first + TB_STATE_P, state_node, state_offset, &f[0][0], p->state_count,
                  3);
        add_block(rows, v, first + TB_STATE_L, state_node, state_offset, &torque[0][0],
                  p->state_count, 3);
    }
}

/* The point's own states' rows: cleared, then its rates' derivatives. */
static void state_rows(tb__jacobian_rows *rows, const tb__point_jacobian *p,
                       const tb__point_side sides[2], size_t node, size_t offset)
{
    const tb__jacobian_room *j = rows->room;
    const size_t count = p->state_count;
    for (size_t k = 0; k < count; ++k) {
        memset(row_of(j, rows->values, node, p->state_first + k), 0,
               j->row_length[node] * sizeof(double));
    }
    for (int c = 0; c < 2; ++c) {
        const size_t u = sides[c].node;
        const size_t columns = u == (size_t)-1 ? (size_t)-1 : tb__jacobian_find_columns(j, node, u);
        if (columns == (size_t)-1) {
            continue;
        }
        double rate[3][TB_STATE_SIZE];
        chain(p->rate_u, p->rate_w, &sides[c], rate);
        if (c == 0) {
            add_turn(p->rate_turn_a, &sides[0], rate);
        }
        for (size_t k = 0; k < count; ++k) {
            double *row = row_of(j, rows->values, node, p->state_first + k) + columns;
            for (int i = 0; i < TB_STATE_SIZE; ++i) {
                row[i] += rate[k][i];
            }
        }
    }
    const size_t own = tb__jacobian_find_columns(j, node, node) + offset;
    for (size_t k = 0; k < count; ++k) {
        double *row = row_of(j, rows->values, node, p->state_first + k) + own;
        for (size_t i = 0; i < count; ++i) {
            row[i] += p->rate_s[k][i];
        }
    }
}

void tb__jacobian_add_point(tb__jacobian_rows *rows, const tb_scene *scene,
                            const tb__point_jacobian *p)
{
    tb__point_side sides[2];
    point_side(scene, rows->y, p->body_a, p->arm_a, -1.0, &sides[0]);
    point_side(scene, rows->y, p->body_b, p->arm_b, 1.0, &sides[1]);
    double force[2][3][TB_STATE_SIZE];
    for (int c = 0; c < 2; ++c) {
        if (sides[c].node != (size_t)-1) {
            chain(p->force_u, p->force_w, &sides[c], force[c]);
        }
    }
    if (sides[0].node != (size_t)-1) {
        add_turn(p->force_turn_a, &sides[0], force[0]);
    }
    const tb__jacobian_room *j = rows->room;
    const size_t node = p->state_count > 0 ? j->node_of[p->state_first] : (size_t)-1;
    const size_t offset = p->state_count > 0 ? p->state_first - j->node_start[node] : 0;
    load_rows(rows, p, sides, force, 0, node, offset);
    load_rows(rows, p, sides, force, 1, node, offset);
    if (p->state_count > 0) {
        state_rows(rows, p, sides, node, offset);
    }
}

void tb__jacobian_set_diagonal(tb__jacobian_rows *rows, size_t first, size_t count, double value)
{
    const tb__jacobian_room *j = rows->room;
    for (size_t r = first; r < first + count; ++r) {
        const size_t node = j->node_of[r];
        const size_t own = tb__jacobian_find_columns(j, node, node);
        row_of(j, rows->values, node, r)[own + (r - j->node_start[node])] = value;
    }
}

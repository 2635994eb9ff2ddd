/* The contact Jacobian's values at (t, y), on the pattern scene_jacobian.c built:
 *
 * - the kinematic rows exactly: dx/dt = P / M gives 1/M against P; dq/dt = 1/2 (0, omega) (x) q
 *   with omega = R I^-1 R^T L (R the rotation of q/|q|) gives, against q,
 *   1/2 Omega(omega) + 1/2 Xi(q) d omega/dq and, against L, 1/2 Xi(q) R I^-1 R^T, where
 *   (0, w) (x) q = Omega(w) q = Xi(q) w, and a change dq turns the body by
 *   dtheta = (2/|q|) vec(dq (x) conj(q) / |q|) (world frame; the change along q turns nothing), so
 *   d omega = -omega x dtheta + R I^-1 R^T (L x dtheta);
 * - the loads' rows (dP, dL) and the effects' own states' rows: each effect with analytic rows
 *   (tb__effect_ops.jacobian: contact, ground) adds its own, one pass over its points
 *   (jacobian_rows.h); constant loads (gravity) have none; the effects left (springs, drag,
 *   user effects, ...) by difference quotients of their part of the derivative alone
 *   (tb__scene_quotient_part), a colour of columns at a time (Curtis, Powell and Reid: the columns
 *   of one colour share no row, so one evaluation gives them all), with the increment
 *   sqrt(eps) max(|y_j|, s_j), s_j the component's natural size (tb_scene_absolute_tolerances at
 *   scale 1). A scene whose effects all have analytic rows takes no quotient;
 * - the loads' rows of an asleep body zero, as its derivative is.
 * Allocates nothing: the scratch was made with the pattern. */
#include "scene/scene_jacobian.h"

#include "scene/jacobian_rows.h"

#include "math/tb_math.h"

#include <float.h>
#include <math.h>
#include <string.h>

static size_t node_size(const tb__jacobian_room *j, size_t u)
{
    return j->node_start[u + 1] - j->node_start[u];
}

/* The entry of row r (a row of node v) at column offset within the row. */
static size_t entry_of(const tb__jacobian_room *j, size_t v, size_t r, size_t offset)
{
    return j->row_base[v] + (r - j->node_start[v]) * j->row_length[v] + offset;
}

/* What the quotients difference: under rosenbrock, whose rows are all quotients
 * (tb__scene_rows_by_quotients), the whole derivative, as before the analytic rows, so that its
 * steps are those it took then to the bit; else the part without analytic rows. */
typedef int (*part_fn)(double t, const double *y, double *dydt, void *ctx);
static part_fn quotient_of(const tb_scene *scene)
{
    return scene->guard_method == TB_METHOD_ROSENBROCK ? tb_scene_derivative
                                                       : tb__scene_quotient_part;
}

/* Moves column k of every node of colour c with more than k components by its increment,
 * sqrt(eps) max(|y_j|, s_j), forward (sign 1) or back (sign -1) from y, into out (y elsewhere);
 * whether any moved. */
static bool perturb(const tb__jacobian_room *j, size_t c, size_t k, const double *y, double sign,
                    double *out)
{
    bool any = false;
    for (size_t i = j->color_first[c]; i < j->color_first[c + 1]; ++i) {
        const size_t u = j->by_color[i], col = j->node_start[u] + k;
        if (k < node_size(j, u)) {
            const double h = sqrt(DBL_EPSILON) * fmax(fabs(y[col]), j->scale[col]);
            out[col] = y[col] + sign * (h > 0.0 ? h : sqrt(DBL_EPSILON));
            any = true;
        }
    }
    return any;
}

/* Column k of every node of colour c with more than k components, from one evaluation forward
 * of y (against f_base, f at y), or two, forward and back, where `central`. */
static int quotient_columns(tb_scene *scene, const tb__jacobian_room *j, size_t c, size_t k,
                            double t, const double *y, bool central, double *values)
{
    const bool any = perturb(j, c, k, y, 1.0, j->y_work);
    int rc = any ? quotient_of(scene)(t, j->y_work, j->f_work, scene) : 0;
    if (any && central && rc == 0) {
        perturb(j, c, k, y, -1.0, j->y_back);
        rc = quotient_of(scene)(t, j->y_back, j->f_back, scene);
    }
    const double *before = central ? j->f_back : j->f_base;
    for (size_t i = j->color_first[c]; i < j->color_first[c + 1] && any; ++i) {
        const size_t u = j->by_color[i], col = j->node_start[u] + k;
        if (k >= node_size(j, u)) {
            continue;
        }
        /* the increments as represented */
        const double h = j->y_work[col] - (central ? j->y_back[col] : y[col]);
        for (size_t e = j->adjacent_start[u]; e < j->adjacent_start[u + 1] && rc == 0; ++e) {
            const size_t v = j->adjacent[e], offset = tb__jacobian_find_columns(j, v, u) + k;
            for (size_t r = j->node_start[v]; r < j->node_start[v + 1]; ++r) {
                values[entry_of(j, v, r, offset)] = (j->f_work[r] - before[r]) / h;
            }
        }
        j->y_work[col] = y[col];
        j->y_back[col] = y[col];
    }
    return rc;
}

/* Whether rosenbrock's quotients are to be central at (t, y): where a body's nearest gap
 * (tb__scene_event_gaps) is within TB__TOUCH_REACH position increments of touching. The
 * contact's normal force max(0, k d + ...) has a kink at depth 0: a forward increment that
 * deepens a contact at exact touch takes its spring, one that opens it takes nothing, so a
 * forward quotient gives each spring to one body of the pair only (the one whose increment
 * presses it), and the step is explicit in it for the other. A column of ten boxes set exactly
 * on each other was thrown apart at 1/240 s that way (test_rosenbrock); a central quotient
 * takes half the spring for each, as the law's two slopes average. Elsewhere one side of the
 * kink is beyond both increments and the forward quotient is as good, at half the cost. */
#define TB__TOUCH_REACH 4.0
static bool at_a_touch(tb_scene *scene, const tb__jacobian_room *j, double t, const double *y)
{
    if (scene->guard_method != TB_METHOD_ROSENBROCK || !tb__scene_has_events(scene)) {
        return false;
    }
    double reach = 0.0; /* the largest position increment */
    for (size_t s = 0; s < scene->slot_count; ++s) {
        for (size_t a = 0; a < 3; ++a) {
            const size_t col = TB_STATE_SIZE * s + TB_STATE_X + a;
            reach = fmax(reach, sqrt(DBL_EPSILON) * fmax(fabs(y[col]), j->scale[col]));
        }
    }
    tb__scene_event_gaps(t, y, j->gaps, scene);
    for (size_t b = 0; b < scene->body_count; ++b) {
        if (fabs(j->gaps[b]) <= TB__TOUCH_REACH * reach) {
            return true;
        }
    }
    return false;
}

static void cross_matrix(const double a[3], double out[3][3])
{
    const double m[3][3] = {{0.0, -a[2], a[1]}, {a[2], 0.0, -a[0]}, {-a[1], a[0], 0.0}};
    memcpy(out, m, sizeof m);
}

void tb__jacobian_rotation(const tb__body *body, const double *s, double omega[3], double W[3][3],
                           double G[3][4], double d_omega[3][4])
{
    const double *q = s + TB_STATE_Q, *L = s + TB_STATE_L;
    double R[9];
    tb__q_to_matrix_any(R, q);
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            W[a][b] = 0.0;
            for (int k = 0; k < 3; ++k) {
                W[a][b] += R[3 * a + k] * body->inv_moments[k] * R[3 * b + k];
            }
        }
    }
    double wx[3][3], lx[3][3];
    for (int a = 0; a < 3; ++a) {
        omega[a] = W[a][0] * L[0] + W[a][1] * L[1] + W[a][2] * L[2];
    }
    cross_matrix(omega, wx);
    cross_matrix(L, lx);
    /* G: dtheta = G dq = (2/|q|) [-u | w 1 + [u]x] dq, (w, u) = q/|q| */
    const double norm = tb__q_norm(q), w = q[0] / norm;
    const double u[3] = {q[1] / norm, q[2] / norm, q[3] / norm};
    double ux[3][3];
    cross_matrix(u, ux);
    for (int a = 0; a < 3; ++a) {
        G[a][0] = -2.0 / norm * u[a];
        for (int b = 0; b < 3; ++b) {
            G[a][b + 1] = 2.0 / norm * ((a == b ? w : 0.0) + ux[a][b]);
        }
    }
    for (int a = 0; a < 3; ++a) { /* (-[omega]x + W [L]x) G */
        double M[3];
        for (int k = 0; k < 3; ++k) {
            M[k] = -wx[a][k] + W[a][0] * lx[0][k] + W[a][1] * lx[1][k] + W[a][2] * lx[2][k];
        }
        for (int b = 0; b < 4; ++b) {
            d_omega[a][b] = M[0] * G[0][b] + M[1] * G[1][b] + M[2] * G[2][b];
        }
    }
}

/* The body's dq/dt rows against its own q and L: rows[4][13] by its state's components. */
static void quaternion_rows(const tb__body *body, const double *s, double rows[4][TB_STATE_SIZE])
{
    double d_omega[3][4], W[3][3], G[3][4], omega[3];
    tb__jacobian_rotation(body, s, omega, W, G, d_omega);
    const double *q = s + TB_STATE_Q;
    /* (0, w) (x) q = Omega(w) q = Xi(q) w, rows as kinematics() writes them */
    const double Omega[4][4] = {{0.0, -omega[0], -omega[1], -omega[2]},
                                {omega[0], 0.0, -omega[2], omega[1]},
                                {omega[1], omega[2], 0.0, -omega[0]},
                                {omega[2], -omega[1], omega[0], 0.0}};
    const double Xi[4][3] = {
        {-q[1], -q[2], -q[3]}, {q[0], q[3], -q[2]}, {-q[3], q[0], q[1]}, {q[2], -q[1], q[0]}};
    memset(rows, 0, 4 * TB_STATE_SIZE * sizeof(double));
    for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) {
            double sum = Omega[a][b];
            for (int k = 0; k < 3; ++k) {
                sum += Xi[a][k] * d_omega[k][b];
            }
            rows[a][TB_STATE_Q + b] = 0.5 * sum;
        }
        for (int b = 0; b < 3; ++b) {
            rows[a][TB_STATE_L + b] =
                0.5 * (Xi[a][0] * W[0][b] + Xi[a][1] * W[1][b] + Xi[a][2] * W[2][b]);
        }
    }
}

/* The kinematic rows (x and q) of slot s: only its own columns are not zero. */
static void kinematic_rows(const tb_scene *scene, const tb__jacobian_room *j, size_t s,
                           const double *y, double *values)
{
    const tb__body *body = &scene->bodies[s];
    const size_t own = tb__jacobian_find_columns(j, s, s), first = TB_STATE_SIZE * s;
    double rows[4][TB_STATE_SIZE];
    quaternion_rows(body, y + first, rows);
    for (size_t r = first; r < first + TB_STATE_P; ++r) {
        double *row = values + entry_of(j, s, r, 0);
        memset(row, 0, j->row_length[s] * sizeof(double));
        if (r < first + TB_STATE_Q) {
            row[own + TB_STATE_P + (r - first)] = body->inv_mass;
        } else {
            memcpy(row + own, rows[r - first - TB_STATE_Q], sizeof rows[0]);
        }
    }
}

/* The loads' rows (P and L) of the asleep bodies: zero, as sleep_zero makes their derivative. */
static void asleep_rows(const tb_scene *scene, const tb__jacobian_room *j, double *values)
{
    for (size_t s = 0; s < scene->slot_count; ++s) {
        if (!tb__body_asleep(scene, scene->slot_ids[s])) {
            continue;
        }
        const size_t first = TB_STATE_SIZE * s;
        for (size_t r = first + TB_STATE_P; r < first + TB_STATE_SIZE; ++r) {
            memset(values + entry_of(j, s, r, 0), 0, j->row_length[s] * sizeof(double));
        }
    }
}

/* The quotients of the effects without analytic rows, into every entry of the pattern. */
static int quotient_rows(tb_scene *scene, const tb__jacobian_room *j, double t, const double *y,
                         double *values)
{
    const bool central = at_a_touch(scene, j, t, y);
    int rc = central ? 0 : quotient_of(scene)(t, y, j->f_base, scene);
    memcpy(j->y_work, y, j->n * sizeof(double));
    if (central) {
        memcpy(j->y_back, y, j->n * sizeof(double));
    }
    for (size_t c = 0; c < j->color_count && rc == 0; ++c) {
        for (size_t k = 0; k < TB_STATE_SIZE && rc == 0; ++k) {
            rc = quotient_columns(scene, j, c, k, t, y, central, values);
        }
    }
    return rc;
}

int tb__scene_jacobian_values(tb_scene *scene, double t, const double *y, const double *fy,
                              double *values)
{
    (void)fy; /* the quotients are of their own part of the derivative */
    const tb__jacobian_room *j = scene->jacobian;
    int rc = 0;
    if (tb__scene_has_quotient_part(scene)) {
        rc = quotient_rows(scene, j, t, y, values);
    } else {
        memset(values, 0, j->entries * sizeof(double));
    }
    rc = rc != 0 ? rc : tb__scene_motions(scene, t, y, j->f_work); /* the quotients moved them */
    tb__jacobian_rows rows = {j, values, y};
    for (size_t k = 0; k < scene->effect_count && rc == 0; ++k) {
        const tb__effect *effect = &scene->effects[k];
        if (!tb__scene_rows_by_quotients(scene, effect->ops) && effect->ops->jacobian != NULL) {
            rc = effect->ops->jacobian(effect, scene, t, y, &rows);
        }
    }
    if (rc == 0) {
        asleep_rows(scene, j, values);
    }
    for (size_t s = 0; s < scene->slot_count && rc == 0; ++s) {
        kinematic_rows(scene, j, s, y, values);
    }
    return rc;
}

/* J M^-1 J^T lambda = b for the joints' rows, exactly, by a block Cholesky factor L L^T whose
 * blocks are the joints (up to 6 x 6). Two joints couple where they share a dynamic body. The
 * pattern is made when a joint is added: a minimum-degree elimination order (on a chain or a
 * tree the leaves go first, so no block fills in and the cost is linear in the joints; a loop
 * fills one block column per loop), each column's blocks below the diagonal, and the list of
 * updates L(i, k) -= L(i, j) L(k, j)^T the right-looking factorisation makes. Each solve then
 * assembles, factors and substitutes with no allocation.
 *
 * Rows that repeat one another (a door on two coaxial hinges, a planar loop of hinges) make
 * J M^-1 J^T singular, positive semi-definite: the accelerations are unique, lambda is not.
 * A row whose pivot, once the rows before it are eliminated, falls to TB__PIVOT_DROP of its
 * own diagonal (round-off of a combination of the others) is dropped: its column of L is zero
 * and its lambda 0. That is the factor of J M^-1 J^T without the row, so the other rows are
 * solved exactly; the system is consistent (the dropped row is a combination of the others,
 * and so is its right-hand side: the same accelerations' rows), so the dropped row holds too,
 * and its share of the load goes to the rows it repeats (tests/test_joints_redundant.c). */
#include "constraints/joints_internal.h"

#include "core/validate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A pivot at most this fraction of its row's diagonal drops the row. A repeated row's pivot is
 * round-off, about 1e-16 to 1e-14 of it; an independent row's is its squared sine to the span
 * of the rows before it, so rows kept apart by more than 1e-5 rad stay in the solve. */
#define TB__PIVOT_DROP 1e-10

/* A growing list of joint indices (the graph's adjacency during the ordering). */
typedef struct list {
    size_t *items;
    size_t count, capacity;
} list;

static bool list_push(list *l, size_t item)
{
    if (l->count == l->capacity) {
        const size_t capacity = l->capacity > 0 ? 2 * l->capacity : 4;
        size_t *grown = tb__realloc_array(l->items, capacity, sizeof *grown);
        if (grown == NULL) {
            return false;
        }
        l->items = grown;
        l->capacity = capacity;
    }
    l->items[l->count++] = item;
    return true;
}

static bool list_has(const list *l, size_t item)
{
    for (size_t k = 0; k < l->count; ++k) {
        if (l->items[k] == item) {
            return true;
        }
    }
    return false;
}

static void list_remove(list *l, size_t item)
{
    for (size_t k = 0; k < l->count; ++k) {
        if (l->items[k] == item) {
            l->items[k] = l->items[--l->count];
            return;
        }
    }
}

static bool share_body(const tb_scene *scene, const tb__joint *a, const tb__joint *b)
{
    if (!tb__joint_in_pattern(a) || !tb__joint_in_pattern(b)) { /* a soft joint: loads */
        return false;
    }
    for (int s = 0; s < 2; ++s) {
        for (int u = 0; u < 2; ++u) {
            if (a->body[s] == b->body[u] && tb__joint_side_moves(scene, a->body[s])) {
                return true;
            }
        }
    }
    return false;
}

/* The joint graph (adjacency by shared dynamic bodies). */
static bool build_graph(const tb_scene *scene, const tb__joint *joints, size_t count, list *adj)
{
    for (size_t i = 0; i < count; ++i) {
        for (size_t k = i + 1; k < count; ++k) {
            if (share_body(scene, &joints[i], &joints[k]) &&
                (!list_push(&adj[i], k) || !list_push(&adj[k], i))) {
                return false;
            }
        }
    }
    return true;
}

/* Minimum-degree elimination: order[p] the joint eliminated p-th; pattern[j] its neighbours
 * still in the graph then (the column's blocks, fill included). */
static bool eliminate(size_t count, list *adj, size_t *order, list *pattern)
{
    unsigned char *gone = calloc(count > 0 ? count : 1, 1);
    bool ok = gone != NULL;
    for (size_t p = 0; p < count && ok; ++p) {
        size_t v = count;
        for (size_t j = 0; j < count; ++j) {
            if (!gone[j] && (v == count || adj[j].count < adj[v].count)) {
                v = j;
            }
        }
        order[p] = v;
        gone[v] = 1;
        const list *n = &adj[v];
        for (size_t a = 0; a < n->count && ok; ++a) {
            ok = list_push(&pattern[v], n->items[a]);
            list_remove(&adj[n->items[a]], v);
            for (size_t b = 0; b < n->count && ok; ++b) {
                const size_t x = n->items[a], y = n->items[b];
                if (x != y && !list_has(&adj[x], y)) {
                    ok = list_push(&adj[x], y); /* fill: v's neighbours become a clique */
                }
            }
        }
    }
    free(gone);
    return ok;
}

/* The index of block (row joint, column position p) in the solver's column, by bisection on
 * the positions of the column's rows. */
static size_t find_block(const tb__joint_solver *solver, const size_t *position, size_t p,
                         size_t row)
{
    size_t low = solver->column_start[p], high = solver->column_start[p + 1];
    while (low + 1 < high) {
        const size_t middle = low + (high - low) / 2;
        if (position[solver->below_joint[middle]] <= position[row]) {
            low = middle;
        } else {
            high = middle;
        }
    }
    return solver->below[low];
}

/* Sorts a column's rows by position (insertion: a column holds a few). */
static void sort_by_position(list *column, const size_t *position)
{
    for (size_t k = 1; k < column->count; ++k) {
        const size_t item = column->items[k];
        size_t j = k;
        for (; j > 0 && position[column->items[j - 1]] > position[item]; --j) {
            column->items[j] = column->items[j - 1];
        }
        column->items[j] = item;
    }
}

/* Each column's rows by position, their block indices (after the count diagonal ones). */
static bool lay_columns(tb__joint_solver *s, list *pattern, const size_t *position)
{
    size_t total = 0;
    for (size_t p = 0; p < s->count; ++p) {
        total += pattern[s->order[p]].count;
    }
    s->below = tb__malloc_array(total > 0 ? total : 1, sizeof(size_t));
    s->below_joint = tb__malloc_array(total > 0 ? total : 1, sizeof(size_t));
    if (s->below == NULL || s->below_joint == NULL) {
        return false;
    }
    size_t e = 0;
    for (size_t p = 0; p < s->count; ++p) {
        list *column = &pattern[s->order[p]];
        sort_by_position(column, position);
        s->column_start[p] = e;
        for (size_t k = 0; k < column->count; ++k, ++e) {
            s->below[e] = s->count + e;
            s->below_joint[e] = column->items[k];
        }
    }
    s->column_start[s->count] = e;
    s->block_count = s->count + e;
    return true;
}

/* The updates each column makes on the later ones: L(b, a) -= L(b, v) L(a, v)^T for rows
 * a <= b of column v (by position), the diagonal block of a where a = b. */
static bool list_updates(tb__joint_solver *s, const size_t *position)
{
    size_t total = 0;
    for (size_t p = 0; p < s->count; ++p) {
        const size_t m = s->column_start[p + 1] - s->column_start[p];
        total += m * (m + 1) / 2;
    }
    s->updates = tb__malloc_array(total > 0 ? total : 1, sizeof(tb__block_update));
    if (s->updates == NULL) {
        return false;
    }
    size_t u = 0;
    for (size_t p = 0; p < s->count; ++p) {
        s->update_start[p] = u;
        const size_t begin = s->column_start[p], end = s->column_start[p + 1];
        for (size_t a = begin; a < end; ++a) {
            for (size_t b = a; b < end; ++b) {
                const size_t ra = s->below_joint[a], rb = s->below_joint[b];
                s->updates[u++] = (tb__block_update){
                    .first = s->below[b],
                    .second = s->below[a],
                    .target = a == b ? ra : find_block(s, position, position[ra], rb),
                    .first_joint = rb,
                    .second_joint = ra};
            }
        }
    }
    s->update_start[s->count] = u;
    return true;
}

/* Every shared body's contribution to a block of J M^-1 J^T (the diagonal ones included). */
static bool list_couplings(const tb_scene *scene, tb__joint_solver *s, const tb__joint *joints,
                           const size_t *position)
{
    size_t capacity = 2 * s->count, n = 0;
    for (size_t i = 0; i < s->count; ++i) {
        capacity += 4 * (s->column_start[position[i] + 1] - s->column_start[position[i]]);
    }
    s->couplings = tb__malloc_array(capacity > 0 ? capacity : 1, sizeof(tb__joint_coupling));
    if (s->couplings == NULL) {
        return false;
    }
    for (size_t p = 0; p < s->count; ++p) {
        const size_t k = s->order[p];
        for (int side = 0; side < 2; ++side) {
            if (tb__joint_in_pattern(&joints[k]) &&
                tb__joint_side_moves(scene, joints[k].body[side])) {
                s->couplings[n++] = (tb__joint_coupling){k, k, side, side, k};
            }
        }
        for (size_t e = s->column_start[p]; e < s->column_start[p + 1]; ++e) {
            const size_t i = s->below_joint[e];
            for (int si = 0; si < 2; ++si) {
                for (int sk = 0; sk < 2; ++sk) {
                    if (joints[i].body[si] == joints[k].body[sk] &&
                        tb__joint_side_moves(scene, joints[k].body[sk])) {
                        s->couplings[n++] = (tb__joint_coupling){i, k, si, sk, s->below[e]};
                    }
                }
            }
        }
    }
    s->coupling_count = n;
    return true;
}

void tb__joint_solver_free(tb__joint_solver *solver)
{
    free(solver->order);
    free(solver->column_start);
    free(solver->below);
    free(solver->below_joint);
    free(solver->update_start);
    free(solver->updates);
    free(solver->couplings);
    free(solver->blocks);
    free(solver->scale);
    memset(solver, 0, sizeof *solver);
}

static bool lay_out(const tb_scene *scene, const tb__joint *joints, tb__joint_solver *s, list *adj,
                    list *pattern, size_t *position)
{
    const size_t n = s->count;
    s->order = tb__malloc_array(n, sizeof(size_t));
    s->column_start = tb__malloc_array(n + 1, sizeof(size_t));
    s->update_start = tb__malloc_array(n + 1, sizeof(size_t));
    if (s->order == NULL || s->column_start == NULL || s->update_start == NULL ||
        !build_graph(scene, joints, n, adj) || !eliminate(n, adj, s->order, pattern)) {
        return false;
    }
    for (size_t p = 0; p < n; ++p) {
        position[s->order[p]] = p;
    }
    if (!lay_columns(s, pattern, position) || !list_updates(s, position) ||
        !list_couplings(scene, s, joints, position)) {
        return false;
    }
    s->blocks = tb__malloc_array(s->block_count, TB__BLOCK * sizeof(double));
    s->scale = tb__malloc_array(n > 0 ? n : 1, TB__JOINT_ROWS * sizeof(double));
    return s->blocks != NULL && s->scale != NULL;
}

tb_status tb__joint_solver_build(const tb_scene *scene, const tb__joint *joints, size_t count,
                                 tb__joint_solver *out)
{
    tb__joint_solver solver = {.count = count};
    list *adj = calloc(count, sizeof(list)), *pattern = calloc(count, sizeof(list));
    size_t *position = tb__malloc_array(count, sizeof(size_t));
    const bool ok = adj != NULL && pattern != NULL && position != NULL &&
                    lay_out(scene, joints, &solver, adj, pattern, position);
    for (size_t j = 0; j < count && adj != NULL && pattern != NULL; ++j) {
        free(adj[j].items);
        free(pattern[j].items);
    }
    free(adj);
    free(pattern);
    free(position);
    if (!ok) {
        tb__joint_solver_free(&solver);
        return TB_STATUS_OUT_OF_MEMORY;
    }
    tb__joint_solver_free(out);
    *out = solver;
    return TB_STATUS_OK;
}

/* --- the numbers --------------------------------------------------------------------------- */

static double row_dot(const tb__joint_row *a, int sa, const tb__joint_row *b, int sb)
{
    return a->v[sa][0] * b->v[sb][0] + a->v[sa][1] * b->v[sb][1] + a->v[sa][2] * b->v[sb][2] +
           a->w[sa][0] * b->w[sb][0] + a->w[sa][1] * b->w[sb][1] + a->w[sa][2] * b->w[sb][2];
}

/* The kernels below take their row counts as constants where they are inlined into a
 * dispatch, so that the compiler unrolls their loops for 3, 5 and 6 rows (the assembly of the
 * blocks was half of a chain's step with the counts read at run time). */
#if defined(__GNUC__) || defined(__clang__)
#define TB__UNROLLED static inline __attribute__((always_inline))
#else
#define TB__UNROLLED static inline
#endif

/* B += J_side W_side^T for the mi rows of J and mk of W (a diagonal block: its lower half). */
TB__UNROLLED void add_product(double *B, const tb__joint_row *J, int js, const tb__joint_row *W,
                              int ws, int mi, int mk, bool diagonal)
{
    for (int r = 0; r < mi; ++r) {
        for (int q = 0; q < (diagonal ? r + 1 : mk); ++q) {
            B[TB__JOINT_ROWS * r + q] += row_dot(&J[r], js, &W[q], ws);
        }
    }
}

/* One shared body's part of a block, dispatched on the row counts. */
static void add_coupling(double *B, const tb__joint_coupling *cp, const tb__joint_eval *ei,
                         const tb__joint_eval *ek, int mi, int mk)
{
    const tb__joint_row *J = ei->J, *W = ek->W;
    const int js = cp->row_side, ws = cp->column_side;
    if (cp->row_joint == cp->column_joint) { /* its lower half is read */
        switch (mi) {
        case 3:
            add_product(B, J, js, W, ws, 3, 3, true);
            return;
        case 5:
            add_product(B, J, js, W, ws, 5, 5, true);
            return;
        default:
            add_product(B, J, js, W, ws, 6, 6, true);
            return;
        }
    }
#define TB__CASE(a, b)                                                                             \
    case 8 * (a) + (b):                                                                            \
        add_product(B, J, js, W, ws, a, b, false);                                                 \
        return;
    switch (8 * mi + mk) {
        TB__CASE(3, 3)
        TB__CASE(3, 5)
        TB__CASE(3, 6)
        TB__CASE(5, 3)
        TB__CASE(5, 5)
        TB__CASE(5, 6)
        TB__CASE(6, 3)
        TB__CASE(6, 5)
    default:
        add_product(B, J, js, W, ws, 6, 6, false);
        return;
    }
#undef TB__CASE
}

static void assemble(tb__joint_solver *s, const tb__joint *joints, const tb__joint_eval *evals)
{
    for (size_t p = 0; p < s->count; ++p) {
        const size_t v = s->order[p];
        memset(s->blocks + TB__BLOCK * v, 0, TB__BLOCK * sizeof(double));
        for (size_t e = s->column_start[p]; e < s->column_start[p + 1]; ++e) {
            memset(s->blocks + TB__BLOCK * s->below[e], 0, TB__BLOCK * sizeof(double));
        }
    }
    for (size_t c = 0; c < s->coupling_count; ++c) {
        const tb__joint_coupling *cp = &s->couplings[c];
        add_coupling(s->blocks + TB__BLOCK * cp->block, cp, &evals[cp->row_joint],
                     &evals[cp->column_joint], joints[cp->row_joint].solved_rows,
                     joints[cp->column_joint].solved_rows);
    }
    for (size_t j = 0; j < s->count; ++j) { /* each row's own scale, for dropping repeats */
        for (int r = 0; r < joints[j].solved_rows; ++r) {
            s->scale[TB__JOINT_ROWS * j + r] = s->blocks[TB__BLOCK * j + (TB__JOINT_ROWS + 1) * r];
        }
    }
}

/* D = L L^T in place (lower), m x m, with 1 / L_jj kept on the diagonal (the substitutions
 * multiply); a row whose pivot is at most TB__PIVOT_DROP of its scale is dropped (1 / L_jj and
 * its column 0). 0, or 1 for a pivot that is not a number. */
TB__UNROLLED int factor_diagonal(double *D, const double *scale, int m)
{
    for (int j = 0; j < m; ++j) {
        double d = D[TB__JOINT_ROWS * j + j];
        for (int k = 0; k < j; ++k) {
            d -= D[TB__JOINT_ROWS * j + k] * D[TB__JOINT_ROWS * j + k];
        }
        if (isnan(d)) {
            return 1;
        }
        const double inverse = d > TB__PIVOT_DROP * scale[j] ? 1.0 / sqrt(d) : 0.0;
        D[TB__JOINT_ROWS * j + j] = inverse;
        for (int i = j + 1; i < m; ++i) {
            double x = D[TB__JOINT_ROWS * i + j];
            for (int k = 0; k < j; ++k) {
                x -= D[TB__JOINT_ROWS * i + k] * D[TB__JOINT_ROWS * j + k];
            }
            D[TB__JOINT_ROWS * i + j] = x * inverse;
        }
    }
    return 0;
}

/* B <- B L^-T for B of rows x m. */
TB__UNROLLED void right_solve(double *B, int rows, const double *L, int m)
{
    for (int i = 0; i < rows; ++i) {
        double *b = B + TB__JOINT_ROWS * i;
        for (int j = 0; j < m; ++j) {
            double x = b[j];
            for (int k = 0; k < j; ++k) {
                x -= b[k] * L[TB__JOINT_ROWS * j + k];
            }
            b[j] = x * L[TB__JOINT_ROWS * j + j];
        }
    }
}

/* T -= F S^T, F of mf x m, S of ms x m; only T's lower half where F is S (a diagonal block). */
TB__UNROLLED void subtract_product(double *T, const double *F, int mf, const double *S, int ms,
                                   int m)
{
    for (int i = 0; i < mf; ++i) {
        for (int j = 0; j < (F == S ? i + 1 : ms); ++j) {
            double x = 0.0;
            for (int k = 0; k < m; ++k) {
                x += F[TB__JOINT_ROWS * i + k] * S[TB__JOINT_ROWS * j + k];
            }
            T[TB__JOINT_ROWS * i + j] -= x;
        }
    }
}

TB__UNROLLED int factor_column(tb__joint_solver *s, const tb__joint *joints, size_t p, int m)
{
    double *D = s->blocks + TB__BLOCK * s->order[p];
    if (factor_diagonal(D, s->scale + TB__JOINT_ROWS * s->order[p], m) != 0) {
        return 1;
    }
    for (size_t e = s->column_start[p]; e < s->column_start[p + 1]; ++e) {
        right_solve(s->blocks + TB__BLOCK * s->below[e], joints[s->below_joint[e]].solved_rows, D,
                    m);
    }
    for (size_t u = s->update_start[p]; u < s->update_start[p + 1]; ++u) {
        const tb__block_update *up = &s->updates[u];
        subtract_product(s->blocks + TB__BLOCK * up->target, s->blocks + TB__BLOCK * up->first,
                         joints[up->first_joint].solved_rows, s->blocks + TB__BLOCK * up->second,
                         joints[up->second_joint].solved_rows, m);
    }
    return 0;
}

static int factor(tb__joint_solver *s, const tb__joint *joints)
{
    int rc = 0;
    for (size_t p = 0; p < s->count && rc == 0; ++p) {
        switch (joints[s->order[p]].solved_rows) {
        case 1: /* a soft joint's axial row */
            rc = factor_column(s, joints, p, 1);
            break;
        case 3:
            rc = factor_column(s, joints, p, 3);
            break;
        case 5:
            rc = factor_column(s, joints, p, 5);
            break;
        case 6:
            rc = factor_column(s, joints, p, 6);
            break;
        default: /* a soft or broken joint: no rows */
            break;
        }
    }
    return rc;
}

/* L y = b for column p: y = L_pp^-1 b_p, then the rows below take their share. */
TB__UNROLLED void forward_column(const tb__joint_solver *s, const tb__joint *joints,
                                 tb__joint_eval *evals, size_t p, int m)
{
    const size_t v = s->order[p];
    const double *L = s->blocks + TB__BLOCK * v;
    double *y = evals[v].lambda;
    for (int i = 0; i < m; ++i) {
        for (int k = 0; k < i; ++k) {
            y[i] -= L[TB__JOINT_ROWS * i + k] * y[k];
        }
        y[i] *= L[TB__JOINT_ROWS * i + i];
    }
    for (size_t e = s->column_start[p]; e < s->column_start[p + 1]; ++e) {
        const double *B = s->blocks + TB__BLOCK * s->below[e];
        double *b = evals[s->below_joint[e]].lambda;
        for (int i = 0; i < joints[s->below_joint[e]].solved_rows; ++i) {
            for (int k = 0; k < m; ++k) {
                b[i] -= B[TB__JOINT_ROWS * i + k] * y[k];
            }
        }
    }
}

/* L^T x = y for column p: the rows below give back their share, then x = L_pp^-T. */
TB__UNROLLED void backward_column(const tb__joint_solver *s, const tb__joint *joints,
                                  tb__joint_eval *evals, size_t p, int m)
{
    const size_t v = s->order[p];
    const double *L = s->blocks + TB__BLOCK * v;
    double *x = evals[v].lambda;
    for (size_t e = s->column_start[p]; e < s->column_start[p + 1]; ++e) {
        const double *B = s->blocks + TB__BLOCK * s->below[e];
        const double *xw = evals[s->below_joint[e]].lambda;
        for (int i = 0; i < joints[s->below_joint[e]].solved_rows; ++i) {
            for (int k = 0; k < m; ++k) {
                x[k] -= B[TB__JOINT_ROWS * i + k] * xw[i];
            }
        }
    }
    for (int i = m - 1; i >= 0; --i) {
        for (int k = i + 1; k < m; ++k) {
            x[i] -= L[TB__JOINT_ROWS * k + i] * x[k];
        }
        x[i] *= L[TB__JOINT_ROWS * i + i];
    }
}

/* L L^T x = b, b in each eval's lambda (overwritten by x). */
static void substitute(const tb__joint_solver *s, const tb__joint *joints, tb__joint_eval *evals)
{
    for (size_t p = 0; p < s->count; ++p) {
        const int m = joints[s->order[p]].solved_rows;
        if (m == 3) {
            forward_column(s, joints, evals, p, 3);
        } else if (m == 1) {
            forward_column(s, joints, evals, p, 1);
        } else if (m > 0) {
            forward_column(s, joints, evals, p, m == 5 ? 5 : 6);
        }
    }
    for (size_t p = s->count; p-- > 0;) {
        const int m = joints[s->order[p]].solved_rows;
        if (m == 3) {
            backward_column(s, joints, evals, p, 3);
        } else if (m == 1) {
            backward_column(s, joints, evals, p, 1);
        } else if (m > 0) {
            backward_column(s, joints, evals, p, m == 5 ? 5 : 6);
        }
    }
}

int tb__joint_solve(tb__joint_solver *solver, const tb__joint *joints, tb__joint_eval *evals)
{
    assemble(solver, joints, evals);
    if (factor(solver, joints) != 0) {
        return 1;
    }
    for (size_t j = 0; j < solver->count; ++j) {
        if (joints[j].axial_first) { /* its springs' lambdas are their own */
            evals[j].lambda[0] = joints[j].solved_rows > 0 ? evals[j].rhs[0] : evals[j].lambda[0];
        } else if (joints[j].solved_rows > 0) {
            memcpy(evals[j].lambda, evals[j].rhs, sizeof evals[j].lambda);
        }
    }
    substitute(solver, joints, evals);
    return 0;
}

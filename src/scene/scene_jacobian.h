/* Private: the contact Jacobian's pattern and scratch, shared by scene_jacobian.c (the pattern,
 * built at step boundaries) and scene_jacobian_values.c (the values at (t, y)).
 *
 * The state's components are grouped into nodes: each dynamic body's 13, and each group of an
 * effect's states that belongs to bodies (a ground point's deflection, a friction slot's).
 * Two nodes are coupled when an effect couples them at the boundary: a pair of bodies within
 * 1 mm of each other (TB__JACOBIAN_GAP, among the contact's event pairs) or joined by a spring,
 * a state group and the bodies that hold it. The pattern is every component of a node against every
 * component of each node coupled to it (and itself): the bodies' contact graph, dense 13 x 13
 * blocks. */
#ifndef TUMBLE_SCENE_JACOBIAN_H
#define TUMBLE_SCENE_JACOBIAN_H

#include "scene/scene_internal.h"

#include <stddef.h>

/* An effect's state group and its owners (ids, TB_ALL_BODIES for none), as visited. */
typedef struct tb__state_group {
    size_t first, count, body_a, body_b;
} tb__state_group;

typedef struct tb__scene_jacobian tb__jacobian_room;

struct tb__scene_jacobian {
    size_t n;          /* state size the pattern was built for */
    size_t node_count; /* nodes: the slots' bodies first, then the effects' state groups */
    size_t
        *node_start; /* node_count + 1: node u holds components [node_start[u], node_start[u+1]) */
    size_t *node_of; /* n: each component's node */
    /* each node's closed neighbourhood (itself included), ascending:
     * adjacent[adjacent_start[u] .. adjacent_start[u + 1]) */
    size_t *adjacent_start;
    size_t *adjacent;
    size_t *column_offset; /* per adjacency entry: where that node's columns start in u's rows */
    size_t *row_base;      /* node_count: entry of the node's first row's first column */
    size_t *row_length;    /* node_count: entries in each row of the node */
    size_t entries;        /* the pattern's, diagonal included */
    /* the column groups of the difference quotients: nodes of one colour share no row */
    size_t color_count;
    size_t *color_first; /* color_count + 1, into by_color */
    size_t *by_color;    /* node_count nodes sorted by colour */
    size_t *color;       /* node_count */
    size_t *mark;        /* node_count scratch of the colouring */
    /* scratch, grown at boundaries */
    size_t *edges; /* pairs of nodes (both directions) */
    size_t edge_count, edge_capacity;
    tb__state_group *groups;
    size_t group_count, group_capacity;
    tb__event_pair *pairs;
    size_t pair_capacity;
    double *scale;  /* n: each component's natural size (tb_scene_absolute_tolerances at 1) */
    double *y_work; /* n: the perturbed state */
    double *f_work; /* n: its derivative */
    double *f_base; /* n: the quotient part of the derivative at y (tb__scene_quotient_part) */
    double *y_back; /* n: the state perturbed back (central quotients) */
    double *f_back; /* n: its derivative */
    double *gaps;   /* gap_capacity: each body's nearest gap (central quotients) */
    size_t capacity_n, capacity_nodes, capacity_adjacent, gap_capacity;
    bool valid; /* a pattern was built for the scene's layout */
};

/* What an effect's jacobian op writes into (jacobian_rows.h): the pattern, its values, and y. */
struct tb__jacobian_rows {
    const tb__jacobian_room *room;
    double *values;
    const double *y;
};

/* Where node u's columns start within each row of node v, or (size_t)-1 when the pattern does
 * not couple them (jacobian_point.c). */
size_t tb__jacobian_find_columns(const tb__jacobian_room *j, size_t v, size_t u);

/* A body's rotation derivatives at its state s: omega = W L with W = R I^-1 R^T (R the rotation
 * of q/|q|), dtheta = G dq (world, the turn a change dq makes), and d omega / dq (3 x 4)
 * (scene_jacobian_values.c). */
void tb__jacobian_rotation(const tb__body *body, const double *s, double omega[3], double W[3][3],
                           double G[3][4], double d_omega[3][4]);

/* Of derivative.c: the part of tb_scene_derivative the Jacobian takes by difference quotients:
 * the loads of the effects without analytic rows whose loads depend on y (tb__effect_ops.jacobian
 * NULL, constant_loads false), every effect's own states' rate zero, the kinematic rows as the
 * derivative's; and whether the scene has such an effect. */
int tb__scene_quotient_part(double t, const double *y, double *dydt, void *ctx);
/* The derivative's first stage alone: every body's motion at (t, y) into the scene's motions
 * (tb__derivative_motion), for an effect's jacobian op; scratch (the state's size) gets the
 * kinematic rows. */
int tb__scene_motions(const tb_scene *scene, double t, const double *y, double *scratch);
bool tb__scene_has_quotient_part(const tb_scene *scene);
/* Whether an effect's load rows are difference quotients: it has no analytic rows, it couples
 * bodies (contact between bodies), or the scene's newest integrator is rosenbrock (derivative.c
 * says why); never for constant loads. */
bool tb__scene_rows_by_quotients(const tb_scene *scene, const tb__effect_ops *ops);

/* The values of a built pattern at (t, y) (scene_jacobian_values.c). */
int tb__scene_jacobian_values(tb_scene *scene, double t, const double *y, const double *fy,
                              double *values);

#endif

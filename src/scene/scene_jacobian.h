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
    size_t capacity_n, capacity_nodes, capacity_adjacent;
    bool valid; /* a pattern was built for the scene's layout */
};

/* The values of a built pattern at (t, y) (scene_jacobian_values.c). */
int tb__scene_jacobian_values(tb_scene *scene, double t, const double *y, const double *fy,
                              double *values);

#endif

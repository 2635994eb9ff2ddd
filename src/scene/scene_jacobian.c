/* The contact's sparse Jacobian as tb_ode_system.jacobian: its pattern, the bodies' contact
 * graph, built at step boundaries (tb__scene_jacobian_capacity, where it may allocate), and
 * written with its values at (t, y) (tb__scene_jacobian, which allocates nothing). The nodes and
 * their couplings are described in scene_jacobian.h; the values in scene_jacobian_values.c. */
#include "scene/scene_jacobian.h"

#include "core/validate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Every effect says what it couples: bodies through its event pairs or its sleep partner, its
 * states through state_owners. A user effect that couples bodies says nothing: no Jacobian. */
bool tb__scene_has_jacobian(const tb_scene *scene)
{
    /* joints: their solve (the derivative's last stage) couples every body of a jointed chain,
     * which the pattern does not hold; the colours would then mix the chain's columns */
    if (tb__scene_separable(scene) || scene->constraint_ops != NULL) {
        return false;
    }
    for (size_t k = 0; k < scene->effect_count; ++k) {
        const tb__effect_ops *ops = scene->effects[k].ops;
        const bool pairs = ops->stepping != NULL && ops->stepping->event_pairs != NULL;
        if (ops->couples_bodies && !pairs && ops->sleep_partner == NULL) {
            return false;
        }
        if (ops->owns_states && ops->state_owners == NULL) {
            return false;
        }
    }
    return true;
}

void tb__scene_jacobian_free(tb_scene *scene)
{
    tb__jacobian_room *j = scene->jacobian;
    if (j == NULL) {
        return;
    }
    void *owned[] = {j->node_start, j->node_of,    j->adjacent_start, j->adjacent, j->column_offset,
                     j->row_base,   j->row_length, j->color_first,    j->by_color, j->color,
                     j->mark,       j->edges,      j->groups,         j->pairs,    j->scale,
                     j->y_work,     j->f_work,     j->f_base,         j->y_back,   j->f_back,
                     j->gaps};
    for (size_t k = 0; k < sizeof owned / sizeof owned[0]; ++k) {
        free(owned[k]);
    }
    free(j);
    scene->jacobian = NULL;
}

/* Grows *array to hold count elements of size bytes; false when out of memory (unchanged). */
static bool grow(void *array, size_t count, size_t size)
{
    void **p = array;
    void *grown = tb__realloc_array(*p, count > 0 ? count : 1, size);
    if (grown == NULL) {
        return false;
    }
    *p = grown;
    return true;
}

/* The arrays sized by n and by the node count (at most n). */
static bool grow_rooms(tb__jacobian_room *j, size_t n)
{
    if (n <= j->capacity_n) {
        return true;
    }
    const bool ok =
        grow(&j->node_start, n + 1, sizeof(size_t)) && grow(&j->node_of, n, sizeof(size_t)) &&
        grow(&j->adjacent_start, n + 1, sizeof(size_t)) && grow(&j->row_base, n, sizeof(size_t)) &&
        grow(&j->row_length, n, sizeof(size_t)) && grow(&j->color_first, n + 1, sizeof(size_t)) &&
        grow(&j->by_color, n, sizeof(size_t)) && grow(&j->color, n, sizeof(size_t)) &&
        grow(&j->mark, n, sizeof(size_t)) && grow(&j->scale, n, sizeof(double)) &&
        grow(&j->y_work, n, sizeof(double)) && grow(&j->f_work, n, sizeof(double)) &&
        grow(&j->f_base, n, sizeof(double)) && grow(&j->y_back, n, sizeof(double)) &&
        grow(&j->f_back, n, sizeof(double));
    if (ok) {
        j->capacity_n = n;
    }
    return ok;
}

static void visit_group(void *ctx, size_t first, size_t count, size_t body_a, size_t body_b)
{
    tb__jacobian_room *j = ctx;
    if (j->group_count == j->group_capacity) {
        const size_t wanted = 2 * j->group_capacity + 16;
        if (!grow(&j->groups, wanted, sizeof *j->groups)) {
            j->valid = false; /* noted: the build fails */
            return;
        }
        j->group_capacity = wanted;
    }
    j->groups[j->group_count++] = (tb__state_group){first, count, body_a, body_b};
}

/* The nodes: slot s is node s (13 components); after the bodies each state group is a node,
 * and a state no group holds is a node of its own. */
static void build_nodes(tb__jacobian_room *j, const tb_scene *scene)
{
    const size_t bodies = TB_STATE_SIZE * scene->slot_count;
    for (size_t i = bodies; i < j->n; ++i) {
        j->node_of[i] = 0; /* 1: continues the node of the state before it */
    }
    for (size_t g = 0; g < j->group_count; ++g) {
        for (size_t k = 1; k < j->groups[g].count; ++k) {
            j->node_of[j->groups[g].first + k] = 1;
        }
    }
    size_t u = 0;
    for (size_t i = 0; i < j->n; ++i) {
        const bool starts = i < bodies ? i % TB_STATE_SIZE == 0 : j->node_of[i] == 0;
        if (starts) {
            j->node_start[u++] = i;
        }
        j->node_of[i] = u - 1;
    }
    j->node_count = u;
    j->node_start[u] = j->n;
}

/* The node of body id, or (size_t)-1 for none (no state, the world, TB_ALL_BODIES). */
static size_t body_node(const tb_scene *scene, size_t id)
{
    return id < scene->body_count ? scene->slots[id] : (size_t)-1;
}

static bool add_edge(tb__jacobian_room *j, size_t u, size_t v)
{
    if (u == (size_t)-1 || v == (size_t)-1 || u == v) {
        return true;
    }
    if (j->edge_count + 2 > j->edge_capacity) {
        const size_t wanted = 2 * j->edge_capacity + 64;
        if (!grow(&j->edges, 2 * wanted, sizeof(size_t))) {
            return false;
        }
        j->edge_capacity = wanted;
    }
    size_t *e = j->edges + 2 * j->edge_count;
    e[0] = u, e[1] = v, e[2] = v, e[3] = u;
    j->edge_count += 2;
    return true;
}

/* m: a pair of bodies farther apart than this at a step boundary is left out of the pattern.
 * Its contact cannot begin inside the step without the scene's events stopping CVODE at the
 * onset (a body's gap) or the step limit keeping the step shorter than the gap's closing time;
 * and the whole event lookahead (TB__EVENT_LOOKAHEAD, 5 cm) would couple twelve dice into one
 * dense block, whose factorisation then costs what the dense solver's does. */
#define TB__JACOBIAN_GAP 1e-3

/* m: how far beyond TB__JACOBIAN_GAP a pair may be and still enter the pattern. A fixed step
 * (scene->guard_dt > 0: the linearly implicit method, whose matrix must hold every contact the
 * step may make, since no event ends a fixed step at a second contact of a body already
 * touching) covers twice what the pair's closing speed and acceleration can close in one step;
 * adaptive methods (guard_dt 0) keep the pattern above. */
static double pair_reach(const tb_scene *scene, const tb__event_pair *pair)
{
    const double dt = scene->guard_dt;
    return dt > 0.0 ? 2.0 * dt * (fmax(-pair->gap_rate, 0.0) + 0.5 * pair->gravity * dt) : 0.0;
}

/* The pairs of bodies the effect's events see within TB__JACOBIAN_GAP (and pair_reach) at y. */
static bool add_pair_edges(tb__jacobian_room *j, const tb__effect *effect, const tb_scene *scene,
                           const double *y)
{
    const size_t count =
        effect->ops->stepping->event_pairs(effect, scene, y, j->pairs, j->pair_capacity);
    if (count > j->pair_capacity) {
        if (!grow(&j->pairs, count, sizeof *j->pairs)) {
            return false;
        }
        j->pair_capacity = count;
        effect->ops->stepping->event_pairs(effect, scene, y, j->pairs, j->pair_capacity);
    }
    bool ok = true;
    for (size_t k = 0; k < count && ok; ++k) {
        const tb__event_pair *pair = &j->pairs[k];
        ok = pair->gap > TB__JACOBIAN_GAP + pair_reach(scene, pair) ||
             add_edge(j, body_node(scene, pair->body_a), body_node(scene, pair->body_b));
    }
    return ok;
}

static bool collect_edges(tb__jacobian_room *j, const tb_scene *scene, const double *y)
{
    bool ok = true;
    j->edge_count = 0;
    for (size_t g = 0; g < j->group_count && ok; ++g) {
        const tb__state_group *group = &j->groups[g];
        const size_t node = j->node_of[group->first];
        const size_t a = body_node(scene, group->body_a), b = body_node(scene, group->body_b);
        ok = add_edge(j, node, a) && add_edge(j, node, b) && add_edge(j, a, b);
    }
    for (size_t k = 0; k < scene->effect_count && ok; ++k) {
        const tb__effect *effect = &scene->effects[k];
        const tb__effect_ops *ops = effect->ops;
        if (ops->couples_bodies && ops->stepping != NULL && ops->stepping->event_pairs != NULL) {
            ok = add_pair_edges(j, effect, scene, y);
        } else if (ops->couples_bodies && ops->sleep_partner != NULL) {
            ok = add_edge(j, body_node(scene, effect->body),
                          body_node(scene, ops->sleep_partner(effect)));
        }
    }
    return ok;
}

static int compare_edges(const void *a, const void *b)
{
    const size_t *p = a, *q = b;
    return p[0] != q[0] ? (p[0] < q[0] ? -1 : 1) : (p[1] < q[1] ? -1 : p[1] > q[1]);
}

/* Each node's closed neighbourhood, ascending, from the sorted edges. */
static bool build_adjacency(tb__jacobian_room *j)
{
    if (j->edge_count > 0) { /* no edge (bodies apart): edges may still be NULL */
        qsort(j->edges, j->edge_count, 2 * sizeof(size_t), compare_edges);
    }
    const size_t most = j->edge_count + j->node_count;
    if (most > j->capacity_adjacent) {
        if (!grow(&j->adjacent, most, sizeof(size_t)) ||
            !grow(&j->column_offset, most, sizeof(size_t))) {
            return false;
        }
        j->capacity_adjacent = most;
    }
    size_t e = 0, count = 0;
    for (size_t u = 0; u < j->node_count; ++u) {
        j->adjacent_start[u] = count;
        bool self = false;
        for (; e < j->edge_count && j->edges[2 * e] == u; ++e) {
            const size_t v = j->edges[2 * e + 1];
            if (!self && v > u) {
                j->adjacent[count++] = u, self = true;
            }
            if (count == j->adjacent_start[u] || j->adjacent[count - 1] != v) {
                j->adjacent[count++] = v;
            }
        }
        if (!self) {
            j->adjacent[count++] = u;
        }
    }
    j->adjacent_start[j->node_count] = count;
    return true;
}

static size_t node_size(const tb__jacobian_room *j, size_t u)
{
    return j->node_start[u + 1] - j->node_start[u];
}

/* Where each node's rows and, within them, each neighbour's columns lie among the entries. */
static void lay_out_rows(tb__jacobian_room *j)
{
    size_t entries = 0;
    for (size_t u = 0; u < j->node_count; ++u) {
        size_t length = 0;
        for (size_t e = j->adjacent_start[u]; e < j->adjacent_start[u + 1]; ++e) {
            j->column_offset[e] = length;
            length += node_size(j, j->adjacent[e]);
        }
        j->row_base[u] = entries;
        j->row_length[u] = length;
        entries += length * node_size(j, u);
    }
    j->entries = entries;
}

/* A state group no body holds (a free friction slot) couples only to itself; but a slot taken
 * inside a step acts on bodies the pattern does not know, so such nodes get colours of their
 * own, never shared with a body's columns. */
static bool unheld(const tb__jacobian_room *j, const tb_scene *scene, size_t u)
{
    return j->node_start[u] >= TB_STATE_SIZE * scene->slot_count &&
           j->adjacent_start[u + 1] - j->adjacent_start[u] == 1;
}

/* Greedy distance-2 colouring (Curtis, Powell and Reid): no two nodes of one colour share a row,
 * so one derivative evaluation gives the columns of a whole colour. */
static void color_nodes(tb__jacobian_room *j, const tb_scene *scene)
{
    size_t colors = 0, unheld_color = (size_t)-1;
    for (size_t u = 0; u < j->node_count; ++u) {
        j->color[u] = (size_t)-1;
        j->mark[u] = (size_t)-1;
    }
    for (size_t u = 0; u < j->node_count; ++u) {
        if (unheld(j, scene, u)) {
            unheld_color = unheld_color == (size_t)-1 ? colors++ : unheld_color;
            j->color[u] = unheld_color;
            continue;
        }
        for (size_t e = j->adjacent_start[u]; e < j->adjacent_start[u + 1]; ++e) {
            const size_t v = j->adjacent[e];
            for (size_t f = j->adjacent_start[v]; f < j->adjacent_start[v + 1]; ++f) {
                const size_t c = j->color[j->adjacent[f]];
                if (c != (size_t)-1) {
                    j->mark[c] = u;
                }
            }
        }
        if (unheld_color != (size_t)-1) {
            j->mark[unheld_color] = u;
        }
        size_t c = 0;
        while (c < colors && j->mark[c] == u) {
            ++c;
        }
        j->color[u] = c;
        colors = c == colors ? colors + 1 : colors;
    }
    j->color_count = colors;
    /* by_color: the nodes of each colour, a counting sort */
    memset(j->color_first, 0, (colors + 1) * sizeof(size_t));
    for (size_t u = 0; u < j->node_count; ++u) {
        j->color_first[j->color[u] + 1]++;
    }
    for (size_t c = 0; c < colors; ++c) {
        j->color_first[c + 1] += j->color_first[c];
    }
    for (size_t c = 0; c < colors; ++c) {
        j->mark[c] = j->color_first[c]; /* each colour's next place */
    }
    for (size_t u = 0; u < j->node_count; ++u) {
        j->by_color[j->mark[j->color[u]]++] = u;
    }
}

static tb_status build(tb__jacobian_room *j, tb_scene *scene, const double *y)
{
    j->n = tb_scene_state_size(scene);
    j->valid = true;
    j->group_count = 0;
    for (size_t k = 0; k < scene->effect_count; ++k) {
        const tb__effect *effect = &scene->effects[k];
        if (effect->ops->state_owners != NULL) {
            effect->ops->state_owners(effect, scene, visit_group, j);
        }
    }
    if (!j->valid || !grow_rooms(j, j->n)) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    if (scene->body_count > j->gap_capacity) {
        if (!grow(&j->gaps, scene->body_count, sizeof(double))) {
            return TB_STATUS_OUT_OF_MEMORY;
        }
        j->gap_capacity = scene->body_count;
    }
    build_nodes(j, scene);
    if (!collect_edges(j, scene, y) || !build_adjacency(j)) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    lay_out_rows(j);
    color_nodes(j, scene);
    return tb_scene_absolute_tolerances(scene, 1.0, j->scale);
}

size_t tb__scene_jacobian_capacity(double t, const double *y, void *ctx)
{
    (void)t;
    tb_scene *scene = ctx;
    if (scene->jacobian == NULL) {
        scene->jacobian = calloc(1, sizeof *scene->jacobian);
        if (scene->jacobian == NULL) {
            return 0;
        }
    }
    tb__jacobian_room *j = scene->jacobian;
    if (build(j, scene, y) != TB_STATUS_OK) {
        j->valid = false;
        return 0;
    }
    return j->entries;
}

/* The pattern as compressed sparse rows: each row of node u runs over the columns of its
 * closed neighbourhood, in ascending order. */
static void write_pattern(const tb__jacobian_room *j, size_t *row_starts, size_t *columns)
{
    for (size_t u = 0; u < j->node_count; ++u) {
        for (size_t r = j->node_start[u]; r < j->node_start[u + 1]; ++r) {
            size_t entry = j->row_base[u] + (r - j->node_start[u]) * j->row_length[u];
            row_starts[r] = entry;
            for (size_t e = j->adjacent_start[u]; e < j->adjacent_start[u + 1]; ++e) {
                const size_t v = j->adjacent[e];
                for (size_t c = j->node_start[v]; c < j->node_start[v + 1]; ++c) {
                    columns[entry++] = c;
                }
            }
        }
    }
    row_starts[j->n] = j->entries;
}

int tb__scene_jacobian(double t, const double *y, const double *fy, tb_ode_sparse *J, void *ctx)
{
    tb_scene *scene = ctx;
    const tb__jacobian_room *j = scene->jacobian;
    if (j == NULL || !j->valid || j->n != J->n || j->entries > J->capacity) {
        return -1; /* no pattern for this layout, or more entries than the integrator has room */
    }
    write_pattern(j, J->row_starts, J->columns);
    return tb__scene_jacobian_values(scene, t, y, fy, J->values);
}

/* Static friction between bodies: the contact effect's pool of friction slots, the map from
 * touching points to slots and its update at step boundaries (the law at a point:
 * contact_friction_law.c; contact_friction.h has the design). */
#include "effects/contact_friction.h"

#include "contact/contact_law.h"
#include "core/validate.h"
#include "effects/contact_pass_memo.h"
#include "math/tb_math.h"
#include "scene/jacobian_rows.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

/* A claimed slot whose pair no longer holds it is freed once |z| is below this many
 * presliding distances: a new contact then starts with its spring (nearly) unloaded. At
 * TB__BRISTLE_RELEASE_RATE that takes ln(1000) / 100 = 69 ms after the pair parted. */
#define TB__FRICTION_FREE_DEFLECTION 1e-3
/* Pairs handled per batch of the boundary's pass. */
#define TB__FRICTION_BATCH 16

/* body_a of a slot that no pair holds but that left the queue loaded (a provisional slot whose
 * point parted within the step): it relaxes like an unheld claimed slot and is queued again once
 * relaxed, so that no new point takes up another's deflection. Above every body id. */
#define TB__SLOT_RELAXING ((size_t)-2)

typedef struct tb__friction_slot {
    size_t body_a, body_b;   /* the pair holding it; body_a TB__NO_SLOT when free */
    size_t piece_a, piece_b; /* the pair's touching pieces (tb__pair_contact) */
    double key[3];           /* the point in A's principal frame at the last boundary, m */
} tb__friction_slot;

struct tb__friction_pool {
    size_t capacity;
    tb__friction_slot *slots;
    size_t *queue; /* ring of the free slots, handed out from the head */
    size_t head, free_count;
    size_t *index; /* the claimed slots sorted by (body_a, body_b, piece_a, piece_b) */
    size_t index_count;
    /* bodies + 1 entries, rebuilt with the index: the index entries of the pairs with body_a ==
     * a are [body_first[a], body_first[a + 1]), so that a pair's run is found without a search
     * over the whole index at every derivative */
    size_t bodies;
    size_t *body_first;
    bool *held; /* scratch of the boundary's pass: capacity flags */
    /* scratch of the boundary's pass: the points within the margin but not touching that hold
     * no slot of their pair, each reserved one after the touching points' claims */
    tb__friction_slot *near;
    size_t near_count;
    double free_deflection;
    double last_boundary; /* s: the scene's time at the last boundary; NAN before the first */
    tb_contact_friction_stats stats;
};

tb__friction_pool *tb__friction_pool_create(size_t slots, size_t bodies, double presliding)
{
    tb__friction_pool *pool = calloc(1, sizeof *pool);
    if (pool == NULL) {
        return NULL;
    }
    pool->slots = tb__malloc_array(slots, sizeof *pool->slots);
    pool->queue = tb__malloc_array(slots, sizeof *pool->queue);
    pool->index = tb__malloc_array(slots, sizeof *pool->index);
    pool->held = tb__malloc_array(slots, sizeof *pool->held);
    pool->near = tb__malloc_array(slots, sizeof *pool->near);
    if (pool->slots == NULL || pool->queue == NULL || pool->index == NULL || pool->held == NULL ||
        pool->near == NULL) {
        tb__friction_pool_destroy(pool);
        return NULL;
    }
    pool->body_first = calloc(bodies + 1, sizeof *pool->body_first);
    if (pool->body_first == NULL) {
        tb__friction_pool_destroy(pool);
        return NULL;
    }
    pool->capacity = slots;
    pool->bodies = bodies;
    tb__friction_restart(pool, NAN, NULL);
    pool->free_deflection = TB__FRICTION_FREE_DEFLECTION * presliding;
    pool->stats.slots = slots;
    return pool;
}

void tb__friction_pool_destroy(tb__friction_pool *pool)
{
    if (pool != NULL) {
        free(pool->slots);
        free(pool->queue);
        free(pool->index);
        free(pool->held);
        free(pool->near);
        free(pool->body_first);
        free(pool);
    }
}

size_t tb__friction_pool_slots(const tb__friction_pool *pool)
{
    return pool->capacity;
}

/* Whether a pair holds the slot (not free, not relaxing on its own). */
static bool paired(const tb__friction_slot *slot)
{
    return slot->body_a < TB__SLOT_RELAXING;
}

void tb__friction_state_owners(const tb__friction_pool *pool, size_t first_state,
                               tb__coupling_visit visit, void *ctx)
{
    for (size_t s = 0; s < pool->capacity; ++s) {
        const tb__friction_slot *slot = &pool->slots[s];
        const bool claimed = paired(slot);
        visit(ctx, first_state + TB__FRICTION_SLOT_STATES * s, TB__FRICTION_SLOT_STATES,
              claimed ? slot->body_a : TB_ALL_BODIES, claimed ? slot->body_b : TB_ALL_BODIES);
    }
}

/* Whether slot s's pair comes before pair p's: by bodies, then by pieces (a compound body's
 * piece pairs each keep their own slots). */
static bool pair_before(const tb__friction_slot *s, const tb__friction_slot *p)
{
    if (s->body_a != p->body_a || s->body_b != p->body_b) {
        return s->body_a < p->body_a || (s->body_a == p->body_a && s->body_b < p->body_b);
    }
    return s->piece_a < p->piece_a || (s->piece_a == p->piece_a && s->piece_b < p->piece_b);
}

static bool same_pair(const tb__friction_slot *s, const tb__friction_slot *p)
{
    return s->body_b == p->body_b && s->piece_a == p->piece_a && s->piece_b == p->piece_b;
}

/* The index entries [*first, *end) of pair p: among body a's (a run sorted by pair, as long as
 * a's partners times their points: a table under a dozen dice holds 48), those of p, found by
 * bisection. */
static void pair_run(const tb__friction_pool *pool, const tb__friction_slot *p, size_t *first,
                     size_t *end)
{
    const size_t a = p->body_a;
    if (a >= pool->bodies) { /* not a body of the effect: it holds no slot */
        *first = *end = 0;
        return;
    }
    size_t low = pool->body_first[a], high = pool->body_first[a + 1];
    while (low < high) { /* the first entry not before p */
        const size_t middle = low + (high - low) / 2;
        if (pair_before(&pool->slots[pool->index[middle]], p)) {
            low = middle + 1;
        } else {
            high = middle;
        }
    }
    *first = low;
    high = pool->body_first[a + 1];
    while (low < high && same_pair(&pool->slots[pool->index[low]], p)) {
        ++low;
    }
    *end = low;
}

/* body_first from the sorted index. */
static void index_bodies(tb__friction_pool *pool)
{
    size_t k = 0;
    for (size_t a = 0; a <= pool->bodies; ++a) {
        pool->body_first[a] = k;
        while (k < pool->index_count && pool->slots[pool->index[k]].body_a == a) {
            ++k;
        }
    }
}

/* Every slot free and queued, those whose anchor in z is unloaded first, each group in slot
 * order: with z NULL or all zero, the queue of a new pool. */
static void free_every_slot(tb__friction_pool *pool, const double *z)
{
    size_t k = 0;
    for (int loaded = 0; loaded < 2; ++loaded) {
        for (size_t s = 0; s < pool->capacity; ++s) {
            const double *zs = z != NULL ? z + TB__FRICTION_SLOT_STATES * s : NULL;
            if ((zs != NULL && (zs[0] != 0.0 || zs[1] != 0.0 || zs[2] != 0.0)) == (loaded == 1)) {
                pool->slots[s].body_a = TB__NO_SLOT;
                pool->queue[k++] = s;
            }
        }
    }
    pool->head = 0;
    pool->free_count = pool->capacity;
    pool->index_count = 0;
    index_bodies(pool);
}

void tb__friction_restart(tb__friction_pool *pool, double t, const double *z)
{
    if (t == pool->last_boundary) {
        return; /* the run continues where it stopped: the slots keep their anchors in z */
    }
    free_every_slot(pool, z);
    pool->last_boundary = NAN;
    pool->stats.in_use = 0;
}

void tb__friction_effect_restart(const tb__effect *effect, const tb_scene *scene, double t,
                                 const double *y)
{
    (void)scene;
    tb__friction_restart(tb__contact_of(effect)->friction, t, y + effect->state_offset);
}

static double distance2(const double p[3], const double q[3])
{
    const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    return tb__v3_dot(d, d);
}

/* The keys of pair's points in A's principal frame; touching[j]: depth > 0. */
static void point_keys(const tb__pair_contact *pair, const tb__motion *motion_a,
                       double keys[TB__MANIFOLD_POINTS][3], bool touching[TB__MANIFOLD_POINTS])
{
    for (int j = 0; j < pair->manifold.count; ++j) {
        const tb__contact_point *p = &pair->manifold.points[j];
        const double arm[3] = {p->position[0] - motion_a->x[0], p->position[1] - motion_a->x[1],
                               p->position[2] - motion_a->x[2]};
        tb__q_rotate_inverse(keys[j], motion_a->q, arm);
        touching[j] = p->depth > 0.0;
    }
}

/* When every open point's nearest unused entry (the first of equal distances, finite) is its
 * own, no two the same, the greedy rounds of match_claimed give each open point that entry
 * (a round's least distance is then some open point's nearest, and taking it leaves every other
 * open point's nearest unused): writes them and returns true. Else false, slots untouched. */
static bool own_nearest(const tb__friction_pool *pool, size_t first, size_t run, int count,
                        double distance[TB__MANIFOLD_POINTS][TB__MANIFOLD_POINTS],
                        const bool open[TB__MANIFOLD_POINTS], const bool used[TB__MANIFOLD_POINTS],
                        size_t slots[TB__MANIFOLD_POINTS])
{
    size_t nearest[TB__MANIFOLD_POINTS];
    bool taken[TB__MANIFOLD_POINTS] = {false};
    for (int j = 0; j < count; ++j) {
        double best = INFINITY;
        nearest[j] = run;
        for (size_t r = 0; r < run && open[j]; ++r) {
            if (!used[r] && distance[j][r] < best) {
                best = distance[j][r];
                nearest[j] = r;
            }
        }
        if (open[j] && (nearest[j] == run || taken[nearest[j]])) {
            return false;
        }
        taken[open[j] ? nearest[j] : 0] |= open[j];
    }
    for (int j = 0; j < count; ++j) {
        slots[j] = open[j] ? pool->index[first + nearest[j]] : slots[j];
    }
    return true;
}

/* Greedy nearest-first matching of the wanted points that have no slot yet to the run's slots
 * that none holds yet (a pair claims at most one slot per point it ever had at once, so the run
 * holds at most TB__MANIFOLD_POINTS). */
static void match_claimed(const tb__friction_pool *pool, size_t first, size_t end, int count,
                          double keys[TB__MANIFOLD_POINTS][3],
                          const bool wanted[TB__MANIFOLD_POINTS], size_t slots[TB__MANIFOLD_POINTS])
{
    bool used[TB__MANIFOLD_POINTS] = {false}, open[TB__MANIFOLD_POINTS] = {false};
    const size_t run = end - first < TB__MANIFOLD_POINTS ? end - first : TB__MANIFOLD_POINTS;
    /* every distance once; the rounds then only compare them */
    double distance[TB__MANIFOLD_POINTS][TB__MANIFOLD_POINTS];
    int left = 0;
    for (int j = 0; j < count && run > 0; ++j) {
        open[j] = wanted[j] && slots[j] == TB__NO_SLOT;
        left += open[j];
        for (size_t r = 0; r < run; ++r) {
            used[r] = used[r] || slots[j] == pool->index[first + r];
            distance[j][r] =
                open[j] ? distance2(keys[j], pool->slots[pool->index[first + r]].key) : INFINITY;
        }
    }
    if (own_nearest(pool, first, run, count, distance, open, used, slots)) {
        return;
    }
    for (size_t round = 0; round < run && left > 0; ++round, --left) {
        double best = INFINITY;
        int point = -1;
        size_t entry = 0;
        for (int j = 0; j < count; ++j) {
            for (size_t r = 0; r < run && open[j]; ++r) {
                const double d = used[r] ? INFINITY : distance[j][r];
                if (d < best) {
                    best = d;
                    point = j;
                    entry = r;
                }
            }
        }
        if (point < 0) {
            return;
        }
        used[entry] = true;
        open[point] = false;
        slots[point] = pool->index[first + entry];
    }
}

void tb__friction_match(const tb__friction_pool *pool, const tb__pair_contact *pair,
                        const tb__motion *motion_a, size_t *fresh,
                        size_t slots[TB__MANIFOLD_POINTS])
{
    double keys[TB__MANIFOLD_POINTS][3];
    bool touching[TB__MANIFOLD_POINTS];
    const int count = pair->manifold.count;
    point_keys(pair, motion_a, keys, touching);
    for (int j = 0; j < TB__MANIFOLD_POINTS; ++j) {
        slots[j] = TB__NO_SLOT;
    }
    size_t first, end;
    const tb__friction_slot key = {pair->body_a, pair->body_b, pair->piece_a, pair->piece_b, {0}};
    pair_run(pool, &key, &first, &end);
    match_claimed(pool, first, end, count, keys, touching, slots);
    for (int j = 0; j < count; ++j) {
        if (touching[j] && slots[j] == TB__NO_SLOT) {
            if (*fresh < pool->free_count) {
                slots[j] = pool->queue[(pool->head + *fresh) % pool->capacity];
            }
            ++*fresh; /* past free_count: no slot, counted at the boundary */
        }
    }
}

/* A claimed slot between two asleep bodies: frozen, kept claimed. */
static bool slot_asleep(const tb__friction_slot *slot, const tb_scene *scene)
{
    return paired(slot) && tb__pair_resting(scene, slot->body_a, slot->body_b);
}

void tb__friction_relax_all(const tb__friction_pool *pool, const tb_scene *scene, const double *z,
                            double *dz)
{
    for (size_t s = 0; s < pool->capacity; ++s) {
        const double rate = slot_asleep(&pool->slots[s], scene) ? 0.0 : TB__BRISTLE_RELEASE_RATE;
        for (size_t k = TB__FRICTION_SLOT_STATES * s; k < TB__FRICTION_SLOT_STATES * (s + 1); ++k) {
            dz[k] = -rate * z[k];
        }
    }
}

void tb__friction_relax_jacobian(const tb__friction_pool *pool, const tb_scene *scene,
                                 size_t first_state, struct tb__jacobian_rows *rows)
{
    for (size_t s = 0; s < pool->capacity; ++s) {
        const double rate = slot_asleep(&pool->slots[s], scene) ? 0.0 : TB__BRISTLE_RELEASE_RATE;
        tb__jacobian_set_diagonal(rows, first_state + TB__FRICTION_SLOT_STATES * s,
                                  TB__FRICTION_SLOT_STATES, -rate);
    }
}

/* The boundary's pass over one pair: held slots take the points' keys, provisional ones are
 * claimed for the pair; link: the pair's bodies share a sleeping island. */
static void hold_pair(tb__friction_pool *pool, const tb_scene *scene, const double *y,
                      const tb__pair_contact *pair, bool link, size_t *fresh)
{
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, pair->body_a, &motion);
    if (link) {
        tb__scene_sleep_link(scene, pair->body_a, pair->body_b);
    }
    tb__friction_hold(pool, pair, &motion, fresh);
}

/* The points within the margin that do not touch: the pair's claimed slots that no touching
 * point holds, nearest first, else one reserved at the boundary's end, so that a point that
 * starts touching within the next step finds a slot of its own pair. */
static void hold_near(tb__friction_pool *pool, const tb__pair_contact *pair,
                      double keys[TB__MANIFOLD_POINTS][3], const bool touching[TB__MANIFOLD_POINTS],
                      size_t slots[TB__MANIFOLD_POINTS])
{
    const int count = pair->manifold.count;
    bool near[TB__MANIFOLD_POINTS] = {false};
    for (int j = 0; j < count; ++j) {
        near[j] = !touching[j];
    }
    const tb__friction_slot key = {pair->body_a, pair->body_b, pair->piece_a, pair->piece_b, {0}};
    size_t first, end;
    pair_run(pool, &key, &first, &end);
    match_claimed(pool, first, end, count, keys, near, slots);
    for (int j = 0; j < count && pair->body_a < pool->bodies; ++j) {
        if (near[j] && slots[j] == TB__NO_SLOT && pool->near_count < pool->capacity) {
            tb__friction_slot *reserved = &pool->near[pool->near_count++];
            *reserved = key;
            tb__v3_set(reserved->key, keys[j][0], keys[j][1], keys[j][2]);
        }
    }
}

void tb__friction_hold(tb__friction_pool *pool, const tb__pair_contact *pair,
                       const tb__motion *motion_a, size_t *fresh)
{
    double keys[TB__MANIFOLD_POINTS][3];
    bool touching[TB__MANIFOLD_POINTS];
    size_t slots[TB__MANIFOLD_POINTS];
    point_keys(pair, motion_a, keys, touching);
    tb__friction_match(pool, pair, motion_a, fresh, slots); /* the touching points, as f(t, y) */
    hold_near(pool, pair, keys, touching, slots);
    for (int j = 0; j < pair->manifold.count; ++j) {
        if (slots[j] == TB__NO_SLOT) {
            continue;
        }
        tb__friction_slot *slot = &pool->slots[slots[j]];
        slot->body_a = pair->body_a;
        slot->body_b = pair->body_b;
        slot->piece_a = pair->piece_a;
        slot->piece_b = pair->piece_b;
        tb__v3_set(slot->key, keys[j][0], keys[j][1], keys[j][2]);
        pool->held[slots[j]] = true;
    }
}

/* Puts the claims of the pass (the slots held, not yet in the index) into the sorted index;
 * frees the claimed slots no pair holds whose deflection has relaxed. A slot's place in the
 * index only changes when it is claimed or freed, so the index stays nearly sorted and one
 * insertion per claim keeps it so. */
static void update_index(tb__friction_pool *pool, const tb_scene *scene, const double *z)
{
    size_t kept = 0;
    for (size_t k = 0; k < pool->index_count; ++k) {
        const size_t s = pool->index[k];
        const double *zs = z + TB__FRICTION_SLOT_STATES * s;
        if (!pool->held[s] && tb__v3_norm(zs) < pool->free_deflection &&
            !slot_asleep(&pool->slots[s], scene)) {
            pool->slots[s].body_a = TB__NO_SLOT;
            pool->queue[(pool->head + pool->free_count++) % pool->capacity] = s;
        } else {
            pool->index[kept++] = s;
        }
        pool->held[s] = false; /* what remains held is newly claimed */
    }
    pool->index_count = kept;
    for (size_t s = 0; s < pool->capacity; ++s) {
        if (!pool->held[s]) {
            continue;
        }
        pool->held[s] = false;
        size_t k = pool->index_count++;
        const tb__friction_slot *claimed = &pool->slots[s];
        for (; k > 0 && pair_before(claimed, &pool->slots[pool->index[k - 1]]); --k) {
            pool->index[k] = pool->index[k - 1];
        }
        pool->index[k] = s;
    }
    index_bodies(pool);
}

/* The boundary's pass over the effect's pairs at y (scene->time), then its end. */
static void boundary_pass(const tb__effect *effect, const tb_scene *scene, const double *y,
                          bool link)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    tb__friction_pool *pool = contact->friction;
    tb__friction_boundary_begin(pool);
    tb__pair_contact batch[TB__FRICTION_BATCH];
    tb__contact_pairs_begin(contact->pairs, scene, scene->time, y);
    tb__pass_memo_begin(contact->memo, scene, scene->time, y); /* for the next step's start */
    size_t count, fresh = 0;
    while ((count = tb__contact_pairs_next(contact->pairs, scene, y, batch, TB__FRICTION_BATCH)) >
           0) {
        tb__pass_memo_add(contact->memo, batch, count);
        for (size_t k = 0; k < count; ++k) {
            hold_pair(pool, scene, y, &batch[k], link, &fresh);
        }
    }
    tb__pass_memo_end(contact->memo);
    tb__friction_boundary_end(pool, scene, y + effect->state_offset, fresh);
}

void tb__friction_post_step(const tb__effect *effect, const tb_scene *scene, const double *y)
{
    boundary_pass(effect, scene, y, true);
}

bool tb__friction_boundary_due(const tb__friction_pool *pool, double t)
{
    return t != pool->last_boundary;
}

void tb__friction_step_start(const tb__effect *effect, const tb_scene *scene, const double *y)
{
    if (tb__friction_boundary_due(tb__contact_of(effect)->friction, scene->time)) {
        boundary_pass(effect, scene, y, false); /* the islands are linked at the post-step hook */
    }
}

void tb__friction_boundary_begin(tb__friction_pool *pool)
{
    for (size_t s = 0; s < pool->capacity; ++s) {
        pool->held[s] = false;
    }
    pool->near_count = 0;
}

/* The queue's slots whose deflection is loaded (a provisional slot whose point parted within the
 * step, a restart's loaded anchor) leave it and relax as TB__SLOT_RELAXING, put into the index
 * with the claims, until update_index queues them again relaxed; the rest keep their order. */
static void set_aside_loaded(tb__friction_pool *pool, const double *z)
{
    const double loaded = pool->free_deflection * pool->free_deflection;
    size_t kept = 0;
    for (size_t k = 0; k < pool->free_count; ++k) {
        const size_t s = pool->queue[(pool->head + k) % pool->capacity];
        const double *zs = z + TB__FRICTION_SLOT_STATES * s;
        if (tb__v3_dot(zs, zs) >= loaded) {
            pool->slots[s].body_a = TB__SLOT_RELAXING;
            pool->held[s] = true;
        } else {
            pool->queue[(pool->head + kept++) % pool->capacity] = s;
        }
    }
    pool->free_count = kept;
}

/* The near points' reservations, from the queue's head (after the touching points' claims). */
static void reserve_near(tb__friction_pool *pool)
{
    for (size_t k = 0; k < pool->near_count && pool->free_count > 0; ++k) {
        const size_t s = pool->queue[pool->head];
        pool->head = (pool->head + 1) % pool->capacity;
        pool->free_count--;
        pool->slots[s] = pool->near[k];
        pool->held[s] = true;
    }
}

void tb__friction_boundary_end(tb__friction_pool *pool, const tb_scene *scene, const double *z,
                               size_t fresh)
{
    const size_t claimed = fresh < pool->free_count ? fresh : pool->free_count;
    pool->head = (pool->head + claimed) % pool->capacity;
    pool->free_count -= claimed;
    set_aside_loaded(pool, z);
    reserve_near(pool);
    update_index(pool, scene, z);
    pool->last_boundary = scene->time;
    tb_contact_friction_stats *stats = &pool->stats;
    stats->boundaries++;
    stats->overflows += fresh - claimed;
    stats->in_use = pool->index_count;
    stats->peak_in_use = stats->in_use > stats->peak_in_use ? stats->in_use : stats->peak_in_use;
}

const tb_contact_friction_stats *tb__friction_stats(const tb__friction_pool *pool)
{
    return &pool->stats;
}

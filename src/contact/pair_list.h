/* Private: the broad phase's candidate pairs kept from one pass to the next with a skin (issue 23
 * item 7), so that RK4's four derivatives a step do not each sort and sweep again.
 *
 * A build grows each box by a skin (a share of its largest side, SKIN_SHARE in pair_list.c),
 * sweeps the grown boxes (broad_phase.h) and keeps the overlapping pairs in the canonical order:
 * by (first, second) box index. A later pass whose boxes each lie inside their grown boxes of the
 * build (the same count; for a build limited to the pairs with an active box, a limited pass
 * whose active boxes were all active then) finds its overlapping pairs among those candidates
 * (two boxes that meet have grown boxes that meet) and keeps those that meet now by the sweep's
 * own test (closed intervals on the three axes), with an active box when limited. Otherwise it
 * builds again. Either way a
 * pass gives exactly the pairs a sweep of its boxes gives, in the canonical order, so the pairs
 * and their order depend on the pass's boxes alone, never on the passes before it: the
 * derivative that reads them stays a pure function of (t, y).
 *
 * Nothing grows inside a pass: the list holds PAIRS_PER_BOX candidates a box (pair_list.c).
 * When the grown boxes make more, the build is made again without the skin (the pass's own
 * pairs, kept for a pass that does not move); when the pass's own pairs are more than that, it
 * gives them in the sweep's order, streamed from the broad phase as before the list. Which of
 * the two orders a pass gives depends on its own pairs' count alone. */
#ifndef TUMBLE_PAIR_LIST_H
#define TUMBLE_PAIR_LIST_H

#include "contact/broad_phase.h"

#include <stdint.h>

/* A kept pair: box indices, first < second (a list holds at most 2^32 boxes). */
typedef struct tb__list_pair {
    uint32_t first, second;
} tb__list_pair;

typedef struct tb__pair_list {
    /* the sweep; between builds its boxes are the grown boxes of the last build */
    tb__broad_phase broad;
    tb__aabb *bounds;            /* box capacity: the pass's boxes, filled by the caller */
    unsigned char *built_active; /* box capacity: broad.active at the last build */
    size_t pair_capacity;        /* PAIRS_PER_BOX a box, at least a few */
    tb__list_pair *pairs;        /* pair_capacity: the candidates, in canonical order */
    tb__list_pair *scratch;      /* pair_capacity: the canonical sort's buffer */
    size_t *counts;              /* box capacity + 1: the canonical sort's counts */
    size_t pair_count;           /* candidates kept */
    size_t built_count;          /* boxes at the last build */
    size_t next;                 /* the pass's next candidate */
    double share;                /* the next build's skin, a share of a box's largest side */
    bool built_limited;          /* the last build swept only the pairs with an active box */
    bool limited;                /* this pass gives only the pairs with an active box */
    bool valid;                  /* the candidates are the grown boxes' pairs */
    bool streaming;              /* this pass streams the sweep (more pairs than the list holds) */
    unsigned long long passes, builds; /* counts since init, read by the tests */
} tb__pair_list;

/* Allocates room for box_capacity boxes (at most 2^32; 0 is allowed) and their candidates; on
 * failure list is left empty and TB_STATUS_OUT_OF_MEMORY returned. */
tb_status tb__pair_list_init(tb__pair_list *list, size_t box_capacity);
void tb__pair_list_free(tb__pair_list *list);

/* The next pass builds again (the boxes were renumbered: shapes set or removed). */
void tb__pair_list_invalidate(tb__pair_list *list);

/* Starts a pass over bounds[0, count) and broad.active[0, count) (count <= box capacity), both
 * filled by the caller; limited: only the pairs with an active box (tb__broad_phase_sort_active),
 * else all. */
void tb__pair_list_begin(tb__pair_list *list, size_t count, bool limited);

/* Writes up to capacity of the pass's overlapping pairs (first < second) after the last ones and
 * returns how many; 0 when the pass is done. */
size_t tb__pair_list_next(tb__pair_list *list, tb__index_pair *out, size_t capacity);

#endif

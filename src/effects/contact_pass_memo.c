/* The contact pass a step boundary ran, kept for the derivative at the same (t, y)
 * (contact_pass_memo.h). */
#include "effects/contact_pass_memo.h"

#include "core/validate.h"
#include "scene/scene_internal.h"

#include <stdlib.h>
#include <string.h>

/* Room for this many pairs per body of the effect: a resting pile of boxes has about 3. */
#define TB__PASS_MEMO_PAIRS_PER_BODY 4

struct tb__pass_memo {
    tb__pair_contact *pairs;
    size_t count, capacity;
    double *states; /* the bodies' states the pass ran at: TB_STATE_SIZE slots doubles */
    size_t slots, states_capacity;
    double t;
    unsigned long long effects, layout, sleep; /* the scene's generations then */
    bool recording, kept;
};

tb__pass_memo *tb__pass_memo_create(size_t bodies, size_t slots)
{
    tb__pass_memo *memo = calloc(1, sizeof *memo);
    if (memo == NULL) {
        return NULL;
    }
    /* bodies, slots: at most what the scene's arrays hold, so the products fit */
    memo->capacity = TB__PASS_MEMO_PAIRS_PER_BODY * (bodies > 4 ? bodies : 4);
    memo->states_capacity = TB_STATE_SIZE * (slots > 0 ? slots : 1);
    memo->pairs = tb__malloc_array(memo->capacity, sizeof *memo->pairs);
    memo->states = tb__malloc_array(memo->states_capacity, sizeof *memo->states);
    if (memo->pairs == NULL || memo->states == NULL) {
        tb__pass_memo_destroy(memo);
        return NULL;
    }
    return memo;
}

void tb__pass_memo_destroy(tb__pass_memo *memo)
{
    if (memo != NULL) {
        free(memo->pairs);
        free(memo->states);
        free(memo);
    }
}

void tb__pass_memo_begin(tb__pass_memo *memo, const tb_scene *scene, double t, const double *y)
{
    memo->kept = false;
    memo->count = 0;
    memo->slots = scene->slot_count;
    /* bodies added since the memo was made: no room for their states, nothing kept */
    memo->recording = TB_STATE_SIZE * memo->slots <= memo->states_capacity;
    if (!memo->recording) {
        return;
    }
    memcpy(memo->states, y, TB_STATE_SIZE * memo->slots * sizeof(double));
    memo->t = t;
    memo->effects = scene->effects_generation;
    memo->layout = scene->layout_generation;
    memo->sleep = tb__scene_sleep_generation(scene);
}

void tb__pass_memo_add(tb__pass_memo *memo, const tb__pair_contact *pairs, size_t count)
{
    /* more pairs than room: the pass is not kept (nothing is allocated inside a step) */
    memo->recording = memo->recording && count <= memo->capacity - memo->count;
    if (memo->recording) {
        memcpy(memo->pairs + memo->count, pairs, count * sizeof(tb__pair_contact));
        memo->count += count;
    }
}

void tb__pass_memo_end(tb__pass_memo *memo)
{
    memo->kept = memo->recording;
    memo->recording = false;
}

bool tb__pass_memo_at(const tb__pass_memo *memo, const tb_scene *scene, double t, const double *y,
                      const tb__pair_contact **pairs, size_t *count)
{
    /* the generations first: a changed scene is told by them, not by the states */
    const bool same =
        memo != NULL && memo->kept && t == memo->t && memo->slots == scene->slot_count &&
        memo->effects == scene->effects_generation && memo->layout == scene->layout_generation &&
        memo->sleep == tb__scene_sleep_generation(scene) &&
        (memo->slots == 0 ||
         memcmp(memo->states, y, TB_STATE_SIZE * memo->slots * sizeof(double)) == 0);
    *pairs = same ? memo->pairs : NULL;
    *count = same ? memo->count : 0;
    return same;
}

/* Private: the contact pass a step boundary ran (the friction slots' update, at the state the
 * next step starts from), kept so that the derivative at the same (t, y) hands its pairs to the
 * law instead of running the broad and narrow phase again (contact_pass_memo.c). A pass reads
 * only t, the bodies' states in y, their shapes and kinds and the asleep set (contact_pairs.h),
 * so a pass at the same t, the same bits of those states, the same effects and layout
 * generations (a shape, a motion source, a body added) and the same sleep generation lists the
 * same pairs in the same order: the derivative stays a pure function of (t, y), bit for bit. */
#ifndef TUMBLE_CONTACT_PASS_MEMO_H
#define TUMBLE_CONTACT_PASS_MEMO_H

#include "contact/contact_pairs.h"

typedef struct tb__pass_memo tb__pass_memo;

/* An empty memo with room for a pass over `bodies` bodies in a scene of `slots` dynamic ones
 * (NULL: out of memory). Its memory is all allocated here: a pass with more pairs than its room
 * (4 per body), or in a scene with bodies added since, is not kept (the derivative runs it). */
tb__pass_memo *tb__pass_memo_create(size_t bodies, size_t slots);
void tb__pass_memo_destroy(tb__pass_memo *memo);

/* Recording a pass at (t, y): begin forgets the last one, add keeps a batch of its pairs, end
 * makes it the memo's. */
void tb__pass_memo_begin(tb__pass_memo *memo, const tb_scene *scene, double t, const double *y);
void tb__pass_memo_add(tb__pass_memo *memo, const tb__pair_contact *pairs, size_t count);
void tb__pass_memo_end(tb__pass_memo *memo);

/* Whether the recorded pass ran at this t, these bits of the bodies' states in y and the
 * scene's generations now; then its pairs (*count of them, in the pass's order). */
bool tb__pass_memo_at(const tb__pass_memo *memo, const tb_scene *scene, double t, const double *y,
                      const tb__pair_contact **pairs, size_t *count);

#endif

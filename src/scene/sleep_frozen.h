/* Private: what asleep bodies cost a derivative (sleep.c). An asleep body whose state in y is,
 * bit for bit, the one it fell asleep with (its snapshot) is frozen: whatever depends on its
 * state alone (its motion, its shape's pose and bounds) is what an earlier evaluation found,
 * and may be kept instead of computed again. Integrators leave an asleep body's state as it is
 * (its derivative is 0); a derivative at another y (a difference quotient's column, a user's
 * call) finds the body not frozen and computes it, so the derivative stays a pure function of
 * (t, y). */
#ifndef TUMBLE_SLEEP_FROZEN_H
#define TUMBLE_SLEEP_FROZEN_H

#include "scene/scene_internal.h"

#include <stdint.h>
#include <string.h>

/* Whether body id is asleep with its snapshot's state in y, bit for bit (a -0 for a 0 is a
 * change: the motion made from it could differ in a zero's sign); compared inline, word by
 * word, for it runs per asleep body per derivative. */
static inline bool tb__body_frozen(const tb_scene *scene, const double *y, size_t id)
{
    if (!tb__body_asleep(scene, id)) {
        return false;
    }
    const double *s = tb__body_state(scene, y, id),
                 *kept = scene->sleep->snapshot + TB_STATE_SIZE * id;
    uint64_t difference = 0;
    for (int k = 0; k < TB_STATE_SIZE; ++k) {
        uint64_t a, b;
        memcpy(&a, s + k, sizeof a);
        memcpy(&b, kept + k, sizeof b);
        difference |= a ^ b;
    }
    return difference == 0;
}

#endif

/* Private: uniform gravity's parameters (effect_loads.c), read by its file and its lane form
 * (effect_lanes.c). */
#ifndef TUMBLE_EFFECT_LOADS_H
#define TUMBLE_EFFECT_LOADS_H

#include "scene/scene_internal.h"

typedef struct tb__gravity_params {
    double g[3]; /* m/s^2, world */
} tb__gravity_params;

/* A gravity effect's parameters. */
static inline const tb__gravity_params *tb__gravity_of(const tb__effect *effect)
{
    return effect->params;
}

#endif

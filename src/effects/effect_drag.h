/* Private: drag's parameters (effect_drag.c), read by its file and its lane form
 * (effect_lanes.c). */
#ifndef TUMBLE_EFFECT_DRAG_H
#define TUMBLE_EFFECT_DRAG_H

#include "scene/scene_internal.h"

typedef struct tb__drag_params {
    double linear, quadratic, angular, angular_quadratic; /* see tb_drag_def */
} tb__drag_params;

#endif

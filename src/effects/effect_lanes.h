/* Private: the lane forms (scene/lanes.h) of gravity and drag, compiled once per vector path
 * (effect_lanes.c, TB__LANES_NAME); each kind's row gathers its forms for every path:
 * {TB__EFFECT_LANES(tb__drag_lanes)}. */
#ifndef TUMBLE_EFFECT_LANES_H
#define TUMBLE_EFFECT_LANES_H

#include "scene/lanes.h"

void tb__gravity_lanes_baseline(const tb__effect *effect, const tb__lanes *lanes);
void tb__drag_lanes_baseline(const tb__effect *effect, const tb__lanes *lanes);
#ifdef TB__LANES_X86
void tb__gravity_lanes_avx2(const tb__effect *effect, const tb__lanes *lanes);
void tb__gravity_lanes_avx512(const tb__effect *effect, const tb__lanes *lanes);
void tb__drag_lanes_avx2(const tb__effect *effect, const tb__lanes *lanes);
void tb__drag_lanes_avx512(const tb__effect *effect, const tb__lanes *lanes);
#define TB__EFFECT_LANES(form) form##_baseline, form##_avx2, form##_avx512
#else
#define TB__EFFECT_LANES(form) form##_baseline, NULL, NULL
#endif

#endif

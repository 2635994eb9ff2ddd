/* What the MuJoCo peers (bench_peer, bench_peer_contact) share: MuJoCo's header and a model
 * compiled from XML. Only with TUMBLE_BENCH_MUJOCO (bench/CMakeLists.txt, scripts/bench.sh). */
#ifndef TUMBLE_BENCH_MUJOCO_H
#define TUMBLE_BENCH_MUJOCO_H

#ifdef TUMBLE_BENCH_MUJOCO
#include <mujoco/mujoco.h>

#include <stdio.h>

/* A model from XML, or NULL with the reason on stderr after the benchmark's name. */
static inline mjModel *bench_mujoco_model(const char *benchmark, const char *xml)
{
    char error[1000] = "";
    mjSpec *spec = mj_parseXMLString(xml, NULL, error, sizeof error);
    mjModel *model = spec != NULL ? mj_compile(spec, NULL) : NULL;
    if (model == NULL) {
        fprintf(stderr, "%s: MuJoCo refused the model: %s\n", benchmark,
                spec != NULL ? mjs_getError(spec) : error);
    }
    mj_deleteSpec(spec);
    return model;
}
#endif

#endif

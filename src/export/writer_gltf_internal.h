/* Private: building a glTF document (jansson objects and one binary buffer). Only the
 * writer_gltf*.c sources include it, so jansson stays inside src/io. */
#ifndef TUMBLE_WRITER_GLTF_INTERNAL_H
#define TUMBLE_WRITER_GLTF_INTERNAL_H

#include "export/writer_internal.h"

#include <jansson.h>

typedef struct tb__gltf {
    json_t *nodes, *meshes, *materials, *animations, *accessors, *views;
    unsigned char *buffer; /* the binary chunk, its views 4-byte aligned */
    size_t size, capacity;
    bool failed; /* out of memory on the way */
} tb__gltf;

/* What an accessor holds: float scalars, vectors and unsigned 32-bit indices. */
typedef enum tb__gltf_type {
    TB__GLTF_SCALAR,
    TB__GLTF_VEC3,
    TB__GLTF_VEC4,
    TB__GLTF_INDEX
} tb__gltf_type;

/* What a buffer view is for: vertex attributes, triangle indices, or animation data. */
typedef enum tb__gltf_use { TB__GLTF_VERTICES, TB__GLTF_INDICES, TB__GLTF_ANIMATION } tb__gltf_use;

void tb__gltf_init(tb__gltf *g);
void tb__gltf_free(tb__gltf *g);

/* Copies count elements of data (float, or uint32_t for TB__GLTF_INDEX) into the buffer as a
 * view of its own and adds an accessor; min and max (may be NULL) as glTF wants them for
 * positions and animation inputs. Returns the accessor's index. */
long tb__gltf_accessor(tb__gltf *g, const void *data, size_t count, tb__gltf_type type,
                       tb__gltf_use use, const double *min, const double *max);

/* The animation of every body from the writer's frames (none for fewer than two frames: a
 * single frame is a still, which the nodes' own pose shows). */
void tb__gltf_add_animation(tb__gltf *g, const tb_writer *w);

/* The document into the writer's file. */
tb_status tb__gltf_write_glb(tb__gltf *g, json_t *root, tb_writer *w);
tb_status tb__gltf_write_text(tb__gltf *g, json_t *root, tb_writer *w);

/* The writer's contact events as scenes[0].extras.tumble_events (writer_gltf_events.c); NULL
 * when there are none, or no memory (*failed set then). */
json_t *tb__events_json(const tb_writer *writer, bool *failed);

#endif

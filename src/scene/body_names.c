/* Body names by hash, so finding a name (and checking a new one is unique) costs the same at
 * any number of bodies: open addressing with linear probing over a power-of-two table kept at
 * most half full, slots holding body id + 1 (0 for an empty slot). */
#include "scene/scene_internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* FNV-1a, 64 bits: a byte-wise hash with good spread on short, similar strings (body1,
 * body2, ...). */
static uint64_t name_hash(const char *name)
{
    uint64_t hash = 14695981039346656037ULL;
    for (const unsigned char *c = (const unsigned char *)name; *c != '\0'; ++c) {
        hash = (hash ^ *c) * 1099511628211ULL;
    }
    return hash;
}

/* Puts body id in the first free slot of its probe sequence. */
static void place(size_t *slots, size_t slot_count, const char *name, size_t id)
{
    size_t k = (size_t)name_hash(name) & (slot_count - 1);
    while (slots[k] != 0) {
        k = (k + 1) & (slot_count - 1);
    }
    slots[k] = id + 1;
}

tb_status tb__scene_reserve_names(tb_scene *scene, size_t body_count)
{
    size_t slot_count = scene->name_slot_count > 0 ? scene->name_slot_count : 16;
    while (slot_count < 2 * body_count) {
        if (slot_count > SIZE_MAX / (4 * sizeof(size_t))) {
            return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "name table for %zu bodies",
                                  body_count);
        }
        slot_count *= 2;
    }
    if (slot_count == scene->name_slot_count) {
        return TB_STATUS_OK;
    }
    size_t *slots = calloc(slot_count, sizeof *slots);
    if (slots == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "name table of %zu slots",
                              slot_count);
    }
    for (size_t i = 0; i < scene->body_count; ++i) {
        place(slots, slot_count, scene->names[i], i);
    }
    free(scene->name_slots);
    scene->name_slots = slots;
    scene->name_slot_count = slot_count;
    return TB_STATUS_OK;
}

void tb__scene_insert_name(tb_scene *scene, size_t id)
{
    place(scene->name_slots, scene->name_slot_count, scene->names[id], id);
}

bool tb__scene_lookup_name(const tb_scene *scene, const char *name, size_t *out_id)
{
    if (scene->name_slot_count == 0) {
        return false;
    }
    const size_t mask = scene->name_slot_count - 1;
    for (size_t k = (size_t)name_hash(name) & mask; scene->name_slots[k] != 0; k = (k + 1) & mask) {
        const size_t id = scene->name_slots[k] - 1;
        if (strcmp(scene->names[id], name) == 0) {
            *out_id = id;
            return true;
        }
    }
    return false;
}

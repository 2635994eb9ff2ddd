/* Writers: USD prim names for the bodies and ground planes. A prim name is an identifier,
 * [A-Za-z_][A-Za-z0-9_]*, unique among its siblings: other bytes become '_', a name that starts
 * with a digit (or is empty) gets a '_' in front, and a name taken already gets the first free
 * suffix _2, _3, ... (names taken are kept in a hash set, so this costs the same at any number of
 * bodies). The body's own name stays in its prim's customData. */
#include "export/writer_internal.h"

#include <ctype.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct name_set {
    const char (*names)[TB__USD_NAME_SIZE];
    size_t *slots; /* name index + 1, 0 for an empty slot */
    size_t slot_count;
} name_set;

/* FNV-1a, 64 bits. */
static uint64_t name_hash(const char *name)
{
    uint64_t hash = 14695981039346656037ULL;
    for (const unsigned char *c = (const unsigned char *)name; *c != '\0'; ++c) {
        hash = (hash ^ *c) * 1099511628211ULL;
    }
    return hash;
}

/* Whether candidate is taken; if not, and index is given, it is taken now as names[index]. */
static bool taken(name_set *set, const char *candidate, size_t index, bool take)
{
    size_t k = (size_t)name_hash(candidate) & (set->slot_count - 1);
    for (; set->slots[k] != 0; k = (k + 1) & (set->slot_count - 1)) {
        if (strcmp(set->names[set->slots[k] - 1], candidate) == 0) {
            return true;
        }
    }
    if (take) {
        set->slots[k] = index + 1;
    }
    return false;
}

/* source as an identifier, with room left for a suffix. */
static void identifier(char *out, const char *source)
{
    size_t n = 0;
    const unsigned char first = (unsigned char)source[0];
    if (!(first < 0x80 && isalpha(first)) && first != '_') {
        out[n++] = '_';
    }
    for (const char *c = source; *c != '\0' && n < TB_NAME_SIZE; ++c) {
        const unsigned char byte = (unsigned char)*c;
        const bool keep = byte == '_' || (byte < 0x80 && isalnum(byte));
        out[n++] = keep ? *c : '_';
    }
    out[n] = '\0';
}

/* out = base "_" suffix. identifier() leaves base at most TB_NAME_SIZE bytes, and the suffix
 * takes at most 21 of the 24 bytes kept for it; were base longer, its end would give way, never
 * the suffix (whose loss would make every candidate the same name). Written without snprintf,
 * whose truncation gcc cannot rule out here (-Wformat-truncation in the Debug build). */
static void suffixed(char *out, const char *base, size_t suffix)
{
    char tail[24];
    const size_t tail_length = (size_t)snprintf(tail, sizeof tail, "_%zu", suffix);
    size_t keep = strlen(base);
    if (keep > TB__USD_NAME_SIZE - 1 - tail_length) {
        keep = TB__USD_NAME_SIZE - 1 - tail_length;
    }
    memmove(out, base, keep);
    memcpy(out + keep, tail, tail_length + 1);
}

tb_status tb__usd_names(const char *const *sources, size_t count, char (*out)[TB__USD_NAME_SIZE])
{
    name_set set = {.names = (const char(*)[TB__USD_NAME_SIZE])out, .slot_count = 16};
    while (set.slot_count < 2 * count) {
        if (set.slot_count > SIZE_MAX / (4 * sizeof(size_t))) {
            return TB_STATUS_OUT_OF_MEMORY;
        }
        set.slot_count *= 2;
    }
    set.slots = calloc(set.slot_count, sizeof *set.slots);
    if (set.slots == NULL) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    for (size_t k = 0; k < count; ++k) {
        char base[TB__USD_NAME_SIZE];
        identifier(base, sources[k]);
        snprintf(out[k], TB__USD_NAME_SIZE, "%s", base);
        /* count names are taken, so one of the suffixes up to count + 1 is free */
        for (size_t suffix = 2; taken(&set, out[k], k, true); ++suffix) {
            suffixed(out[k], base, suffix);
        }
    }
    free(set.slots);
    return TB_STATUS_OK;
}

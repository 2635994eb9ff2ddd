/* Contact events in written files (tb_writer_set_contact_events): glTF keeps them in the
 * scene's extras, where an animation tool's script finds them beside the animation. */
#include "export/writer_gltf_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <stdlib.h>
#include <string.h>

tb_status tb_writer_set_contact_events(tb_writer *writer, const tb_contact_event *events,
                                       size_t count)
{
    if (writer == NULL || (events == NULL && count > 0)) {
        return writer == NULL ? TB_STATUS_NULL_POINTER
                              : tb__set_detail(writer->detail, TB_STATUS_NULL_POINTER,
                                               "events: is NULL, count %zu", count);
    }
    writer->detail[0] = '\0';
    if (writer->format != TB_OUTPUT_GLB && writer->format != TB_OUTPUT_GLTF) {
        return tb__set_detail(writer->detail, TB_STATUS_INVALID_ARGUMENT,
                              "%s: %s files have no place for contact events (glb, gltf have)",
                              writer->path, tb_output_format_name(writer->format));
    }
    for (size_t k = 0; k < count; ++k) {
        const size_t ids[2] = {events[k].body_a, events[k].body_b};
        for (int i = 0; i < 2; ++i) {
            if (ids[i] >= writer->body_count && !(i == 1 && ids[i] == TB_WORLD)) {
                return tb__set_detail(writer->detail, TB_STATUS_INVALID_ARGUMENT,
                                      "events[%zu].body_%c: %zu, the writer has %zu bodies", k,
                                      i == 0 ? 'a' : 'b', ids[i], writer->body_count);
            }
        }
    }
    tb_contact_event *copy = count > 0 ? tb__malloc_array(count, sizeof *copy) : NULL;
    if (count > 0 && copy == NULL) {
        return tb__set_detail(writer->detail, TB_STATUS_OUT_OF_MEMORY, "%zu contact events", count);
    }
    if (count > 0) {
        memcpy(copy, events, count * sizeof *copy);
    }
    free(writer->events);
    writer->events = copy;
    writer->event_count = count;
    return TB_STATUS_OK;
}

static json_t *numbers(const double *v, size_t n)
{
    json_t *array = json_array();
    for (size_t k = 0; k < n; ++k) {
        json_array_append_new(array, json_real(v[k]));
    }
    return array;
}

static const char *name_of(const tb_writer *w, size_t id)
{
    return id == TB_WORLD ? "ground" : w->names[id];
}

json_t *tb__events_json(const tb_writer *w, bool *failed)
{
    if (w->event_count == 0) {
        return NULL;
    }
    json_t *array = json_array();
    for (size_t k = 0; k < w->event_count && array != NULL; ++k) {
        const tb_contact_event *e = &w->events[k];
        json_t *object =
            json_pack("{s:f, s:s, s:s, s:s, s:o, s:o, s:f, s:f}", "t", e->t, "kind",
                      tb_contact_event_kind_name(e->kind), "body_a", name_of(w, e->body_a),
                      "body_b", name_of(w, e->body_b), "point", numbers(e->point, 3), "normal",
                      numbers(e->normal, 3), "speed", e->speed, "impulse", e->impulse);
        if (object == NULL || json_array_append_new(array, object) != 0) {
            json_decref(array);
            array = NULL;
        }
    }
    *failed |= array == NULL;
    return array;
}

/* tumble run --events FILE: the scene's contact events (include/tumble/contact_events.h) kept
 * during the run and written at its end as CSV or JSON, by the file's extension. */
#ifndef TUMBLE_CLI_EVENTS_H
#define TUMBLE_CLI_EVENTS_H

#include "output.h"

#include "tumble/tumble.h"

#include <stdbool.h>
#include <stddef.h>

typedef struct cli_events {
    cli_output output;
    bool json;
    tb_contact_event *events; /* count of them, room for capacity */
    size_t count, capacity;
    bool out_of_memory; /* an event could not be kept */
} cli_events;

/* Opens path (.csv or .json, any case; another extension is refused, as is the scene file)
 * and starts the scene's events into it. False with a message on refusal. */
bool cli_events_open(cli_events *e, const char *path, const char *scene_path, tb_scene *scene,
                     double hit_speed, char *message, size_t size);

/* Writes the events kept (one row or object each, body names from scene) and closes the file;
 * ok false: the run failed, the file is removed. False with a message if a write failed or an
 * event was lost. */
bool cli_events_close(cli_events *e, const tb_scene *scene, bool ok, char *message, size_t size);

#endif

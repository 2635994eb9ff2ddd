/* tumble run --events FILE: contact events kept in memory during the run (the callback only
 * appends) and written at its end, so that a failed write is found and reported once. */
#define _POSIX_C_SOURCE 200809L /* strcasecmp */
#include "events.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static void keep(const tb_contact_event *event, void *ctx)
{
    cli_events *e = ctx;
    if (e->count == e->capacity) {
        const size_t capacity = e->capacity == 0 ? 256 : 2 * e->capacity;
        tb_contact_event *grown = capacity > e->capacity && capacity < (size_t)-1 / sizeof *grown
                                      ? realloc(e->events, capacity * sizeof *grown)
                                      : NULL;
        if (grown == NULL) {
            e->out_of_memory = true;
            return;
        }
        e->events = grown;
        e->capacity = capacity;
    }
    e->events[e->count++] = *event;
}

/* The extension of path's last component, or "". */
static const char *extension(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot != NULL && (slash == NULL || dot > slash) ? dot + 1 : "";
}

bool cli_events_open(cli_events *e, const char *path, const char *scene_path, tb_scene *scene,
                     double hit_speed, char *message, size_t size)
{
    *e = (cli_events){.json = strcasecmp(extension(path), "json") == 0};
    if (!e->json && strcasecmp(extension(path), "csv") != 0) {
        snprintf(message, size, "--events %s: must end in .csv or .json", path);
        return false;
    }
    size_t named = 0; /* the rows name a ground plane "ground": a body so named would be it */
    if (tb_scene_ground_count(scene) > 0 &&
        tb_scene_find_body(scene, "ground", &named) == TB_STATUS_OK) {
        snprintf(message, size,
                 "--events %s: body %zu is named \"ground\", the name the events give a ground "
                 "plane, and the scene has a ground plane: rename the body",
                 path, named);
        return false;
    }
    if (!cli_output_open(&e->output, path, scene_path, message, size)) {
        return false;
    }
    tb_contact_events_def def = tb_contact_events_def_default();
    def.fn = keep;
    def.ctx = e;
    def.hit_threshold = hit_speed;
    if (tb_scene_set_contact_events(scene, &def) != TB_STATUS_OK) {
        snprintf(message, size, "--events %s: %s", path, tb_scene_detail(scene));
        cli_events_close(e, scene, false, message, size);
        return false;
    }
    return true;
}

static const char *name_of(const tb_scene *scene, size_t id)
{
    return id == TB_WORLD ? "ground" : tb_scene_body_name(scene, id);
}

static void write_csv(cli_events *e, const tb_scene *scene)
{
    cli_output *out = &e->output;
    cli_output_printf(out, "t,kind,body_a,body_b,x,y,z,nx,ny,nz,speed,impulse\n");
    for (size_t k = 0; k < e->count; ++k) {
        const tb_contact_event *v = &e->events[k];
        cli_output_printf(out, "%.17g,%s,", v->t, tb_contact_event_kind_name(v->kind));
        cli_output_csv_field(out, name_of(scene, v->body_a));
        cli_output_printf(out, ",");
        cli_output_csv_field(out, name_of(scene, v->body_b));
        cli_output_printf(out, ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", v->point[0],
                          v->point[1], v->point[2], v->normal[0], v->normal[1], v->normal[2],
                          v->speed, v->impulse);
    }
}

/* A JSON string: quotes, backslashes and control characters escaped. */
static void json_string(cli_output *out, const char *text)
{
    cli_output_printf(out, "\"");
    for (const unsigned char *c = (const unsigned char *)text; *c != '\0'; ++c) {
        if (*c == '"' || *c == '\\') {
            cli_output_printf(out, "\\%c", *c);
        } else if (*c < 0x20) {
            cli_output_printf(out, "\\u%04x", *c);
        } else {
            cli_output_printf(out, "%c", *c);
        }
    }
    cli_output_printf(out, "\"");
}

static void write_json(cli_events *e, const tb_scene *scene)
{
    cli_output *out = &e->output;
    cli_output_printf(out, "[");
    for (size_t k = 0; k < e->count; ++k) {
        const tb_contact_event *v = &e->events[k];
        cli_output_printf(out,
                          "%s\n  {\"t\": %.17g, \"kind\": \"%s\", \"body_a\": ", k == 0 ? "" : ",",
                          v->t, tb_contact_event_kind_name(v->kind));
        json_string(out, name_of(scene, v->body_a));
        cli_output_printf(out, ", \"body_b\": ");
        json_string(out, name_of(scene, v->body_b));
        cli_output_printf(out,
                          ", \"point\": [%.17g, %.17g, %.17g], \"normal\": [%.17g, %.17g, %.17g], "
                          "\"speed\": %.17g, \"impulse\": %.17g}",
                          v->point[0], v->point[1], v->point[2], v->normal[0], v->normal[1],
                          v->normal[2], v->speed, v->impulse);
    }
    cli_output_printf(out, "\n]\n");
}

bool cli_events_close(cli_events *e, const tb_scene *scene, bool ok, char *message, size_t size)
{
    size_t dropped = 0;
    const bool whole = tb_scene_contact_events_status(scene, &dropped) == TB_STATUS_OK;
    if (ok) {
        (e->json ? write_json : write_csv)(e, scene);
    }
    const bool written = cli_output_close(&e->output, message, size);
    free(e->events);
    e->events = NULL;
    if (written && ok && (e->out_of_memory || !whole)) {
        snprintf(message, size, "--events %s: out of memory: %s", e->output.name,
                 e->out_of_memory ? "events could not be kept" : tb_scene_detail(scene));
    }
    if (!ok || !written || e->out_of_memory || !whole) {
        cli_output_remove_partial(e->output.name);
        return !ok; /* a failed run is reported as such; a failed write here */
    }
    return true;
}

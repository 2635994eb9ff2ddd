/* Output files whose every write is checked: a full disk, /dev/full or a closed standard
 * output is a failure with its reason, never a success with the frames lost. */
#ifndef TUMBLE_CLI_OUTPUT_H
#define TUMBLE_CLI_OUTPUT_H

#include <stdbool.h>
#include <stdio.h>

typedef struct cli_output {
    FILE *stream;
    const char *name; /* for messages: the path, or "standard output" */
    int error;        /* errno of the first failed write, flush or close; 0 if none */
} cli_output;

/* Call first thing in main: if standard output is closed, holds its descriptor with /dev/null
 * opened read-only, so that no file opened later lands there and writes still fail. */
void cli_output_guard_stdout(void);

/* True if a and b name the same existing file (same device and inode). */
bool cli_output_same_file(const char *a, const char *b);

/* Opens path for writing (NULL: standard output). Refuses (false, message) a path that is
 * the file `keep` (the scene: same device and inode, whatever the spelling) and a path that
 * cannot be opened. */
bool cli_output_open(cli_output *out, const char *path, const char *keep, char *message,
                     size_t size);

/* printf to the output; a failure is remembered in out->error (later writes are skipped). */
void cli_output_printf(cli_output *out, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* One CSV field per RFC 4180: quoted, with quotes doubled, if it holds a comma, a quote or a
 * line break; as it is otherwise. */
void cli_output_csv_field(cli_output *out, const char *text);

/* Flushes and closes (standard output: flushes only; main closes it). True if every write
 * succeeded; otherwise message says which output and why (strerror). */
bool cli_output_close(cli_output *out, char *message, size_t size);

/* Removes path if it is a regular file (a partly written output); never a device such as
 * /dev/full, a pipe or a directory (the command may run as root). NULL is ignored. */
void cli_output_remove_partial(const char *path);

/* Closes standard output at exit; false with message if that fails (main's last check). */
bool cli_output_close_stdout(char *message, size_t size);

#endif

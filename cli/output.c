/* Checked output: every write, the final flush and the close. */
#define _POSIX_C_SOURCE 200809L /* fcntl, stat, open */
#include "output.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void cli_output_guard_stdout(void)
{
    if (fcntl(STDOUT_FILENO, F_GETFD) == -1 && errno == EBADF) {
        /* open() returns the lowest free descriptor, which is 1 here; read-only, so that a
         * write to standard output still fails (EBADF) as it would on the closed one */
        (void)open("/dev/null", O_RDONLY);
    }
}

bool cli_output_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    return a != NULL && b != NULL && stat(a, &sa) == 0 && stat(b, &sb) == 0 &&
           sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

bool cli_output_open(cli_output *out, const char *path, const char *keep, char *message,
                     size_t size)
{
    *out = (cli_output){.stream = stdout, .name = "standard output", .error = 0};
    if (path == NULL) {
        return true;
    }
    if (cli_output_same_file(path, keep)) {
        snprintf(message, size, "%s is the scene file %s: refusing to overwrite it", path, keep);
        return false;
    }
    out->name = path;
    out->stream = fopen(path, "w");
    if (out->stream == NULL) {
        snprintf(message, size, "%s: cannot open for writing: %s", path, strerror(errno));
        return false;
    }
    return true;
}

void cli_output_printf(cli_output *out, const char *format, ...)
{
    if (out->error != 0) {
        return;
    }
    va_list args;
    va_start(args, format);
    errno = 0;
    if (vfprintf(out->stream, format, args) < 0) {
        out->error = errno != 0 ? errno : EIO;
    }
    va_end(args);
}

void cli_output_csv_field(cli_output *out, const char *text)
{
    if (strpbrk(text, ",\"\r\n") == NULL) {
        cli_output_printf(out, "%s", text);
        return;
    }
    cli_output_printf(out, "\"");
    for (const char *c = text; *c != '\0'; ++c) {
        if (*c == '"') {
            cli_output_printf(out, "\"\"");
        } else {
            cli_output_printf(out, "%c", *c);
        }
    }
    cli_output_printf(out, "\"");
}

bool cli_output_close(cli_output *out, char *message, size_t size)
{
    if (fflush(out->stream) != 0 && out->error == 0) {
        out->error = errno;
    }
    if (ferror(out->stream) && out->error == 0) {
        out->error = EIO;
    }
    if (out->stream != stdout && fclose(out->stream) != 0 && out->error == 0) {
        out->error = errno;
    }
    out->stream = NULL;
    if (out->error != 0) {
        snprintf(message, size, "writing %s failed: %s", out->name, strerror(out->error));
        return false;
    }
    return true;
}

bool cli_output_close_stdout(char *message, size_t size)
{
    const bool failed = fflush(stdout) != 0 || ferror(stdout);
    const int reason = errno;
    if (fclose(stdout) != 0 || failed) {
        snprintf(message, size, "writing standard output failed: %s",
                 strerror(failed ? reason : errno));
        return false;
    }
    return true;
}

void cli_output_remove_partial(const char *path)
{
    struct stat info;
    if (path != NULL && stat(path, &info) == 0 && S_ISREG(info.st_mode)) {
        remove(path);
    }
}

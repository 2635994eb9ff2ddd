/* Writers: CSV text, a row per body per frame. Numbers are printed with 17 significant
 * digits, which read back (strtod, NumPy, pandas) as exactly the double that was printed. */
#include "export/writer_internal.h"

#include <errno.h>
#include <string.h>

tb_status tb__csv_header(tb_writer *writer)
{
    errno = 0;
    if (fputs("t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n", writer->file) == EOF) {
        return tb__writer_io_failure(writer, "write failed");
    }
    return TB_STATUS_OK;
}

/* A body name as one CSV field (RFC 4180): quoted, quotes doubled, when it holds a comma, a
 * quote or a line break. */
static void name_field(FILE *file, const char *name)
{
    if (strpbrk(name, ",\"\r\n") == NULL) {
        fputs(name, file);
        return;
    }
    fputc('"', file);
    for (const char *c = name; *c != '\0'; ++c) {
        if (*c == '"') {
            fputc('"', file);
        }
        fputc(*c, file);
    }
    fputc('"', file);
}

tb_status tb__csv_frame(tb_writer *writer, double t, const double *values)
{
    errno = 0;
    for (size_t id = 0; id < writer->body_count; ++id) {
        const double *s = values + 13 * id;
        fprintf(writer->file, "%.17g,", t);
        name_field(writer->file, writer->names[id]);
        fprintf(writer->file,
                ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], s[8], s[9], s[10], s[11], s[12]);
    }
    /* a full disk shows as the stream's error flag, checked once a frame */
    return ferror(writer->file) ? tb__writer_io_failure(writer, "write failed") : TB_STATUS_OK;
}

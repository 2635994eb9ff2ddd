/* Writers: CSV text, a row per body per frame. Numbers are printed with 17 significant
 * digits, which read back (strtod, NumPy, pandas) as exactly the double that was printed. */
#include "io/writer_internal.h"

#include <errno.h>

tb_status tb__csv_header(tb_writer *writer)
{
    errno = 0;
    if (fputs("t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n", writer->file) == EOF) {
        return tb__writer_io_failure(writer, "write failed");
    }
    return TB_STATUS_OK;
}

tb_status tb__csv_frame(tb_writer *writer, double t, const tb_scene *scene)
{
    errno = 0;
    for (size_t id = 0; id < writer->body_count; ++id) {
        double s[13];
        tb__writer_readout(scene, id, s);
        fprintf(writer->file,
                "%.17g,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                "%.17g\n",
                t, writer->names[id], s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], s[8], s[9],
                s[10], s[11], s[12]);
    }
    /* a full disk shows as the stream's error flag, checked once a frame */
    return ferror(writer->file) ? tb__writer_io_failure(writer, "write failed") : TB_STATUS_OK;
}

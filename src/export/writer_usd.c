/* Writers: USD ASCII layers (.usda), the text form of USD that usd-core, usdview, Houdini and
 * Omniverse read. The stage is z up in metres, one time code a frame (timeCodesPerSecond = fps),
 * its default prim "world" an Xform holding one Xform a body, named after the body, whose
 * xformOp:translate (double3) and xformOp:orient (quatd, real part first) are the shape frame's
 * pose at every frame (writer_usd_samples.c), as the CSV's x..z and qw..qz. The body's shape is
 * its child "shape": a Cube (size 1, scaled to the box's edges), Sphere, Capsule or Cylinder
 * (axis Z; height the length between the caps' centres, as tumble's), an ellipsoid as a Sphere
 * of radius 1 scaled to its semi-axes, a mesh as a Mesh of its own vertices and triangles, and
 * what has no USD primitive (points, a body given by its inertia) as a Mesh of the glTF
 * writer's tessellation. Ground planes are square Meshes, as in glTF. */
#include "export/writer_internal.h"

#include "core/detail.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A string literal: quotes, backslashes and control bytes escaped. */
static void put_string(FILE *file, const char *text)
{
    fputc('"', file);
    for (const unsigned char *c = (const unsigned char *)text; *c != '\0'; ++c) {
        if (*c == '"' || *c == '\\') {
            fprintf(file, "\\%c", *c);
        } else if (*c < 0x20 || *c == 0x7f) {
            fprintf(file, "\\x%02x", *c);
        } else {
            fputc(*c, file);
        }
    }
    fputc('"', file);
}

static void put_header(const tb_writer *w)
{
    const tb__frames *f = &w->frames;
    const double start = f->count > 0 ? tb__usd_time_code(f->t[0], w->fps) : 0.0;
    const double end = f->count > 0 ? tb__usd_time_code(f->t[f->count - 1], w->fps) : 0.0;
    fprintf(w->file,
            "#usda 1.0\n(\n    defaultPrim = \"world\"\n"
            "    doc = \"tumble %s: bodies %zu, frames %zu; tumble's world is z up, SI units\"\n"
            "    endTimeCode = %.17g\n    framesPerSecond = %.17g\n    kilogramsPerUnit = 1\n"
            "    metersPerUnit = 1\n"
            "    startTimeCode = %.17g\n    timeCodesPerSecond = %.17g\n    upAxis = \"Z\"\n)\n\n"
            "def Xform \"world\"\n{\n",
            tb_version(), w->body_count, f->count, end, w->fps, start, w->fps);
}

static void put_extent(FILE *file, const double low[3], const double high[3])
{
    fprintf(file, "            float3[] extent = [(%.9g, %.9g, %.9g), (%.9g, %.9g, %.9g)]\n",
            low[0], low[1], low[2], high[0], high[1], high[2]);
}

/* Cube, Sphere (also an ellipsoid, scaled), Capsule, Cylinder. */
static void put_primitive(FILE *file, const tb__shape *s)
{
    static const char *const kinds[] = {[TB__SHAPE_BOX] = "Cube",
                                        [TB__SHAPE_SPHERE] = "Sphere",
                                        [TB__SHAPE_ELLIPSOID] = "Sphere",
                                        [TB__SHAPE_CYLINDER] = "Cylinder",
                                        [TB__SHAPE_CAPSULE] = "Capsule"};
    fprintf(file, "        def %s \"shape\"\n        {\n", kinds[s->kind]);
    const double r = s->size[0], h = s->size[1];
    if (s->kind == TB__SHAPE_BOX || s->kind == TB__SHAPE_ELLIPSOID) {
        const bool box = s->kind == TB__SHAPE_BOX;
        const double a = box ? 0.5 : 1.0;
        fprintf(file, box ? "            double size = 1\n" : "            double radius = 1\n");
        put_extent(file, (double[3]){-a, -a, -a}, (double[3]){a, a, a});
        fprintf(file,
                "            double3 xformOp:scale = (%.17g, %.17g, %.17g)\n"
                "            uniform token[] xformOpOrder = [\"xformOp:scale\"]\n",
                s->size[0], s->size[1], s->size[2]);
    } else if (s->kind == TB__SHAPE_SPHERE) {
        fprintf(file, "            double radius = %.17g\n", r);
        put_extent(file, (double[3]){-r, -r, -r}, (double[3]){r, r, r});
    } else {
        const double z = 0.5 * h + (s->kind == TB__SHAPE_CAPSULE ? r : 0.0);
        fprintf(file,
                "            uniform token axis = \"Z\"\n            double height = %.17g\n"
                "            double radius = %.17g\n",
                h, r);
        put_extent(file, (double[3]){-r, -r, -z}, (double[3]){r, r, z});
    }
    fputs("        }\n", file);
}

/* A Mesh prim of count points (floats, as USD's point3f holds them) and triangles. */
static void put_mesh(FILE *file, const char *indent, const char *name, const float *points,
                     size_t count, const uint32_t *indices, size_t index_count,
                     const float *normals)
{
    double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
    fprintf(file, "%sdef Mesh \"%s\"\n%s{\n%s    int[] faceVertexCounts = [", indent, name, indent,
            indent);
    for (size_t k = 0; k < index_count / 3; ++k) {
        fputs(k > 0 ? ", 3" : "3", file);
    }
    fprintf(file, "]\n%s    int[] faceVertexIndices = [", indent);
    for (size_t k = 0; k < index_count; ++k) {
        fprintf(file, k > 0 ? ", %u" : "%u", (unsigned)indices[k]);
    }
    fprintf(file, "]\n%s    point3f[] points = [", indent);
    for (size_t k = 0; k < count; ++k) {
        const float *p = points + 3 * k;
        fprintf(file, "%s(%.9g, %.9g, %.9g)", k > 0 ? ", " : "", p[0], p[1], p[2]);
        for (int i = 0; i < 3; ++i) {
            low[i] = fmin(low[i], p[i]);
            high[i] = fmax(high[i], p[i]);
        }
    }
    fprintf(file, "]\n");
    if (normals != NULL) {
        fprintf(file, "%s    normal3f[] normals = [", indent);
        for (size_t k = 0; k < count; ++k) {
            const float *n = normals + 3 * k;
            fprintf(file, "%s(%.9g, %.9g, %.9g)", k > 0 ? ", " : "", n[0], n[1], n[2]);
        }
        fprintf(file, "] (\n%s        interpolation = \"vertex\"\n%s    )\n", indent, indent);
    }
    fprintf(file, "%s    uniform token subdivisionScheme = \"none\"\n", indent);
    if (count > 0) {
        fprintf(file, "%s    float3[] extent = [(%.9g, %.9g, %.9g), (%.9g, %.9g, %.9g)]\n", indent,
                low[0], low[1], low[2], high[0], high[1], high[2]);
    }
    fprintf(file, "%s}\n", indent);
}

/* A triangle mesh shape as itself: its vertices shared, USD's face-varying nothing. */
static bool put_mesh_shape(FILE *file, const tb__shape *s)
{
    float *points = malloc((3 * s->vertex_count + 1) * sizeof *points);
    uint32_t *indices = malloc((3 * s->triangle_count + 1) * sizeof *indices);
    if (points != NULL && indices != NULL) {
        for (size_t k = 0; k < 3 * s->vertex_count; ++k) {
            points[k] = (float)s->vertices[k];
        }
        for (size_t k = 0; k < 3 * s->triangle_count; ++k) {
            indices[k] = (uint32_t)s->triangles[k];
        }
        put_mesh(file, "        ", "shape", points, s->vertex_count, indices, 3 * s->triangle_count,
                 NULL);
    }
    const bool done = points != NULL && indices != NULL;
    free(points);
    free(indices);
    return done;
}

static bool put_tessellated(FILE *file, const char *indent, const char *name, tb__mesh *mesh)
{
    if (!mesh->failed) {
        put_mesh(file, indent, name, mesh->positions, mesh->vertex_count, mesh->indices,
                 mesh->index_count, mesh->normals);
    }
    const bool done = !mesh->failed;
    tb__mesh_free(mesh);
    return done;
}

static bool put_shape(FILE *file, const tb__shape *s)
{
    switch (s->kind) {
    case TB__SHAPE_BOX:
    case TB__SHAPE_SPHERE:
    case TB__SHAPE_ELLIPSOID:
    case TB__SHAPE_CYLINDER:
    case TB__SHAPE_CAPSULE:
        put_primitive(file, s);
        return true;
    case TB__SHAPE_MESH:
        return put_mesh_shape(file, s);
    default: {
        tb__mesh mesh = {0};
        tb__mesh_of_shape(&mesh, s);
        return put_tessellated(file, "        ", "shape", &mesh);
    }
    }
}

/* A body's shape: one piece at the shape origin as the prim "shape" (as a single shape always
 * was); otherwise each piece k in an Xform "piece_k" that places it in the body's shape frame. */
static bool put_pieces(FILE *file, const tb__look *look)
{
    const tb__shape *first = &look->pieces[0];
    const bool plain = look->piece_count == 1 && first->position[0] == 0.0 &&
                       first->position[1] == 0.0 && first->position[2] == 0.0 &&
                       first->orientation[0] == 1.0;
    if (plain) {
        return put_shape(file, first);
    }
    bool done = true;
    for (size_t k = 0; k < look->piece_count && done; ++k) {
        const double *p = look->pieces[k].position, *q = look->pieces[k].orientation;
        fprintf(file,
                "        def Xform \"piece_%zu\"\n        {\n"
                "        double3 xformOp:translate = (%.17g, %.17g, %.17g)\n"
                "        quatd xformOp:orient = (%.17g, %.17g, %.17g, %.17g)\n"
                "        uniform token[] xformOpOrder = [\"xformOp:translate\", "
                "\"xformOp:orient\"]\n\n",
                k, p[0], p[1], p[2], q[0], q[1], q[2], q[3]);
        done = put_shape(file, &look->pieces[k]);
        fputs("        }\n", file);
    }
    return done;
}

static bool put_body(const tb_writer *w, size_t id, const char *prim)
{
    FILE *file = w->file;
    fprintf(
        file,
        "    def Xform \"%s\" (\n        customData = {\n            string tumbleBody = ", prim);
    put_string(file, w->names[id]);
    fputs("\n        }\n    )\n    {\n", file);
    if (w->frames.count > 0) {
        tb__usd_put_pose_samples(w, id);
    } else {
        fputs("        double3 xformOp:translate = (0, 0, 0)\n"
              "        quatd xformOp:orient = (1, 0, 0, 0)\n",
              file);
    }
    fputs("        uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:orient\"]\n\n",
          file);
    const bool done = put_pieces(file, &w->looks.bodies[id]);
    fputs("    }\n\n", file);
    return done;
}

/* Prim names for the bodies, then the grounds ("ground_1", ...), then the joints ("joint_0",
 * ... by index), unique together. */
static char (*prim_names(const tb_writer *w))[TB__USD_NAME_SIZE]
{
    const size_t others = w->looks.ground_count + w->looks.joint_count;
    const size_t count = w->body_count + others;
    char(*names)[TB__USD_NAME_SIZE] = malloc((count + 1) * sizeof *names);
    char(*made)[TB_NAME_SIZE] = malloc((others + 1) * sizeof *made);
    const char **sources = malloc((count + 1) * sizeof *sources);
    bool done = names != NULL && made != NULL && sources != NULL;
    for (size_t k = 0; done && k < count; ++k) {
        const size_t g = k - w->body_count, j = g - w->looks.ground_count;
        if (k >= w->body_count && g < w->looks.ground_count) {
            snprintf(made[g], TB_NAME_SIZE, "ground_%zu", g + 1);
        } else if (k >= w->body_count) {
            snprintf(made[g], TB_NAME_SIZE, "joint_%zu", j);
        }
        sources[k] = k < w->body_count ? w->names[k] : made[g];
    }
    done = done && tb__usd_names(sources, count, names) == TB_STATUS_OK;
    free(made);
    free(sources);
    if (!done) {
        free(names);
        return NULL;
    }
    return names;
}

/* def.fps 0: 1 / the first interval, whole within 1e-9 (t = k / fps gives fps to an ulp or
 * two); one frame or none: 1. */
static void infer_fps(tb_writer *w)
{
    if (w->fps > 0) {
        return;
    }
    const tb__frames *f = &w->frames;
    const double fps = f->count > 1 ? 1.0 / (f->t[1] - f->t[0]) : 1.0;
    w->fps = fabs(fps - round(fps)) <= 1e-9 * fps ? round(fps) : fps;
}

tb_status tb__usd_write(tb_writer *w)
{
    infer_fps(w);
    char(*names)[TB__USD_NAME_SIZE] = prim_names(w);
    bool done = names != NULL;
    if (done) {
        put_header(w);
    }
    for (size_t id = 0; done && id < w->body_count; ++id) {
        done = put_body(w, id, names[id]);
    }
    double center[3], half_size;
    tb__ground_extent(&w->frames, center, &half_size);
    for (size_t k = 0; done && k < w->looks.ground_count; ++k) {
        tb__mesh mesh = {0};
        tb__mesh_of_ground(&mesh, &w->looks.grounds[k], center, half_size);
        done = put_tessellated(w->file, "    ", names[w->body_count + k], &mesh);
    }
    const size_t first_joint = w->body_count + w->looks.ground_count;
    for (size_t j = 0; done && j < w->looks.joint_count; ++j) {
        tb__usd_put_joint(w, j, names[first_joint + j], names);
    }
    if (done) {
        fputs("}\n", w->file);
    }
    free(names);
    if (!done) {
        return tb__set_detail(w->detail, TB_STATUS_OUT_OF_MEMORY, "%s: USD of %zu frames", w->path,
                              w->frames.count);
    }
    return ferror(w->file) ? tb__writer_io_failure(w, "write failed") : TB_STATUS_OK;
}

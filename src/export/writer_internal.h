/* Private: the writer object, the frames it keeps, and the format back ends. */
#ifndef TUMBLE_WRITER_INTERNAL_H
#define TUMBLE_WRITER_INTERNAL_H

#include "tumble/joints.h"
#include "tumble/writer.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

/* Frames kept in memory for the formats written at close (npz, glTF), one array per quantity
 * in the layout NumPy reads: frame-major, then body, then component. */
typedef struct tb__frames {
    size_t count, capacity, body_count;
    double *t;                /* [count] s */
    double *position;         /* [count][body_count][3] shape origin, world, m */
    double *orientation;      /* [count][body_count][4] shape -> world (w, x, y, z) */
    double *velocity;         /* [count][body_count][3] of the shape origin, world, m/s */
    double *angular_velocity; /* [count][body_count][3] world, rad/s */
} tb__frames;

/* npz frames streamed to the file as they come (writer_npz_stream.c). */
typedef struct tb__npz_stream tb__npz_stream;

/* What each body looks like (glTF, USD). Sizes in the shape frame, m. */
typedef enum tb__shape_kind {
    TB__SHAPE_INERTIA = 0, /* no shape given: the ellipsoid of equal mass and inertia */
    TB__SHAPE_BOX,
    TB__SHAPE_SPHERE,
    TB__SHAPE_CYLINDER, /* axis along z */
    TB__SHAPE_CAPSULE,  /* axis along z, length between the hemispheres' centres */
    TB__SHAPE_ELLIPSOID,
    TB__SHAPE_MESH,
    TB__SHAPE_POINTS /* each point a small sphere */
} tb__shape_kind;

typedef struct tb__shape {
    tb__shape_kind kind;
    double size[3]; /* box edges, ellipsoid semi-axes, or (radius, length, 0) */
    double *vertices;
    size_t vertex_count;     /* mesh vertices or points, [3 * vertex_count] */
    unsigned *triangles;     /* mesh only, [3 * triangle_count] */
    size_t triangle_count;   /* */
    tb_mass_properties mass; /* for TB__SHAPE_INERTIA */
    double position[3];      /* where the piece sits in the body's shape frame, m */
    double orientation[4];   /* piece frame -> body's shape frame, unit (w, x, y, z) */
} tb__shape;

/* One body as drawn: its pieces (the scene's, tb_scene_body_piece; one TB__SHAPE_INERTIA
 * piece for a body without a shape), and its mass properties. */
typedef struct tb__look {
    tb__shape *pieces;
    size_t piece_count;
    tb_mass_properties mass;
} tb__look;

typedef struct tb__ground {
    double normal[3]; /* unit, out of the ground */
    double offset;    /* plane normal . x = offset, m */
} tb__ground;

/* A joint as drawn (glTF: a marker at its anchor, a child of its first body's node) and as
 * described (USD: a UsdPhysics joint prim). Frames from the scene's state at open. */
typedef struct tb__joint_mark {
    const char *type;      /* "ball", "hinge", ... (tb_joint_type_name) */
    size_t body_a, body_b; /* body ids; body_b TB_WORLD for the world */
    double anchor[3];      /* in body_a's shape frame, m */
    double anchor_b[3];    /* in body_b's shape frame (the world's for TB_WORLD), m */
    /* The joint's frame, its x along def.axis, in each body's shape frame (the world's for
     * TB_WORLD): unit (w, x, y, z), joint frame -> body shape frame. */
    double frame_a[4], frame_b[4];
    double radius;    /* the marker sphere's, m */
    tb_joint_def def; /* as given (tb_scene_joint_def): limits, breaking */
} tb__joint_mark;

typedef struct tb__looks {
    tb__look *bodies; /* [body_count] */
    tb__ground *grounds;
    size_t ground_count;
    tb__joint_mark *joints; /* [joint_count], NULL for none (writer_joints.c) */
    size_t joint_count;
} tb__looks;

struct tb_writer {
    tb_output_format format;
    tb_rotation_keys rotation_keys;
    size_t body_count;
    char (*names)[TB_NAME_SIZE];
    char *path;         /* where the file ends up */
    char *written_path; /* where it is written: "<path>.partial", or path itself */
    FILE *file;
    tb__frames frames;       /* npz, glTF: kept in memory until close */
    tb__npz_stream *stream;  /* npz with a known frame count, into a file that can seek */
    size_t announced_frames; /* npz: def.frame_count, 0 if not known */
    double fps;              /* USD: time codes per second (0 until known) */
    double sample_tolerance; /* USD: rad, 0 for samples at the frames only */
    double *values;          /* [13 * body_count]: one frame's read-outs from the scene */
    tb__looks looks;         /* glTF, USD */
    double last_t;
    size_t frame_count;
    tb_contact_event *events; /* glTF: tb_writer_set_contact_events's copy (event_count) */
    size_t event_count;
    tb_status failed; /* a write failed: every later call reports it */
    char detail[TB_DETAIL_SIZE];
};

/* The scene's joints into looks->joints (writer_joints.c); TB_STATUS_OUT_OF_MEMORY. */
tb_status tb__looks_joints(tb__looks *looks, const tb_scene *scene, tb_error *error);

tb_status tb__frames_init(tb__frames *frames, size_t body_count);
/* The place of the next frame (room made for it): t[1], position[3 n], orientation[4 n],
 * velocity[3 n], angular_velocity[3 n]; TB_STATUS_OUT_OF_MEMORY. frames->count++ takes it. */
tb_status tb__frames_slot(tb__frames *frames, double **out_parts);
void tb__frames_free(tb__frames *frames);

/* "path: what failed: strerror" into the writer's detail; returns TB_STATUS_IO_ERROR. */
tb_status tb__writer_io_failure(tb_writer *writer, const char *what);

/* Back ends. */
tb_status tb__csv_header(tb_writer *writer);
tb_status tb__csv_frame(tb_writer *writer, double t, const double *values);
tb_status tb__npz_write(tb_writer *writer);
tb_status tb__gltf_write(tb_writer *writer);
tb_status tb__usd_write(tb_writer *writer);

/* USD: a prim name's room (a body name, a leading '_' and a suffix). */
#define TB__USD_NAME_SIZE (TB_NAME_SIZE + 24)
/* USD prim names for count names: identifiers, unique (writer_usd_names.c);
 * TB_STATUS_OUT_OF_MEMORY. */
tb_status tb__usd_names(const char *const *sources, size_t count, char (*out)[TB__USD_NAME_SIZE]);
/* The time code of t: t fps, a whole number when within 1e-9 of one. */
double tb__usd_time_code(double t, double fps);
/* Body id's xformOp:translate and xformOp:orient time samples into the writer's file. */
void tb__usd_put_pose_samples(const tb_writer *w, size_t id);
/* Joint j as a UsdPhysics joint prim named prim under /world, its bodies the prims body_prims
 * (writer_usd_joints.c). */
void tb__usd_put_joint(const tb_writer *w, size_t j, const char *prim,
                       char (*body_prims)[TB__USD_NAME_SIZE]);

/* Shapes and ground planes for glTF and USD, from the scene alone: each body's pieces
 * (tb_scene_body_piece; a piece with a visual mesh as that mesh, tb_scene_body_visual_mesh; a
 * body without a shape as its visual mesh or its inertia ellipsoid; a convex piece as its hull)
 * and the ground planes (tb_scene_get_ground). */
tb_status tb__looks_load(tb__looks *looks, const tb_scene *scene, tb_error *error);
void tb__looks_free(tb__looks *looks, size_t body_count);

/* A triangle mesh in the shape frame, as glTF stores it: float positions and unit normals,
 * counter-clockwise (outward) triangles. */
typedef struct tb__mesh {
    float *positions; /* [3 * vertex_count] m */
    float *normals;   /* [3 * vertex_count] */
    size_t vertex_count, vertex_capacity;
    uint32_t *indices; /* [index_count], 3 a triangle */
    size_t index_count, index_capacity;
    bool failed; /* out of memory on the way */
} tb__mesh;

/* Appends the shape's surface in its own frame (ground: a square of half_size m around center,
 * on the plane); a body's, every piece placed in the body's shape frame. */
void tb__mesh_of_shape(tb__mesh *mesh, const tb__shape *shape);
void tb__mesh_of_body(tb__mesh *mesh, const tb__look *look);
void tb__mesh_of_ground(tb__mesh *mesh, const tb__ground *ground, const double center[3],
                        double half_size);
void tb__mesh_free(tb__mesh *mesh);
/* Where the ground squares go and how big: around the bodies' mean first position, at least
 * 10 m across their spread in every direction. */
void tb__ground_extent(const tb__frames *frames, double center[3], double *half_size);

#endif

/* Status codes and error details shared by every tumble function that can fail. */
#ifndef TUMBLE_STATUS_H
#define TUMBLE_STATUS_H

#include "tumble/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One list gives both the names and the messages, so the two cannot drift apart.
 * X(NAME, value, message). 0 is success; every error is negative. */
#define TB_STATUS_LIST(X)                                                                          \
    X(OK, 0, "success")                                                                            \
    X(INVALID_ARGUMENT, -1, "invalid argument")                                                    \
    X(NULL_POINTER, -2, "required pointer is NULL")                                                \
    X(OUT_OF_MEMORY, -3, "out of memory")                                                          \
    X(OUT_OF_RANGE, -4, "index out of range")                                                      \
    X(NOT_FINITE, -5, "value is not finite (NaN or infinity)")                                     \
    X(BAD_MASS_PROPERTIES, -6, "mass properties are not physical")                                 \
    X(BAD_MESH, -7, "triangle mesh is not closed, consistently oriented and non-degenerate")       \
    X(DERIVATIVE_FAILED, -8, "derivative callback reported an error")                              \
    X(HOOK_FAILED, -9, "post-step hook reported an error")                                         \
    X(STATE_NOT_FINITE, -10, "integration produced a non-finite state")                            \
    X(SOLVER_FAILED, -11, "ODE solver failed")                                                     \
    X(UNSUPPORTED, -12, "operation not supported by this integrator")                              \
    X(CANCELLED, -13, "stopped by a callback")                                                     \
    X(PARSE_ERROR, -14, "scene file is not valid JSON")                                            \
    X(BAD_SCENE, -15, "scene file describes something invalid")                                    \
    X(IO_ERROR, -16, "file could not be read or written")                                          \
    X(UNSTABLE_STEP, -17, "fixed step is beyond the scene's stability limit")                      \
    X(LAYOUT_CHANGED, -18, "the scene's layout changed after the integrator was made")             \
    X(BUSY, -19, "object is in use by a call in progress (re-entrant call)")                       \
    X(TOO_MANY_STEPS, -20, "step budget used up before the target time")

typedef enum tb_status {
#define TB__STATUS_ENUM(name, value, message) TB_STATUS_##name = value,
    TB_STATUS_LIST(TB__STATUS_ENUM)
#undef TB__STATUS_ENUM
} tb_status;

/* The library's version, "major.minor.patch" (TB_VERSION_STRING of the build). */
TB_API const char *tb_version(void);

/* Human-readable message for a status; never NULL ("unknown status" for values not listed). */
TB_API const char *tb_status_string(tb_status status);

/* The status's name without prefix, e.g. "NOT_FINITE"; never NULL ("UNKNOWN" if not listed). */
TB_API const char *tb_status_name(tb_status status);

/* Size of every detail buffer, including the terminating NUL: room for the longest message
 * (the unstable-step advice naming a body of TB_NAME_SIZE - 1 characters, wrapped with the
 * time it was found, is about 330) with room to spare; test_hard_cases checks it ends
 * intact. */
#define TB_DETAIL_SIZE 1024

/* Detail of a failure that has no object to keep it (creation, free functions such as the
 * mass-property routines). Functions take a `tb_error *out_error` that may be NULL. On
 * failure they write a message naming the input that was wrong, e.g.
 * "mass: must be > 0, got -1"; on success they leave it empty. */
typedef struct tb_error {
    tb_status status;
    char message[TB_DETAIL_SIZE];
} tb_error;

#ifdef __cplusplus
}
#endif

#endif

/* A watch on a run from inside its derivative work: the accuracy sweep's CPU budget and its
 * progress within a frame. A run reports to its caller only at frames (tb_frame_fn), and an
 * adaptive setting that crawls can spend minutes inside one frame (ark-imex with dense
 * difference quotients on the stack of boxes: over 7 minutes of CPU before t = 1.6 ms of its
 * first 1/30 s frame), where neither a budget checked at frames nor a progress line could come.
 * The derivative calls the watch every TB__RUN_WATCH_EVERY evaluations with its t; a non-zero
 * answer fails that evaluation with TB__RUN_WATCH_STOPPED, which every method treats as a
 * failed derivative and so ends the run (CVODE and ARKODE: an unrecoverable right-hand side).
 * With no watch set (every run but the sweep's) the derivative does what it did, and the
 * watch never changes a derivative's values: a run it does not stop is the run without it. */
#ifndef TB_SCENE_RUN_WATCH_H
#define TB_SCENE_RUN_WATCH_H

/* Evaluations between calls: the call reads the process CPU clock (a system call, about a
 * microsecond), under 1 % of even the cheapest contact derivative taken this often. */
#define TB__RUN_WATCH_EVERY 256u

/* What the derivative returns when the watch stops it (negative: not recoverable). */
#define TB__RUN_WATCH_STOPPED (-77)

typedef struct tb__run_watch {
    int (*fn)(double t, void *ctx); /* non-zero: stop the run */
    void *ctx;
    unsigned countdown; /* evaluations until the next call */
} tb__run_watch;

#endif

/* TB_API marks the public functions. A shared libtumble is built with hidden visibility, so
 * only these are exported; on Windows they become dllexport/dllimport. */
#ifndef TUMBLE_EXPORT_H
#define TUMBLE_EXPORT_H

#if defined(_WIN32) && defined(TUMBLE_SHARED)
#ifdef TUMBLE_BUILDING
#define TB_API __declspec(dllexport)
#else
#define TB_API __declspec(dllimport)
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define TB_API __attribute__((visibility("default")))
#else
#define TB_API
#endif

#endif

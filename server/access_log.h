/* access_log.h - one line per HTTP request on stderr (time, request id, method, path, status, bytes,
 * queue/render/encode ms), and the daemon's other log lines with a level filter. */
#ifndef LUCENTD_ACCESS_LOG_H
#define LUCENTD_ACCESS_LOG_H

#include "config.h"

#include <stddef.h>

struct access_entry {
    const char *request_id, *method, *path;
    unsigned status;          /* 0: no response was sent */
    size_t bytes;
    double queue_ms, render_ms, encode_ms, total_ms;
    const char *cache;        /* "hit", "miss" or "-" */
    const char *note;         /* why the connection ended early, or NULL */
};

void log_set_level(enum log_level level);
void log_request(const struct access_entry *e);
void log_line(enum log_level level, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#endif

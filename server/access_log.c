/* access_log.c - the daemon's log on stderr: one access line per request, written at completion (final status
 * and bytes), and leveled messages; each line is one write, so threads never interleave lines. */
#include "access_log.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static enum log_level current = LOG_INFO;

void log_set_level(enum log_level level)
{
    current = level;
}

static void timestamp(char *buf, size_t cap)
{
    struct timespec ts;
    struct tm tm;
    clock_gettime(CLOCK_REALTIME, &ts);
    gmtime_r(&ts.tv_sec, &tm);
    size_t n = strftime(buf, cap, "%Y-%m-%dT%H:%M:%S", &tm);
    snprintf(buf + n, cap - n, ".%03ldZ", ts.tv_nsec / 1000000);
}

/* Request text is printed escaped: a path must not be able to forge log lines. */
static void printable(const char *in, char *out, size_t cap)
{
    size_t o = 0;
    for (; in && *in && o + 4 < cap; in++) {
        unsigned char c = (unsigned char)*in;
        if (c < 0x21 || c > 0x7e || c == '%')
            o += (size_t)snprintf(out + o, cap - o, "%%%02X", c);
        else
            out[o++] = (char)c;
    }
    out[o] = 0;
}

void log_request(const struct access_entry *e)
{
    if (current < LOG_INFO)
        return;
    char ts[40], path[300], method[24];
    timestamp(ts, sizeof ts);
    printable(e->path, path, sizeof path);
    printable(e->method, method, sizeof method);
    char line[768];
    int n = snprintf(line, sizeof line,
                     "%s access id=%s %s %s status=%u bytes=%zu queue_ms=%.1f render_ms=%.1f encode_ms=%.1f "
                     "total_ms=%.1f cache=%s%s%s\n",
                     ts, e->request_id, method, path, e->status, e->bytes, e->queue_ms, e->render_ms, e->encode_ms,
                     e->total_ms, e->cache, e->note ? " note=" : "", e->note ? e->note : "");
    if (n > 0)
        fwrite(line, 1, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1, stderr);
}

void log_line(enum log_level level, const char *fmt, ...)
{
    static const char *const names[] = {"error", "warn", "info", "debug"};
    if (level > current)
        return;
    char ts[40], msg[1024], line[1200];
    timestamp(ts, sizeof ts);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    int n = snprintf(line, sizeof line, "%s %s lucentd: %s\n", ts, names[level], msg);
    if (n > 0)
        fwrite(line, 1, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1, stderr);
}

/* url_unescape.h - percent-decoding of the request path and of each query key and value, in place:
 * libmicrohttpd's, except that %00 stays as sent (so every byte sent is part of what is validated). */
#ifndef LUCENTD_URL_UNESCAPE_H
#define LUCENTD_URL_UNESCAPE_H

#include <stddef.h>

/* Decodes %XX escapes of s in place except %00 and malformed ones, which stay as they are; returns
 * the new length (the result is NUL-terminated and holds no NUL before it). */
size_t url_unescape(char *s);

#endif

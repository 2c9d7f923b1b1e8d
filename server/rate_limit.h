/* rate_limit.h - per-client token buckets: each client address may make `rate` requests a second on
 * average and `burst` at once; more get 429 with the seconds until the next would pass. */
#ifndef LUCENTD_RATE_LIMIT_H
#define LUCENTD_RATE_LIMIT_H

#include <sys/socket.h>

struct rate_limit;

/* NULL when out of memory. rate > 0 requests a second, burst >= 1. */
struct rate_limit *rate_limit_new(double rate, double burst);
void rate_limit_free(struct rate_limit *rl);
/* Takes a token from addr's bucket at time `now` (seconds, monotonic) and returns 0, or returns the
 * seconds until a token will be there and takes none. Safe from any thread. */
double rate_limit_take(struct rate_limit *rl, const struct sockaddr *addr, double now);

#endif

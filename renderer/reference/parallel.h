/* parallel.h - the CPU integrators' thread pool: items handed out in chunks to a few threads, each item's
 * result depending only on the item (so results do not depend on the thread count); stops on cancel. */
#ifndef LUCENT_PARALLEL_H
#define LUCENT_PARALLEL_H

#include <stdatomic.h>
#include <stddef.h>

typedef void (*parallel_fn)(void *ctx, size_t begin, size_t end);

/* Runs fn over [0, count) in chunks of `chunk` on `threads` threads (the caller's among them); once
 * *cancel turns non-zero (cancel may be NULL) no further chunk starts. A thread that cannot be started only
 * costs speed: the others take its share. */
void parallel_run(void *ctx, int threads, size_t count, size_t chunk, parallel_fn fn, const atomic_int *cancel);
/* `requested` threads, or one per online CPU when 0, within 1..PARALLEL_MAX_THREADS. */
int parallel_threads(int requested);
#define PARALLEL_MAX_THREADS 64

#endif

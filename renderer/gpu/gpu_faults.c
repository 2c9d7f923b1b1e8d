/* gpu_faults.c - the plan of injected GPU faults ($LUCENT_FAULTS) and the process-wide frame count it
 * is written against. Only in builds with LUCENT_FAULT_INJECTION (tests); a plan that does not parse
 * is reported once on stderr and injects nothing. */
#include "gpu_faults.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PLAN_MAX 16

static struct {
    enum gpu_fault kind;
    unsigned long frame;
} plan[PLAN_MAX];
static int planned;
static unsigned long frames;
static pthread_once_t once = PTHREAD_ONCE_INIT;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

static enum gpu_fault kind_named(const char *name, size_t len)
{
    static const char *const names[] = {"submit", "lost", "timeout", "hang"};
    for (int i = 0; i < 4; i++)
        if (strlen(names[i]) == len && memcmp(names[i], name, len) == 0)
            return (enum gpu_fault)(GPU_FAULT_SUBMIT + i);
    return GPU_FAULT_NONE;
}

static void read_plan(void)
{
    const char *spec = getenv("LUCENT_FAULTS");
    for (const char *p = spec; p && *p && planned < PLAN_MAX;) {
        const char *at = strchr(p, '@');
        char *end = NULL;
        enum gpu_fault kind = at ? kind_named(p, (size_t)(at - p)) : GPU_FAULT_NONE;
        unsigned long frame = at ? strtoul(at + 1, &end, 10) : 0;
        if (kind == GPU_FAULT_NONE || !end || end == at + 1 || (*end && *end != ',') || frame == 0) {
            fprintf(stderr, "lucent: LUCENT_FAULTS=\"%s\" not understood (KIND@FRAME,... with KIND submit, lost, "
                            "timeout or hang); no faults injected\n", spec);
            planned = 0;
            return;
        }
        plan[planned].kind = kind;
        plan[planned++].frame = frame;
        p = *end ? end + 1 : end;
    }
}

enum gpu_fault gpu_fault_next_frame(void)
{
    pthread_once(&once, read_plan);
    pthread_mutex_lock(&lock);
    unsigned long frame = ++frames;
    pthread_mutex_unlock(&lock);
    for (int i = 0; i < planned; i++)
        if (plan[i].frame == frame) {
            fprintf(stderr, "lucent: frame %lu: injecting the planned GPU fault\n", frame);
            return plan[i].kind;
        }
    return GPU_FAULT_NONE;
}

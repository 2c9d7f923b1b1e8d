/* upload_queue.h - mesh uploads imported off the HTTP thread: mesh_store_put waits for a sandboxed importer
 * (up to import-wall seconds), so each runs on its own thread with its connection suspended. */
#ifndef LUCENTD_UPLOAD_QUEUE_H
#define LUCENTD_UPLOAD_QUEUE_H

#include "lucent.h"
#include "mesh_store.h"

#include <microhttpd.h>

struct upload_job {
    /* Set by the submitter. */
    struct MHD_Connection *connection;
    unsigned char *bytes;          /* owned by the job */
    size_t len;
    char format[8];                /* mesh_store_put's */
    /* Written by the import thread before done is set; read after the resume. */
    int done;                      /* 1 imported (or refused), -1 cancelled by shutdown */
    lucent_status status;
    lucent_error err;
    char id[65];
    struct mesh_info info;
    int created;
    /* Owned by the queue's lock. */
    int refs;
    struct upload_job *next;       /* in the list of running imports */
};

struct upload_queue;

struct resume_gate;

/* Connections are resumed through `resumes`, which must outlive the queue. */
struct upload_queue *upload_queue_create(struct mesh_store *store, int max_running, struct resume_gate *resumes);
/* A job holding one reference (the caller's); takes ownership of bytes (freed with the job). NULL
 * (bytes freed) when out of memory. */
struct upload_job *upload_job_new(unsigned char *bytes, size_t len, const char *format);
void upload_job_release(struct upload_queue *q, struct upload_job *job);
/* Suspends job->connection and starts the import; call from the access handler. -1 (nothing
 * suspended): too many imports running or the queue is closed. */
int upload_queue_submit(struct upload_queue *q, struct upload_job *job);
/* Answers every running import's connection as cancelled and refuses new ones; imports finish. */
void upload_queue_cancel_all(struct upload_queue *q);
/* Waits until no import runs or the deadline (monotonic seconds) passes; returns the number running. */
int upload_queue_wait_idle(struct upload_queue *q, double deadline);
/* Waits for running imports, then frees the queue. */
void upload_queue_destroy(struct upload_queue *q);

#endif

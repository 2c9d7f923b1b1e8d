/* store_lock.h - the mesh store's lock between processes: several lucentd replicas may share one store
 * directory (a ReadWriteMany volume), and every change to its set of entries happens under this lock. */
#ifndef LUCENT_STORE_LOCK_H
#define LUCENT_STORE_LOCK_H

/* Open file description locks (F_OFD_SETLKW): held per open file, released when it is closed or the
 * process dies, and carried by NFS (as POSIX locks) as well as local file systems. */

/* Waits for the exclusive lock on <dir>/store.lock (created if missing); returns its descriptor, which
 * store_unlock releases, or -1 with errno set. */
int store_lock(const char *dir);
void store_unlock(int fd);

/* Marks a file this process is still writing (a shared lock on it); 0 or -1 with errno set. */
int store_claim_file(int fd);
/* Whether some process still writes the file at path (holds a claim on it); 0 when no one does or it
 * cannot be opened. */
int store_file_claimed(const char *path);

#endif

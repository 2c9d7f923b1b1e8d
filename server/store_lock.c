/* store_lock.c - the store's lock between processes and the claims on files being written, both as open
 * file description locks, so a replica that dies releases them with its descriptors. */
#define _GNU_SOURCE /* F_OFD_SETLKW */

#include "store_lock.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <unistd.h>

#define LOCK_NAME "store.lock"

static int ofd_lock(int fd, short type, int wait)
{
    struct flock fl = {.l_type = type, .l_whence = SEEK_SET, .l_start = 0, .l_len = 0};
    int rc;
    while ((rc = fcntl(fd, wait ? F_OFD_SETLKW : F_OFD_SETLK, &fl)) != 0 && errno == EINTR)
        ;
    return rc;
}

int store_lock(const char *dir)
{
    char path[PATH_MAX];
    if ((size_t)snprintf(path, sizeof path, "%s/" LOCK_NAME, dir) >= sizeof path) {
        errno = ENAMETOOLONG;
        return -1;
    }
    int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (fd >= 0 && ofd_lock(fd, F_WRLCK, 1) != 0) {
        int e = errno;
        close(fd);
        errno = e;
        return -1;
    }
    return fd;
}

void store_unlock(int fd)
{
    if (fd >= 0)
        close(fd); /* closing the last descriptor of the description releases its lock */
}

int store_claim_file(int fd)
{
    return ofd_lock(fd, F_RDLCK, 0);
}

int store_file_claimed(const char *path)
{
    int fd = open(path, O_RDWR | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK); /* a write lock needs write access */
    if (fd < 0)
        return 0;
    /* an exclusive lock is refused while any claim stands; taken, it is dropped at once by close */
    int claimed = ofd_lock(fd, F_WRLCK, 0) != 0 && (errno == EAGAIN || errno == EACCES);
    close(fd);
    return claimed;
}

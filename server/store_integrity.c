/* store_integrity.c - the store's key file and keyed MAC (contract in store_integrity.h). The key
 * appears by link() of a complete temporary, so no reader ever sees it half-written. */
#define _GNU_SOURCE /* mkostemp */

#include "store_integrity.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <openssl/evp.h>
#include <openssl/params.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

static lucent_status key_fail(const char *path, const char *what, int e, lucent_error *err)
{
    return lucent_fail(err, LUCENT_E_IO, "store-key", "the mesh store key \"%s\" %s%s%s", path, what, e ? ": " : "",
                       e ? strerror(e) : "");
}

static lucent_status key_create(const char *path, lucent_error *err)
{
    unsigned char key[STORE_KEY_BYTES];
    char tmp[PATH_MAX];
    if (getrandom(key, sizeof key, 0) != (ssize_t)sizeof key)
        return key_fail(path, "cannot be made: no random bytes", errno, err);
    if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp-XXXXXX", path) >= sizeof tmp)
        return key_fail(path, "has too long a path", 0, err);
    int fd = mkostemp(tmp, O_CLOEXEC); /* mode 0600 */
    if (fd < 0)
        return key_fail(path, "cannot be created", errno, err);
    int ok = write(fd, key, sizeof key) == (ssize_t)sizeof key && fsync(fd) == 0;
    int e = errno;
    close(fd);
    if (ok && link(tmp, path) != 0 && errno != EEXIST) /* EEXIST: another process made it first */
        ok = 0, e = errno;
    unlink(tmp);
    return ok ? LUCENT_OK : key_fail(path, "cannot be written", e, err);
}

lucent_status store_key_load(const char *path, unsigned char key[STORE_KEY_BYTES], lucent_error *err)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0 && errno == ENOENT) {
        lucent_status st = key_create(path, err);
        if (st != LUCENT_OK)
            return st;
        fd = open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    }
    if (fd < 0)
        return key_fail(path, "cannot be opened", errno, err);
    struct stat st;
    lucent_status status = LUCENT_OK;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size != STORE_KEY_BYTES)
        status = key_fail(path, "is not a file of exactly 32 bytes", 0, err);
    else if (st.st_mode & (S_IRWXG | S_IRWXO))
        status = key_fail(path, "may be read or written by other users (chmod 600 it)", 0, err);
    else if (read(fd, key, STORE_KEY_BYTES) != STORE_KEY_BYTES)
        status = key_fail(path, "cannot be read", errno, err);
    close(fd);
    return status;
}

#define CHUNK (1 << 20)

/* Read in chunks rather than mapped: a file truncated under a mapping would end the daemon (SIGBUS). */
static int hmac_of_file(EVP_MAC_CTX *ctx, const unsigned char key[STORE_KEY_BYTES], const char *id, int fd,
                        unsigned char *buf, unsigned char out[32])
{
    OSSL_PARAM params[] = {OSSL_PARAM_construct_utf8_string("digest", "SHA256", 0), OSSL_PARAM_construct_end()};
    if (EVP_MAC_init(ctx, key, STORE_KEY_BYTES, params) != 1 ||
        EVP_MAC_update(ctx, (const unsigned char *)id, strlen(id)) != 1)
        return 0;
    off_t at = 0;
    for (;;) {
        ssize_t n = pread(fd, buf, CHUNK, at);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            return 0;
        if (n == 0)
            break;
        if (EVP_MAC_update(ctx, buf, (size_t)n) != 1)
            return 0;
        at += n;
    }
    size_t out_len = 0;
    return EVP_MAC_final(ctx, out, &out_len, 32) == 1 && out_len == 32;
}

lucent_status store_mac_of_file(const unsigned char key[STORE_KEY_BYTES], const char *id, int fd,
                                char mac[STORE_MAC_HEX + 1], lucent_error *err)
{
    unsigned char md[32];
    EVP_MAC *algorithm = EVP_MAC_fetch(NULL, "HMAC", NULL);
    EVP_MAC_CTX *ctx = algorithm ? EVP_MAC_CTX_new(algorithm) : NULL;
    unsigned char *buf = malloc(CHUNK);
    int ok = ctx && buf && hmac_of_file(ctx, key, id, fd, buf, md);
    int e = errno;
    free(buf);
    EVP_MAC_CTX_free(ctx);
    EVP_MAC_free(algorithm);
    if (!ok)
        return lucent_fail(err, LUCENT_E_IO, "", "cannot compute the MAC of mesh %s: %s", id,
                           e ? strerror(e) : "OpenSSL failed");
    for (int i = 0; i < 32; i++)
        snprintf(mac + 2 * i, 3, "%02x", md[i]);
    return LUCENT_OK;
}

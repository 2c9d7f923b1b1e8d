/* sha256_hex.c - sha256 through OpenSSL's EVP interface (libcrypto is already a dependency of the
 * daemon, which computes mesh ids the same way). */
#include "sha256_hex.h"

#include <openssl/evp.h>
#include <stdio.h>

int sha256_hex(const void *data, size_t len, char out[65], lc_error *err)
{
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned int md_len = 0;
    if (!EVP_Digest(data, len, md, &md_len, EVP_sha256(), NULL) || md_len != 32)
        return lc_fail(err, LC_E_INTERNAL, "sha256 failed in libcrypto");
    for (unsigned int i = 0; i < md_len; i++)
        snprintf(out + 2 * i, 3, "%02x", md[i]);
    return LC_OK;
}

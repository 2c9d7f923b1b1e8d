/* store_integrity.h - the mesh store's keyed MAC: HMAC-SHA256 over a mesh's id and its compact file,
 * so a stored mesh changed on disk (damage, or a writer without the key) is never served. */
#ifndef LUCENT_STORE_INTEGRITY_H
#define LUCENT_STORE_INTEGRITY_H

#include "lucent.h"

#define STORE_KEY_BYTES 32
#define STORE_MAC_HEX 64

/* Reads the key, creating it (random, mode 0600) when the file does not exist; a concurrent creator
 * (another replica on the same store) wins or loses atomically and both read the same key. A file of
 * another size, or one other users may read, is refused (LUCENT_E_IO, field "store-key"). */
lucent_status store_key_load(const char *path, unsigned char key[STORE_KEY_BYTES], lucent_error *err);

/* The MAC of mesh `id` whose compact form is the whole of the regular file fd, as lowercase hex. */
lucent_status store_mac_of_file(const unsigned char key[STORE_KEY_BYTES], const char *id, int fd,
                                char mac[STORE_MAC_HEX + 1], lucent_error *err);

#endif

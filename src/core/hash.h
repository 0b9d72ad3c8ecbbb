/* hash.h - FNV-1a, 64 bits: the content hash of the ground truth's cache, the shard identity of a
 * command line and the lighting programs' compile cache. Not for untrusted keys in a table (it is
 * not keyed): a fingerprint of inputs softlight itself chose. */
#ifndef SL_HASH_H
#define SL_HASH_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define SL_FNV1A_START 14695981039346656037ull /* the offset basis */

/* h extended by the n bytes at `bytes`. */
static inline uint64_t sl_fnv1a(uint64_t h, const void *bytes, size_t n)
{
    const unsigned char *p = bytes;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ull; /* the FNV prime */
    }
    return h;
}

/* h extended by the string s with its terminating NUL (so "ab", "c" and "a", "bc" differ). */
static inline uint64_t sl_fnv1a_str(uint64_t h, const char *s) { return sl_fnv1a(h, s, strlen(s) + 1); }

#endif

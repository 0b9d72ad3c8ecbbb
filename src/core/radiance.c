/* radiance.c - a radiance image of any format the library reads (OpenEXR, Radiance .hdr, PFM),
 * told apart by its first bytes, then by its extension. It sits above the formats' readers
 * (exr.c, hdr.c, pfm.c), which sit above file.c's shared reading: calls run one way. */
#include "image.h"

#include <fcntl.h>
#include <stdbool.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static bool has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext);
    if (n < k)
        return false;
    for (size_t i = 0; i < k; i++)
        if ((path[n - k + i] | 0x20) != ext[i]) /* ext is lower case; ASCII letters and '.' */
            return false;
    return true;
}

/* The format is sniffed from a regular file's first bytes, so an environment saved under the
 * wrong extension still reads; anything else (a FIFO would lose the bytes sniffed, /dev/zero
 * has no magic) goes by its extension, and the .hdr reader, whose messages the tests know,
 * takes whatever is left. */
bool sl_image_read_radiance(const char *path, size_t budget, sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    unsigned char head[4] = {0};
    size_t got = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK /* a FIFO must not block the open */);
    struct stat st;
    if (fd >= 0) {
        if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
            ssize_t r = pread(fd, head, sizeof head, 0);
            got = r > 0 ? (size_t)r : 0;
        }
        close(fd);
    }
    sl_error ignored;
    if (got == 4 && sl_image_magic_exr(head, got, path, &ignored))
        return sl_image_read_exr(path, budget, img, repairs, err);
    if (got >= 2 && sl_image_magic_pfm(head, got, path, &ignored))
        return sl_image_read_pfm(path, budget, img, repairs, err);
    if (got >= 2 && head[0] == '#' && head[1] == '?')
        return sl_image_read_hdr(path, budget, img, repairs, err);
    if (has_extension(path, ".exr"))
        return sl_image_read_exr(path, budget, img, repairs, err);
    if (has_extension(path, ".pfm"))
        return sl_image_read_pfm(path, budget, img, repairs, err);
    return sl_image_read_hdr(path, budget, img, repairs, err);
}

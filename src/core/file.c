/* file.c - whole-file reads with a size cap and atomic whole-file writes, and on top of them
 * the reader and the writer every image format shares. It knows no format: the readers of the
 * formats call it, and radiance.c, above them, picks one.
 *
 * A single file written is an output set of one (output_set.c), so a failed or interrupted
 * write never leaves a half file at the target: the bytes go to a temporary beside it (same
 * file system, so rename is atomic), are flushed with fsync, and only then renamed over the
 * target. Any failure removes the temporary file. */
#include "image.h"
#include "output_set.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Reads in the order: the first `head` bytes, `magic` on them, then the rest. A regular file's
 * size is known; pipes and special files grow the buffer as they go, so a device that is not an
 * image (/dev/zero) fails on its first bytes instead of after max_bytes of them. */
bool sl_read_file_checked(const char *path, size_t max_bytes, const char *cap_name, size_t head,
                          sl_magic_check magic, unsigned char **bytes, size_t *size, sl_error *err)
{
    *bytes = NULL;
    *size = 0;
    if (!cap_name)
        cap_name = "";
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return sl_fail(err, SL_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return sl_fail(err, SL_ERR_IO, "%s: cannot stat: %s", path, strerror(e));
    }
    if (S_ISDIR(st.st_mode)) {
        close(fd);
        return sl_fail(err, SL_ERR_IO, "%s: is a directory, not a file", path);
    }
    if (S_ISREG(st.st_mode) && (unsigned long long)st.st_size > max_bytes) {
        close(fd);
        return sl_fail(err, SL_ERR_RANGE, "%s: file is %lld bytes, more than the %zu allowed%s", path,
                       (long long)st.st_size, max_bytes, cap_name);
    }
    /* One byte of slack lets the loop see end-of-file without a second allocation. */
    size_t cap = S_ISREG(st.st_mode) ? (size_t)st.st_size + 1 : 65536;
    if (cap < head)
        cap = head;
    unsigned char *buf = malloc(cap);
    size_t used = 0;
    bool ok = buf != NULL, checked = !magic;
    if (!ok)
        sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for %zu bytes", path, cap);
    while (ok) {
        if (!checked && used >= head) {
            checked = true;
            if (!(ok = magic(buf, used, path, err)))
                break;
        }
        if (used == cap) {
            if (cap > max_bytes) {
                ok = sl_fail(err, SL_ERR_RANGE, "%s: file is more than the %zu bytes allowed%s", path, max_bytes,
                             cap_name);
                break;
            }
            size_t next = cap * 2 > max_bytes + 1 ? max_bytes + 1 : cap * 2;
            unsigned char *grown = realloc(buf, next);
            if (!grown) {
                ok = sl_fail(err, SL_ERR_MEMORY, "%s: out of memory for %zu bytes", path, next);
                break;
            }
            buf = grown;
            cap = next;
        }
        /* the head alone first, so the magic is checked before more is read */
        size_t want = !checked && head - used < cap - used ? head - used : cap - used;
        ssize_t got = read(fd, buf + used, want);
        if (got < 0) {
            if (errno == EINTR)
                continue;
            ok = sl_fail(err, SL_ERR_IO, "%s: read failed at byte %zu: %s", path, used, strerror(errno));
            break;
        }
        if (got == 0)
            break;
        used += (size_t)got;
    }
    if (ok && !checked)
        ok = magic(buf, used, path, err); /* the file is shorter than the head */
    if (ok && used > max_bytes)
        ok = sl_fail(err, SL_ERR_RANGE, "%s: file is more than the %zu bytes allowed%s", path, max_bytes, cap_name);
    close(fd);
    if (!ok) {
        free(buf);
        return false;
    }
    *bytes = buf;
    *size = used;
    return true;
}

bool sl_read_file(const char *path, size_t max_bytes, unsigned char **bytes, size_t *size, sl_error *err)
{
    return sl_read_file_checked(path, max_bytes, NULL, 0, NULL, bytes, size, err);
}

bool sl_write_file_atomic(const char *path, const void *bytes, size_t size, sl_error *err)
{
    sl_output_set one = {0};
    bool ok = sl_output_set_bytes(&one, path, bytes, size, err) && sl_output_set_commit(&one, err);
    sl_output_set_free(&one);
    return ok;
}

/* The file cap under a budget: no valid image file is larger than its decoded floats, headers aside. */
static size_t file_cap(size_t budget)
{
    size_t b = budget ? budget : SL_IMAGE_BUDGET_DEFAULT;
    return b < SL_IMAGE_MAX_FILE_BYTES - SL_IMAGE_HEADER_SLACK ? b + SL_IMAGE_HEADER_SLACK : SL_IMAGE_MAX_FILE_BYTES;
}

bool sl_image_read_with(const char *path, size_t budget, sl_magic_check magic, sl_image_parser parse,
                        sl_image *img, sl_image_repairs *repairs, sl_error *err)
{
    *img = (sl_image){0};
    if (repairs)
        *repairs = (sl_image_repairs){0};
    unsigned char *bytes;
    size_t size;
    char why[96];
    snprintf(why, sizeof why, " by the image memory budget (raise it with %s)", sl_options[SL_OPT_IMAGE_MEMORY].cli);
    if (!sl_read_file_checked(path, file_cap(budget), why, SL_IMAGE_MAGIC_BYTES, magic, &bytes, &size, err))
        return false;
    bool ok = parse(bytes, size, path, budget, img, repairs, err);
    free(bytes);
    return ok;
}

bool sl_image_write_with(const char *path, sl_image_encoder encode, const sl_image *img, sl_error *err)
{
    sl_output_set one = {0};
    bool ok = sl_output_set_image(&one, path, encode, img, err) && sl_output_set_commit(&one, err);
    sl_output_set_free(&one);
    return ok;
}

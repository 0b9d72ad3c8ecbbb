/* output_set.c - the files one command writes, all or none (the contract is in output_set.h):
 * where a path really leads, the temporaries beside the targets, their cleanup, the commit.
 *
 * Temporaries of killed runs. A write that is interrupted by SIGINT or SIGTERM, or by SIGKILL,
 * the OOM killer or a power cut, leaves its temporary behind. A signal handler could remove it
 * in the first two cases only, and would need a process-wide list of pending paths that the
 * handler reads while the set may be growing it (the viewer's SDL also owns SIGINT). Instead a
 * temporary carries its writer's PID in a name nobody else uses, ".NAME.softlight-tmp.PID", and
 * the next set that writes NAME removes those whose PID is gone: this covers every kind of kill,
 * keeps no global state, and between the kill and the next run the file is hidden and says what
 * it is. A PID that is alive (or belongs to another user: kill() says EPERM) is left alone. The
 * test is only as good as the PID namespace: a writer in another namespace sharing the directory
 * could look dead; the cost is then that writer's rename failing with an error, not a wrong file. */
#include "output_set.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TMP_TAG ".softlight-tmp."
/* The temporary's name keeps at most this many bytes of the target's, so that it stays under
 * NAME_MAX (255) with the dot, the tag and a PID. */
#define TMP_BASE_MAX 200
/* Symbolic links followed before giving up, as the kernel's own limit (ELOOP) is 40. */
#define MAX_LINK_HOPS 40

static char *dup_string(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

static const char *kind_name(mode_t mode)
{
    return S_ISDIR(mode)    ? "a directory"
           : S_ISFIFO(mode) ? "a FIFO"
           : S_ISCHR(mode)  ? "a character device"
           : S_ISBLK(mode)  ? "a block device"
           : S_ISSOCK(mode) ? "a socket"
                            : "a special file";
}

static bool refuse(const char *path, bool via_link, mode_t mode, sl_error *err)
{
    return sl_fail(err, SL_ERR_IO, "%s: %s %s, not a regular file; softlight writes only regular files", path,
                   via_link ? "is a symbolic link to" : "is", kind_name(mode));
}

/* `link`'s contents as a path: absolute as read, relative ones joined to link's directory. */
static char *follow_link(const char *link, sl_error *err)
{
    char buf[PATH_MAX];
    ssize_t n = readlink(link, buf, sizeof buf - 1);
    if (n < 0) {
        sl_fail(err, SL_ERR_IO, "%s: cannot read the symbolic link: %s", link, strerror(errno));
        return NULL;
    }
    buf[n] = '\0';
    const char *slash = strrchr(link, '/');
    size_t dir = buf[0] == '/' || !slash ? 0 : (size_t)(slash - link) + 1;
    char *next = malloc(dir + (size_t)n + 1);
    if (!next) {
        sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", link);
        return NULL;
    }
    memcpy(next, link, dir);
    memcpy(next + dir, buf, (size_t)n + 1);
    return next;
}

/* The file a write to `path` replaces: path itself, or where its symbolic links lead (also
 * when the last one leads to a name that does not exist yet: that name is created, as a
 * shell's `>` would). Refuses an existing target that is not a regular file. */
static char *resolve_target(const char *path, sl_error *err)
{
    struct stat st, to;
    if (lstat(path, &st) == 0) {
        if (S_ISLNK(st.st_mode) && stat(path, &to) == 0 && !S_ISREG(to.st_mode)) {
            refuse(path, true, to.st_mode, err);
            return NULL;
        }
        if (!S_ISLNK(st.st_mode) && !S_ISREG(st.st_mode)) {
            refuse(path, false, st.st_mode, err);
            return NULL;
        }
    } else if (errno != ENOENT) {
        sl_fail(err, SL_ERR_IO, "%s: cannot stat: %s", path, strerror(errno));
        return NULL;
    }
    char *cur = dup_string(path);
    if (!cur) {
        sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", path);
        return NULL;
    }
    for (int hops = 0; lstat(cur, &st) == 0 && S_ISLNK(st.st_mode); hops++) {
        if (hops == MAX_LINK_HOPS) {
            sl_fail(err, SL_ERR_IO, "%s: more than %d symbolic links in a row", path, MAX_LINK_HOPS);
            free(cur);
            return NULL;
        }
        char *next = follow_link(cur, err);
        free(cur);
        if (!next)
            return NULL;
        cur = next;
    }
    /* The links may have changed meanwhile; where they end must still be a regular file. */
    if (lstat(cur, &st) == 0 && !S_ISREG(st.st_mode)) {
        refuse(path, strcmp(cur, path) != 0, st.st_mode, err);
        free(cur);
        return NULL;
    }
    return cur;
}

/* The mode a new file would get from open(path, O_CREAT, 0666), or the target's own mode when
 * it exists, so that replacing a file does not change its permissions. The temporary is made
 * 0600. umask can only be read by setting it; this happens on the writing thread only and is
 * restored at once. */
static mode_t target_mode(const char *target)
{
    struct stat st;
    if (stat(target, &st) == 0 && S_ISREG(st.st_mode))
        return st.st_mode & 07777;
    mode_t mask = umask(022);
    umask(mask);
    return 0666 & ~mask;
}

/* The length of target's directory part, its last slash included (0: the current directory). */
static size_t dir_length(const char *target)
{
    const char *slash = strrchr(target, '/');
    return slash ? (size_t)(slash - target) + 1 : 0;
}

/* "DIR/.NAME.softlight-tmp." for target DIR/NAME: the temporaries' prefix without the PID. */
static char *temp_prefix(const char *target)
{
    size_t dir = dir_length(target);
    size_t base = strlen(target + dir);
    if (base > TMP_BASE_MAX)
        base = TMP_BASE_MAX;
    char *p = malloc(dir + 1 + base + sizeof TMP_TAG + 24);
    if (p)
        sprintf(p, "%.*s.%.*s" TMP_TAG, (int)dir, target, (int)base, target + dir);
    return p;
}

/* Remove the temporaries of `target` left by processes that are gone (see the top of the file). */
static void remove_stale(const char *target, const char *prefix)
{
    size_t dir = dir_length(target);
    char dirname[PATH_MAX];
    snprintf(dirname, sizeof dirname, "%.*s", dir ? (int)dir : 1, dir ? target : ".");
    DIR *d = opendir(dirname);
    if (!d)
        return;
    const char *name_prefix = prefix + dir;
    size_t n = strlen(name_prefix);
    for (struct dirent *e; (e = readdir(d));) {
        if (strncmp(e->d_name, name_prefix, n) != 0)
            continue;
        const char *digits = e->d_name + n;
        char *end;
        errno = 0;
        long pid = strtol(digits, &end, 10);
        if (end == digits || *end || errno || pid <= 0 || pid > INT_MAX || pid == (long)getpid())
            continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
            continue;
        unlinkat(dirfd(d), e->d_name, 0);
    }
    closedir(d);
}

static bool write_all(int fd, const void *bytes, size_t size, const char *path, sl_error *err)
{
    const unsigned char *p = bytes;
    size_t done = 0;
    while (done < size) {
        ssize_t put = write(fd, p + done, size - done);
        if (put < 0 && errno == EINTR)
            continue;
        if (put <= 0)
            return sl_fail(err, SL_ERR_IO, "%s: write failed after %zu of %zu bytes: %s", path, done, size,
                           put < 0 ? strerror(errno) : "no progress");
        done += (size_t)put;
    }
    return true;
}

/* Create the temporary for `f->target` (exclusively: an old one of our PID, left by a dead
 * process that had it before us, is removed first), write, set the mode, fsync. */
static bool write_temp(const sl_output_set *set, sl_output_file *f, const void *bytes, size_t size, sl_error *err)
{
    char *prefix = temp_prefix(f->target);
    if (!prefix)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", f->path);
    remove_stale(f->target, prefix);
    char *tmp = malloc(strlen(prefix) + 24);
    if (!tmp) {
        free(prefix);
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", f->path);
    }
    sprintf(tmp, "%s%ld", prefix, (long)getpid());
    free(prefix);
    /* Two targets in one directory whose names agree in the first TMP_BASE_MAX bytes. */
    for (int i = 0; i < set->count; i++)
        if (!strcmp(set->files[i].tmp, tmp)) {
            free(tmp);
            return sl_fail(err, SL_ERR_RANGE, "%s: name too long to tell its temporary from %s's", f->path,
                           set->files[i].path);
        }
    int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0 && errno == EEXIST && unlink(tmp) == 0)
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) {
        int e = errno;
        free(tmp);
        return sl_fail(err, SL_ERR_IO, "%s: cannot create a temporary file beside it: %s", f->path, strerror(e));
    }
    bool ok = write_all(fd, bytes, size, f->path, err);
    if (ok && fchmod(fd, target_mode(f->target)) != 0)
        ok = sl_fail(err, SL_ERR_IO, "%s: cannot set permissions: %s", f->path, strerror(errno));
    if (ok && fsync(fd) != 0)
        ok = sl_fail(err, SL_ERR_IO, "%s: fsync failed: %s", f->path, strerror(errno));
    if (close(fd) != 0 && ok)
        ok = sl_fail(err, SL_ERR_IO, "%s: close failed: %s", f->path, strerror(errno));
    if (!ok) {
        unlink(tmp);
        free(tmp);
        return false;
    }
    f->tmp = tmp;
    return true;
}

static void file_free(sl_output_file *f)
{
    if (f->tmp)
        unlink(f->tmp);
    free(f->tmp);
    free(f->target);
    free(f->path);
    *f = (sl_output_file){0};
}

bool sl_output_set_bytes(sl_output_set *set, const char *path, const void *bytes, size_t size, sl_error *err)
{
    if (set->capture)
        return sl_fail(err, SL_ERR_UNSUPPORTED, "%s: this output cannot be sharded (write it without --shard)", path);
    if (set->committed)
        return sl_fail(err, SL_ERR_RANGE, "%s: output set already committed", path);
    sl_output_file f = {.path = dup_string(path)};
    if (!f.path)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", path);
    f.target = resolve_target(path, err);
    if (!f.target) {
        file_free(&f);
        return false;
    }
    /* The same target named twice (also through a link): the later bytes win, and the earlier
     * temporary (which has the same name) goes first. */
    for (int i = 0; i < set->count; i++) {
        if (strcmp(set->files[i].target, f.target) != 0)
            continue;
        file_free(&set->files[i]);
        memmove(&set->files[i], &set->files[i + 1], (size_t)(set->count - i - 1) * sizeof *set->files);
        set->count--;
        break;
    }
    if (set->count == set->capacity) {
        int cap = set->capacity ? 2 * set->capacity : 8;
        sl_output_file *grown = realloc(set->files, (size_t)cap * sizeof *grown);
        if (!grown) {
            file_free(&f);
            return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", path);
        }
        set->files = grown;
        set->capacity = cap;
    }
    if (!write_temp(set, &f, bytes, size, err)) {
        file_free(&f);
        return false;
    }
    set->files[set->count++] = f;
    return true;
}

bool sl_output_set_image(sl_output_set *set, const char *path, sl_image_encoder encode, const sl_image *img,
                         sl_error *err)
{
    if (set->capture)
        return set->capture(set->capture_user, path, encode, img, err);
    unsigned char *bytes;
    size_t size;
    if (!encode(img, &bytes, &size, err)) {
        sl_error_prefix(err, "%s: ", path);
        return false;
    }
    bool ok = sl_output_set_bytes(set, path, bytes, size, err);
    free(bytes);
    return ok;
}

bool sl_output_set_dir(sl_output_set *set, const char *dir, sl_error *err)
{
    if (set->capture)
        return set->capture(set->capture_user, dir, NULL, NULL, err);
    if (set->dir_count == set->dir_capacity) {
        int cap = set->dir_capacity ? 2 * set->dir_capacity : 4;
        char **grown = realloc(set->dirs, (size_t)cap * sizeof *grown);
        if (!grown)
            return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", dir);
        set->dirs = grown;
        set->dir_capacity = cap;
    }
    char *copy = dup_string(dir);
    if (!copy)
        return sl_fail(err, SL_ERR_MEMORY, "%s: out of memory", dir);
    if (mkdir(dir, 0777) != 0) {
        int e = errno;
        free(copy);
        struct stat st;
        if (e == EEXIST && stat(dir, &st) == 0 && S_ISDIR(st.st_mode))
            return true;
        return sl_fail(err, SL_ERR_IO, "%s: cannot create directory: %s", dir,
                       e == EEXIST ? "something else of that name exists" : strerror(e));
    }
    set->dirs[set->dir_count++] = copy;
    return true;
}

/* Every temporary is complete and fsynced before the first rename, so from here on a crash
 * leaves each target either its old file or its new one, never part of one. The renames are
 * not atomic as a group (POSIX has no such call): a crash, or a failing rename, between two of
 * them leaves some targets new and some old. The first file added, a command's main output
 * (-o), is renamed last, so that a new main output means the whole set is new. (After a power
 * cut which renames reached the disk is the file system's choice: directories are not fsynced.) */
bool sl_output_set_commit(sl_output_set *set, sl_error *err)
{
    if (set->capture)
        return true;
    for (int k = 1; k <= set->count; k++) {
        sl_output_file *f = &set->files[k % set->count];
        if (rename(f->tmp, f->target) != 0)
            return sl_fail(err, SL_ERR_IO, "%s: cannot rename the temporary file into place: %s", f->path,
                           strerror(errno));
        free(f->tmp);
        f->tmp = NULL;
    }
    set->committed = true;
    return true;
}

void sl_output_set_free(sl_output_set *set)
{
    for (int i = 0; i < set->count; i++)
        file_free(&set->files[i]);
    for (int i = set->dir_count - 1; i >= 0; i--) {
        if (!set->committed)
            rmdir(set->dirs[i]);
        free(set->dirs[i]);
    }
    free(set->files);
    free(set->dirs);
    *set = (sl_output_set){0};
}

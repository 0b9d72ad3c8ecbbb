/* model_isolate.c - a model import run in a child process, with its memory and time bounded.
 *
 * Owns: the child process, its limits, its stdout and stderr (an importer's own printing goes to
 * /dev/null), and the stream that carries the imported sl_model (or the error) back to the
 * caller. assimp reads some thirty formats, and a few of its importers
 * trust the counts a file declares: a 50-byte OFF file that declares 10^8 faces makes it
 * allocate gigabytes before failing, and some importers recurse once per nesting level of the
 * file. No check before the import can know every format, so the import itself runs where it
 * cannot take the machine with it: a child forked for it, whose address space may grow by the
 * budget the caller gives (setrlimit RLIMIT_AS) and which is killed when its time is up. An
 * import that runs out of memory, out of time or crashes becomes one error line; the calling
 * process is untouched.
 *
 * The child converts the scene itself (model.c's import) and writes the finished sl_model down
 * a pipe: the struct, then each array. The parent reads it back, checking every count against
 * model.h's caps before it allocates, so a stream cut short or garbled is an error, never a
 * huge allocation. The child ends with _exit: it runs none of the parent's exit handlers
 * (a viewer's display connection, a test framework's reports). */
#include "model.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "scene_internal.h"

/* ---- the stream: a tag, then the model or the error ---- */

enum { STREAM_MODEL = 0x4d4f444c, STREAM_ERROR = 0x4552524f };

static bool write_all(int fd, const void *data, size_t size)
{
    const unsigned char *p = data;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        p += n;
        size -= (size_t)n;
    }
    return true;
}

static bool write_model(int fd, const sl_model *m)
{
    uint32_t tag = STREAM_MODEL;
    bool ok = write_all(fd, &tag, sizeof tag) && write_all(fd, m, sizeof *m) &&
              write_all(fd, m->meshes, (size_t)m->mesh_count * sizeof *m->meshes) &&
              write_all(fd, m->instances, (size_t)m->instance_count * sizeof *m->instances) &&
              write_all(fd, m->materials, (size_t)m->material_count * sizeof *m->materials) &&
              write_all(fd, m->images, (size_t)m->image_count * sizeof *m->images);
    for (int i = 0; ok && i < m->mesh_count; i++) {
        const sl_mesh *s = &m->meshes[i].mesh;
        size_t v = (size_t)s->vertex_count;
        ok = write_all(fd, s->positions, v * sizeof *s->positions) && write_all(fd, s->normals, v * sizeof *s->normals) &&
             (!s->texcoords || write_all(fd, s->texcoords, v * sizeof *s->texcoords)) &&
             (!s->tangents || write_all(fd, s->tangents, v * sizeof *s->tangents)) &&
             write_all(fd, s->indices, (size_t)s->triangle_count * 3 * sizeof *s->indices);
    }
    for (int i = 0; ok && i < m->image_count; i++)
        ok = !m->images[i].bytes || write_all(fd, m->images[i].bytes, m->images[i].size);
    return ok;
}

/* The reading side: a deadline for every read, so that a child stuck in an import is found out
 * while the stream waits for it. */
typedef struct {
    int fd;
    struct timespec deadline;
    bool timed_out;
} reader;

static long ms_left(const reader *r)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (long)(r->deadline.tv_sec - now.tv_sec) * 1000 + (r->deadline.tv_nsec - now.tv_nsec) / 1000000;
}

static bool read_all(reader *r, void *data, size_t size)
{
    unsigned char *p = data;
    while (size > 0) {
        long left = ms_left(r);
        if (left <= 0) {
            r->timed_out = true;
            return false;
        }
        struct pollfd pfd = {.fd = r->fd, .events = POLLIN};
        int ready = poll(&pfd, 1, left > 1000 ? 1000 : (int)left);
        if (ready < 0 && errno == EINTR)
            continue;
        if (ready < 0)
            return false;
        if (ready == 0)
            continue;
        ssize_t n = read(r->fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        p += n;
        size -= (size_t)n;
    }
    return true;
}

/* An array of `count` elements of `size` bytes, after the count was checked against its cap. */
static void *read_array(reader *r, size_t count, size_t size)
{
    if (count == 0)
        return NULL;
    void *p = malloc(count * size);
    if (p && !read_all(r, p, count * size)) {
        free(p);
        return NULL;
    }
    return p;
}

/* The model the child wrote, into *m (zeroed first; on failure what was read is freed by the
 * caller's sl_model_free). */
static bool read_model(reader *r, sl_model *m)
{
    sl_model head;
    if (!read_all(r, &head, sizeof head))
        return false;
    /* Pointers in the stream are the child's; counts are checked before anything is allocated. */
    if (head.mesh_count < 1 || head.mesh_count > SL_MODEL_MAX_MESHES || head.instance_count < 1 ||
        head.instance_count > SL_MODEL_MAX_INSTANCES || head.material_count < 1 ||
        head.material_count > SL_MODEL_MAX_MATERIALS || head.image_count < 0 || head.image_count > SL_MODEL_MAX_IMAGES)
        return false;
    memcpy(m->path, head.path, sizeof m->path);
    m->path[sizeof m->path - 1] = '\0';
    m->has_camera = head.has_camera;
    m->camera = head.camera;
    memcpy(m->warnings, head.warnings, sizeof m->warnings);
    m->warnings[sizeof m->warnings - 1] = '\0';
    m->warnings_left_out = head.warnings_left_out > 0 ? head.warnings_left_out : 0;
    /* The arrays of structs; each one's child pointers say only which arrays follow. */
    if (!(m->meshes = read_array(r, (size_t)head.mesh_count, sizeof *m->meshes)))
        return false;
    bool *uv = calloc((size_t)head.mesh_count, 2 * sizeof *uv);
    if (!uv)
        return false;
    long long vertices = 0;
    bool ok = true;
    for (int i = 0; i < head.mesh_count; i++) {
        sl_mesh *s = &m->meshes[i].mesh;
        uv[2 * i] = s->texcoords != NULL;
        uv[2 * i + 1] = s->tangents != NULL;
        s->positions = s->normals = NULL;
        s->texcoords = NULL;
        s->tangents = NULL;
        s->indices = NULL;
        vertices += s->vertex_count;
        ok = ok && s->vertex_count >= 1 && s->vertex_count <= SCENE_MAX_VERTICES && s->triangle_count >= 1 &&
             s->triangle_count <= SCENE_MAX_TRIANGLES && vertices <= SCENE_MAX_TOTAL_VERTICES &&
             m->meshes[i].material >= 0 && m->meshes[i].material < head.material_count;
    }
    m->mesh_count = head.mesh_count;
    ok = ok && (m->instances = read_array(r, (size_t)head.instance_count, sizeof *m->instances));
    m->instance_count = m->instances ? head.instance_count : 0;
    ok = ok && (m->materials = read_array(r, (size_t)head.material_count, sizeof *m->materials));
    m->material_count = m->materials ? head.material_count : 0;
    ok = ok && (!head.image_count || (m->images = read_array(r, (size_t)head.image_count, sizeof *m->images)));
    m->image_count = m->images ? head.image_count : 0;
    bool *bytes = ok && head.image_count ? calloc((size_t)head.image_count, sizeof *bytes) : NULL;
    ok = ok && (bytes || !head.image_count);
    for (int i = 0; ok && i < m->image_count; i++) {
        bytes[i] = m->images[i].bytes != NULL;
        m->images[i].bytes = NULL;
        m->images[i].path[sizeof m->images[i].path - 1] = '\0';
        ok = !bytes[i] || (m->images[i].size > 0 && m->images[i].size <= SL_MODEL_MAX_FILE_BYTES);
    }
    for (int i = 0; ok && i < m->instance_count; i++)
        ok = m->instances[i].mesh >= 0 && m->instances[i].mesh < m->mesh_count;
    /* The vertex and index arrays, then the embedded images' bytes, in the child's order. */
    for (int i = 0; ok && i < m->mesh_count; i++) {
        sl_mesh *s = &m->meshes[i].mesh;
        size_t v = (size_t)s->vertex_count;
        ok = (s->positions = read_array(r, v, sizeof *s->positions)) && (s->normals = read_array(r, v, sizeof *s->normals)) &&
             (!uv[2 * i] || (s->texcoords = read_array(r, v, sizeof *s->texcoords))) &&
             (!uv[2 * i + 1] || (s->tangents = read_array(r, v, sizeof *s->tangents))) &&
             (s->indices = read_array(r, (size_t)s->triangle_count * 3, sizeof *s->indices));
        for (size_t k = 0; ok && k < (size_t)s->triangle_count * 3; k++)
            ok = s->indices[k] < (uint32_t)s->vertex_count;
    }
    for (int i = 0; ok && i < m->image_count; i++)
        ok = !bytes[i] || (m->images[i].bytes = read_array(r, m->images[i].size, 1));
    free(uv);
    free(bytes);
    return ok;
}

/* ---- the child ---- */

/* The process's current address-space size, from /proc (0 when unknown). */
static size_t address_space_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long pages = 0;
    if (f) {
        if (fscanf(f, "%lu", &pages) != 1)
            pages = 0;
        fclose(f);
    }
    return (size_t)pages * (size_t)sysconf(_SC_PAGESIZE);
}

/* AddressSanitizer maps its shadow and allocator regions as the program runs: an address-space
 * limit would fail its own bookkeeping, so sanitized builds bound the time only. */
#if defined(__SANITIZE_ADDRESS__)
#define ADDRESS_SPACE_LIMIT 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ADDRESS_SPACE_LIMIT 0
#endif
#endif
#ifndef ADDRESS_SPACE_LIMIT
#define ADDRESS_SPACE_LIMIT 1
#else
#include <sanitizer/common_interface_defs.h>
#endif

/* An importer's own printing is not softlight's message: openddlparser (OpenGEX) writes
 * "nullptr returned by creating DDLNode." to std::cerr before assimp fails the import, which
 * made two lines of one error. The child's stdout and stderr go to /dev/null; its error travels
 * down the pipe and the parent prints it. A sanitized build's reports still reach the terminal:
 * the sanitizers write to a copy of the original stderr. */
static void silence_child(void)
{
#if !ADDRESS_SPACE_LIMIT
    int report = dup(STDERR_FILENO);
    if (report >= 0)
        __sanitizer_set_report_fd((void *)(intptr_t)report);
#endif
    int null = open("/dev/null", O_WRONLY);
    if (null < 0)
        return;
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    if (null > STDERR_FILENO)
        close(null);
}

static void run_child(int fd, scene_import_fn fn, void *ctx, size_t memory_bytes, int seconds)
{
    /* The host's crash handlers (a test framework's, a crash reporter's) are not the child's: a
     * crash ends it, and the parent reads the signal. */
    static const int fatal[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGXCPU};
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
        signal(fatal[i], SIG_DFL);
    size_t now = ADDRESS_SPACE_LIMIT ? address_space_bytes() : 0;
    if (now) {
        struct rlimit as = {.rlim_cur = now + memory_bytes, .rlim_max = now + memory_bytes};
        setrlimit(RLIMIT_AS, &as);
    }
    struct rlimit cpu = {.rlim_cur = (rlim_t)seconds + 1, .rlim_max = (rlim_t)seconds + 2};
    setrlimit(RLIMIT_CPU, &cpu);
    silence_child();
    sl_model model;
    sl_error err = {0};
    bool ok;
    if (fn(ctx, &model, &err)) {
        ok = write_model(fd, &model);
    } else {
        uint32_t tag = STREAM_ERROR;
        ok = write_all(fd, &tag, sizeof tag) && write_all(fd, &err, sizeof err);
    }
    _exit(ok ? 0 : 1);
}

/* ---- the parent ---- */

bool sl_scene_import_isolated(scene_import_fn fn, void *ctx, const char *name, size_t memory_bytes, int seconds,
                           sl_model *model, sl_error *err)
{
    memset(model, 0, sizeof *model); /* what a failure leaves */
    int fds[2];
    if (pipe(fds) != 0)
        return sl_fail(err, SL_ERR_IO, "%s: cannot start the import (pipe: %s)", name, strerror(errno));
    fflush(NULL); /* nothing buffered is written twice */
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return sl_fail(err, SL_ERR_IO, "%s: cannot start the import (fork: %s)", name, strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        run_child(fds[1], fn, ctx, memory_bytes, seconds);
    }
    close(fds[1]);
    reader r = {.fd = fds[0]};
    clock_gettime(CLOCK_MONOTONIC, &r.deadline);
    r.deadline.tv_sec += seconds;
    sl_model got;
    memset(&got, 0, sizeof got);
    uint32_t tag = 0;
    bool streamed = read_all(&r, &tag, sizeof tag), ok = false, child_error = false;
    sl_error child = {0};
    if (streamed && tag == STREAM_MODEL)
        ok = read_model(&r, &got);
    else if (streamed && tag == STREAM_ERROR && read_all(&r, &child, sizeof child))
        child_error = true;
    if (!ok && !child_error)
        kill(pid, SIGKILL); /* cut short, timed out or garbled: the child has nothing more to say */
    close(fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (ok) {
        *model = got;
        return true;
    }
    sl_model_free(&got);
    size_t mib = memory_bytes >> 20;
    if (child_error) {
        child.msg[sizeof child.msg - 1] = '\0';
        /* assimp reports an allocation the limit refused as std::bad_alloc. */
        if (child.code == SL_ERR_MEMORY || strstr(child.msg, "bad_alloc"))
            return sl_fail(err, SL_ERR_RANGE, "%s: the import needs more than the %zu MiB a model file of this size may use",
                           name, mib);
        if (err)
            *err = child;
        return false;
    }
    if (r.timed_out || (WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU)))
        return sl_fail(err, SL_ERR_RANGE, "%s: the import took more than the %d s a model file of this size may take",
                       name, seconds);
    /* assimp aborts (std::terminate) when an allocation fails outside its own handlers. */
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT)
        return sl_fail(err, SL_ERR_RANGE, "%s: the importer aborted: the file declares more than the %zu MiB a model "
                       "file of this size may use, or is corrupt", name, mib);
    if (WIFSIGNALED(status) && WTERMSIG(status) != SIGKILL)
        return sl_fail(err, SL_ERR_FORMAT, "%s: the importer crashed on this file (signal %d%s)", name,
                       WTERMSIG(status), WTERMSIG(status) == SIGSEGV ? ": nested too deeply, or corrupt" : "");
    return sl_fail(err, SL_ERR_RANGE, "%s: the import failed within its limits (%zu MiB, %d s): the file declares "
                   "more than they allow, or is corrupt", name, mib, seconds);
}

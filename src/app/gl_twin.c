/* gl_twin.c - softlight-gl as a child process on softlight's G-buffer (gl_twin.h): the private
 * directory, the command, its error line, and the image read back. */
#include "gl_twin.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/subprocess.h"
#include "core/output_set.h"

typedef struct {
    char dir[PATH_MAX];
    bool made;
} temp_dir;

/* Remove the directory's files and subdirectories one level down (all a G-buffer's files make)
 * and the directory. */
static void remove_tree(const char *dir, int depth)
{
    DIR *d = opendir(dir);
    if (d) {
        struct dirent *e;
        char path[PATH_MAX + 256];
        while ((e = readdir(d)))
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
                snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
                if (unlink(path) != 0 && depth > 0)
                    remove_tree(path, depth - 1);
            }
        closedir(d);
    }
    rmdir(dir);
}

/* softlight-gl: $SOFTLIGHT_GL, else beside /proc/self/exe, else "softlight-gl" (PATH). */
static const char *gl_program(char *buf, size_t size)
{
    const char *env = getenv("SOFTLIGHT_GL");
    if (env && env[0])
        return env;
    ssize_t n = readlink("/proc/self/exe", buf, size - 1);
    if (n > 0) {
        buf[n] = '\0';
        char *slash = strrchr(buf, '/');
        if (slash && (size_t)(slash - buf) + sizeof "/softlight-gl" <= size) {
            strcpy(slash, "/softlight-gl");
            if (access(buf, X_OK) == 0)
                return buf;
        }
    }
    return "softlight-gl";
}

/* The first line of `path` (at most size - 1 bytes), without a leading "softlight-gl: ". */
static void first_line(const char *path, char *line, size_t size)
{
    line[0] = '\0';
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    if (fgets(line, (int)size, f)) {
        line[strcspn(line, "\n")] = '\0';
        const char *prefix = "softlight-gl: ";
        if (!strncmp(line, prefix, strlen(prefix)))
            memmove(line, line + strlen(prefix), strlen(line + strlen(prefix)) + 1);
    }
    fclose(f);
}

/* Copy softlight-gl's warnings (its stderr after a success) to ours, but for the scene's own
 * ("softlight: warning: ..."), which the C side's load has printed already. */
static void relay(const char *path, const char *who)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    char line[1024];
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "softlight: ", 11) != 0)
            fprintf(stderr, "%s: %s", who, strncmp(line, "softlight-gl: ", 14) ? line : line + 14);
    fclose(f);
}

/* The GL_RENDERER line softlight-gl -v printed, or "?". */
static void gl_renderer(const char *path, char *name, size_t size)
{
    snprintf(name, size, "?");
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, "GL_RENDERER: ", 13)) {
            line[strcspn(line, "\n")] = '\0';
            if (snprintf(name, size, "%s", line + 13) < 0) /* a long name is cut short */
                name[0] = 0;
            break;
        }
    fclose(f);
}

void sl_print_shell_word(FILE *out, const char *w)
{
    if (w[0] && strspn(w, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_./,:=+-@%") == strlen(w)) {
        fprintf(out, " %s", w);
        return;
    }
    fputs(" '", out);
    for (const char *p = w; *p; p++)
        if (*p == '\'')
            fputs("'\\''", out);
        else
            fputc(*p, out);
    fputc('\'', out);
}

/* softlight-gl's command: the scene, the G-buffer, the output, the camera and the options. Each
 * number is printed with 9 significant digits, which a float reads back exactly. */
static int command(const sl_gl_twin_request *q, const char *program, const char *aov_dir, const char *pfm,
                   char numbers[5][64], const char **argv)
{
    int n = 0;
    argv[n++] = program;
    argv[n++] = "render";
    argv[n++] = q->scene;
    argv[n++] = "--gbuffer";
    argv[n++] = aov_dir;
    argv[n++] = "--pfm";
    argv[n++] = pfm;
    argv[n++] = "--verbose";
    const sl_camera *c = q->camera;
    const char *names[3] = {"--eye", "--target", "--up"};
    const vec3 vectors[3] = {c->eye, c->target, c->up};
    for (int i = 0; i < 3; i++) {
        snprintf(numbers[i], sizeof numbers[i], "%.9g,%.9g,%.9g", (double)vectors[i].x, (double)vectors[i].y,
                 (double)vectors[i].z);
        argv[n++] = names[i];
        argv[n++] = numbers[i];
    }
    snprintf(numbers[3], sizeof numbers[3], "%.9g", (double)c->fovy_deg);
    argv[n++] = "--fovy";
    argv[n++] = numbers[3];
    if (q->env_rotation_deg) {
        snprintf(numbers[4], sizeof numbers[4], "%.9g", (double)*q->env_rotation_deg);
        argv[n++] = "--env-rotation";
        argv[n++] = numbers[4];
    }
    if (q->glsl) {
        argv[n++] = "--lighting";
        argv[n++] = q->glsl;
    }
    for (int i = 0; i < q->option_count; i++)
        argv[n++] = q->options[i];
    argv[n] = NULL;
    return n;
}

bool sl_gl_twin_light(const sl_gl_twin_request *q, sl_image *radiance, sl_image_repairs *repairs, char *renderer,
                      size_t renderer_size, sl_error *err)
{
    if (q->option_count > SL_GL_TWIN_OPTIONS_MAX)
        return sl_fail(err, SL_ERR_RANGE, "more than %d option words for softlight-gl", SL_GL_TWIN_OPTIONS_MAX);
    temp_dir tmp = {{0}, false};
    const char *tmpdir = getenv("TMPDIR");
    snprintf(tmp.dir, sizeof tmp.dir, "%s/softlight-gl-XXXXXX", tmpdir && tmpdir[0] ? tmpdir : "/tmp");
    if (!mkdtemp(tmp.dir))
        return sl_fail(err, SL_ERR_IO, "%s: cannot make a temporary directory: %s", tmp.dir, strerror(errno));
    tmp.made = true;
    char aov_dir[PATH_MAX + 8], pfm[PATH_MAX + 16], log_out[PATH_MAX + 16], log_err[PATH_MAX + 16], path[PATH_MAX];
    snprintf(aov_dir, sizeof aov_dir, "%s/gbuffer", tmp.dir);
    snprintf(pfm, sizeof pfm, "%s/gl.pfm", tmp.dir);
    snprintf(log_out, sizeof log_out, "%s/gl.out", tmp.dir);
    snprintf(log_err, sizeof log_err, "%s/gl.err", tmp.dir);
    sl_output_set out = {0};
    bool ok = sl_output_set_dir(&out, aov_dir, err) &&
              sl_gbuffer_add_aovs(q->gbuffer, q->camera->eye, aov_dir, &out, err) && sl_output_set_commit(&out, err);
    sl_output_set_free(&out);
    if (ok) {
        const char *argv[SL_GL_TWIN_OPTIONS_MAX + 24];
        char numbers[5][64];
        int n = command(q, gl_program(path, sizeof path), aov_dir, pfm, numbers, argv);
        if (q->verbose) {
            fprintf(stderr, "%s: GL:", q->who);
            for (int i = 0; i < n; i++)
                sl_print_shell_word(stderr, argv[i]);
            fputc('\n', stderr);
        }
        int status = sl_spawn_wait((char *const *)argv, log_out, log_err);
        if (status != 0) {
            char line[800];
            first_line(log_err, line, sizeof line);
            if (status < 0 && !line[0])
                ok = sl_fail(err, SL_ERR_IO, "cannot run %s (softlight-gl, or $SOFTLIGHT_GL): the GL side", argv[0]);
            else
                ok = sl_fail(err, SL_ERR_GL, "%s", line[0] ? line : "softlight-gl failed and said nothing");
        }
    }
    if (ok) {
        if (q->relay_warnings)
            relay(log_err, q->who);
        if (renderer)
            gl_renderer(log_out, renderer, renderer_size);
        ok = sl_image_read_pfm(pfm, 0, radiance, repairs, err);
    }
    remove_tree(tmp.dir, 1);
    return ok;
}

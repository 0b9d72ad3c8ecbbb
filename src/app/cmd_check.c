/* cmd_check.c - `softlight check SCENE [--lighting my.c] [--glsl my.frag]`: does a C lighting
 * program agree with its GLSL original?
 *
 * Both shade the same G-buffer: softlight rasterizes the frame and lights it with the C program
 * (the built-in port without --lighting), writes the G-buffer's AOV files into a private
 * temporary directory, and runs `softlight-gl render SCENE --gbuffer DIR` with the GLSL (our own
 * shaders/lighting.frag without --glsl) and the same render options. Rasterization is out of the
 * picture; what differs is how the two shaders evaluate. The figures are sl_compare_images' (C is
 * A, GL is B), after the scene's own tone map for the 8-bit ones, with the worst pixels and the
 * `softlight trace` line that steps into the worst.
 *
 * softlight-gl is a separate program (the command line itself links no OpenGL): $SOFTLIGHT_GL when
 * set, else the softlight-gl beside this executable, else the one on PATH. Its stderr is captured:
 * a failure there (no GL, a GLSL compile error) becomes this command's one error line.
 * Exit status: 0 agreement within --tolerance (p99 relative error), 1 outside it or NaN/Inf
 * in either image, 2 any error. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/args.h"
#include "app/commands.h"
#include "app/lighting_load.h"
#include "app/render_options.h"
#include "app/subprocess.h"
#include "core/output_set.h"
#include "post/compare.h"
#include "render/renderer.h"

#define CHECK_TOLERANCE_DEFAULT 0.05 /* tests/cli/gl_shading.sh's bound for lighting.frag and its port */
#define CHECK_ARGS_MAX 64            /* forwarded words; a longer command line is refused */

typedef struct {
    char dir[PATH_MAX];
    bool made;
} temp_dir;

/* Remove the directory's files (it holds no subdirectories) and the directory. */
static void temp_dir_remove(temp_dir *t)
{
    if (!t->made)
        return;
    DIR *d = opendir(t->dir);
    if (d) {
        struct dirent *e;
        char path[PATH_MAX + 256];
        while ((e = readdir(d)))
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
                snprintf(path, sizeof path, "%s/%s", t->dir, e->d_name);
                unlink(path);
            }
        closedir(d);
    }
    rmdir(t->dir);
    t->made = false;
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
static void relay(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    char line[1024];
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "softlight: ", 11) != 0)
            fprintf(stderr, "softlight check: %s", strncmp(line, "softlight-gl: ", 14) ? line : line + 14);
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

/* A word as a shell reads it back: bare when it is plain, else in single quotes. */
static void print_shell_word(FILE *out, const char *w)
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

int cmd_check(int argc, char **argv)
{
    const char *lighting = NULL, *glsl = NULL, *diff_path = NULL;
    bool verbose = false, debug_shader = false;
    float tolerance = (float)CHECK_TOLERANCE_DEFAULT;
    sl_render_options ro;
    sl_arg table[SL_RENDER_OPTION_COUNT + 6];
    const int render_count = sl_render_options_table(&ro, table);
    int n = render_count;
    table[n++] = (sl_arg){"--lighting", NULL, SL_ARG_STRING, &lighting, 0, 0, NULL, "FILE",
                          "the C lighting program (a source or a shared object; default: the built-in port)", NULL};
    table[n++] = (sl_arg){"--glsl", NULL, SL_ARG_STRING, &glsl, 0, 0, NULL, "FILE.frag",
                          "its GLSL original, run by softlight-gl (default: shaders/lighting.frag)", NULL};
    table[n++] = (sl_arg){"--diff", NULL, SL_ARG_STRING, &diff_path, 0, 0, NULL, "OUT.png",
                          "write a false-colour difference image (tone-mapped levels)", NULL};
    table[n++] = (sl_arg){"--tolerance", NULL, SL_ARG_FLOAT, &tolerance, 0, 1e30, NULL, "T",
                          "exit 1 unless the p99 relative error is <= T (default 0.05)", NULL};
    table[n++] = (sl_arg){"--debug-shader", NULL, SL_ARG_FLAG, &debug_shader, 0, 0, NULL, NULL,
                          "compile the --lighting source with -g -O0", NULL};
    table[n++] = (sl_arg){"--verbose", "-v", SL_ARG_FLAG, &verbose, 0, 0, NULL, NULL,
                          "print the compiler command and the softlight-gl command", NULL};
    const char *positional[1];
    int npos;
    bool help;
    sl_error err = {0};
    sl_render_desc desc;
    if (!sl_args_parse(argc, argv, 2, table, n, positional, 1, &npos, &help, &err) ||
        (!help && !sl_render_options_desc(&ro, &desc, &err))) {
        fprintf(stderr, "softlight check: %s\n", err.msg);
        return 2;
    }
    if (help || npos != 1) {
        sl_args_print_help(help ? stdout : stderr,
                           "softlight check SCENE.json [--lighting my.c] [--glsl my.frag] [--diff d.png] [options]",
                           table, n);
        if (help)
            printf("\nexit status: 0 within --tolerance, 1 outside it or NaN/Inf in either image, 2 errors\n");
        return help ? 0 : 2;
    }
    /* The render options, as given, for softlight-gl and for the trace line (the others are check's). */
    const char *forward[CHECK_ARGS_MAX];
    int nforward = 0;
    for (int i = 2; i < argc; i++) {
        const sl_arg *a = argv[i][0] == '-' ? sl_args_find(table, render_count, argv[i]) : NULL;
        const sl_arg *own = argv[i][0] == '-' && !a ? sl_args_find(table + render_count, n - render_count, argv[i]) : NULL;
        bool takes_value = (a || own) && (a ? a : own)->type != SL_ARG_FLAG && !strchr(argv[i], '=');
        if (a) {
            if (nforward + 2 > CHECK_ARGS_MAX) {
                fprintf(stderr, "softlight check: more than %d option words\n", CHECK_ARGS_MAX);
                return 2;
            }
            forward[nforward++] = argv[i];
            if (takes_value)
                forward[nforward++] = argv[++i];
        } else if (takes_value) {
            i++;
        }
    }
    if (!sl_lighting_load_arg("check", lighting, debug_shader, verbose, &desc.lighting_program))
        return 2;

    sl_scene scene;
    if (!sl_scene_load_with(positional[0], &desc.options, &scene, &err)) {
        fprintf(stderr, "softlight check: %s\n", err.msg);
        return 2;
    }
    fputs(scene.warnings, stderr);
    int status = 2;
    sl_renderer r;
    bool renderer_ready = false;
    sl_output_set out = {0};
    temp_dir tmp = {{0}, false};
    sl_image gl = {0}, diff = {0};
    sl_image_repairs repairs;
    char gl_path[PATH_MAX], aov_dir[PATH_MAX + 8], pfm[PATH_MAX + 16], log_out[PATH_MAX + 16],
        log_err[PATH_MAX + 16];
    if (!sl_render_desc_resolve(&desc, &scene, &err) || !sl_renderer_init(&r, &scene, &desc, &err))
        goto done;
    renderer_ready = true;
    if (!sl_renderer_frame(&r, NULL, &err))
        goto done;
    if (r.lighting_stats.nonfinite)
        fprintf(stderr, "softlight check: warning: %s: %lld pixels had NaN/Inf radiance (written as %s)\n",
                lighting ? lighting : "the built-in program", (long long)r.lighting_stats.nonfinite,
                lighting ? "magenta" : "0");

    const char *tmpdir = getenv("TMPDIR");
    snprintf(tmp.dir, sizeof tmp.dir, "%s/softlight-check-XXXXXX", tmpdir && tmpdir[0] ? tmpdir : "/tmp");
    if (!mkdtemp(tmp.dir)) {
        sl_fail(&err, SL_ERR_IO, "%s: cannot make a temporary directory: %s", tmp.dir, strerror(errno));
        goto done;
    }
    tmp.made = true;
    snprintf(aov_dir, sizeof aov_dir, "%s/gbuffer", tmp.dir);
    snprintf(pfm, sizeof pfm, "%s/gl.pfm", tmp.dir);
    snprintf(log_out, sizeof log_out, "%s/gl.out", tmp.dir);
    snprintf(log_err, sizeof log_err, "%s/gl.err", tmp.dir);
    if (!sl_output_set_dir(&out, aov_dir, &err) ||
        !sl_gbuffer_add_aovs(&r.gbuffer, scene.camera.eye, aov_dir, &out, &err) || !sl_output_set_commit(&out, &err))
        goto done;

    const char *gl_argv[CHECK_ARGS_MAX + 12];
    int ng = 0;
    gl_argv[ng++] = gl_program(gl_path, sizeof gl_path);
    gl_argv[ng++] = "render";
    gl_argv[ng++] = positional[0];
    gl_argv[ng++] = "--gbuffer";
    gl_argv[ng++] = aov_dir;
    gl_argv[ng++] = "--pfm";
    gl_argv[ng++] = pfm;
    gl_argv[ng++] = "--verbose";
    if (glsl) {
        gl_argv[ng++] = "--lighting";
        gl_argv[ng++] = glsl;
    }
    for (int i = 0; i < nforward; i++)
        gl_argv[ng++] = forward[i];
    gl_argv[ng] = NULL;
    if (verbose) {
        fprintf(stderr, "softlight check: GL:");
        for (int i = 0; i < ng; i++)
            print_shell_word(stderr, gl_argv[i]);
        fputc('\n', stderr);
    }
    int gl_status = sl_spawn_wait((char *const *)gl_argv, log_out, log_err);
    if (gl_status != 0) {
        char line[800];
        first_line(log_err, line, sizeof line);
        if (gl_status < 0 && !line[0])
            sl_fail(&err, SL_ERR_IO, "cannot run %s (softlight-gl, or $SOFTLIGHT_GL): the GL side of the check",
                    gl_argv[0]);
        else
            sl_fail(&err, SL_ERR_GL, "%s", line[0] ? line : "softlight-gl failed and said nothing");
        goto done;
    }
    relay(log_err);
    if (!sl_image_read_pfm(pfm, 0, &gl, &repairs, &err))
        goto done;

    sl_compare_desc cd = {.exposure = r.desc.tonemap.exposure, .contrast = r.desc.tonemap.contrast};
    sl_compare_stats stats;
    if (!sl_compare_images(&r.radiance, &gl, &cd, &stats, &err))
        goto done;
    char renderer_name[256];
    gl_renderer(log_out, renderer_name, sizeof renderer_name);
    printf("C   %s\nGL  %s on %s\n", lighting ? lighting : "the built-in program (the port of shaders/lighting.frag)",
           glsl ? glsl : "shaders/lighting.frag", renderer_name);
    printf("scene %s, %dx%d, the same G-buffer shaded both ways\n", positional[0], r.desc.width, r.desc.height);
    sl_compare_print(stdout, &stats, cd.exposure ? cd.exposure : 1.0f, "C", "GL");
    if (stats.worst_count > 0) {
        printf("trace the worst: softlight trace");
        print_shell_word(stdout, positional[0]);
        if (lighting) {
            print_shell_word(stdout, "--lighting");
            print_shell_word(stdout, lighting);
        }
        for (int i = 0; i < nforward; i++)
            print_shell_word(stdout, forward[i]);
        printf(" --pixel %d,%d\n", stats.worst[0].x, stats.worst[0].y);
    }
    if (diff_path) {
        if (!sl_compare_diff_image(&r.radiance, &gl, &cd, &diff, &err) || !sl_image_write_png(diff_path, &diff, &err))
            goto done;
        printf("diff image      %s\n", diff_path);
    }
    bool nonfinite = repairs.nan_count || repairs.inf_count;
    bool ok = !nonfinite && sl_compare_within(&stats, SL_METRIC_P99REL, (double)tolerance);
    printf("%s p99rel = %.6g, tolerance %.6g%s\n", ok ? "PASS" : "FAIL", stats.p99_rel, (double)tolerance,
           nonfinite ? " (NaN/Inf in the GL image)" : "");
    status = ok ? 0 : 1;
done:
    if (status == 2)
        fprintf(stderr, "softlight check: %s\n", err.msg);
    temp_dir_remove(&tmp);
    sl_image_free(&gl);
    sl_image_free(&diff);
    sl_output_set_free(&out);
    if (renderer_ready)
        sl_renderer_free(&r);
    sl_scene_free(&scene);
    return status;
}

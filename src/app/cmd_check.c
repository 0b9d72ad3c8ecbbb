/* cmd_check.c - `softlight check SCENE [--lighting my.c] [--glsl my.frag]`: does a C lighting
 * program agree with its GLSL original?
 *
 * Both shade the same G-buffer: softlight rasterizes the frame and lights it with the C program
 * (the built-in port without --lighting), and softlight-gl lights the same G-buffer with the GLSL
 * (our own shaders/lighting.frag without --glsl) and the same render options (gl_twin.h). The
 * figures are sl_compare_images' (C is A, GL is B), after the scene's own tone map for the 8-bit
 * ones, with the worst pixels and the `softlight trace` line that steps into the worst. A failure
 * on the GL side (no GL, a GLSL compile error) becomes this command's one error line.
 * Exit status: 0 agreement within --tolerance (p99 relative error), 1 outside it or NaN/Inf
 * in either image, 2 any error. */
#include <stdio.h>
#include <string.h>

#include "app/args.h"
#include "app/commands.h"
#include "app/gl_twin.h"
#include "app/lighting_load.h"
#include "app/render_options.h"
#include "post/compare.h"
#include "render/renderer.h"

#define CHECK_TOLERANCE_DEFAULT 0.05 /* tests/cli/gl_shading.sh's bound for lighting.frag and its port */
#define CHECK_ARGS_MAX SL_GL_TWIN_OPTIONS_MAX /* forwarded words; a longer command line is refused */

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
    sl_image gl = {0}, diff = {0};
    sl_image_repairs repairs;
    if (!sl_render_desc_resolve(&desc, &scene, &err))
        goto done;
    if (!sl_renderer_init(&r, &scene, &desc, &err))
        goto done;
    renderer_ready = true;
    if (!sl_renderer_frame(&r, NULL, &err))
        goto done;
    if (r.lighting_stats.nonfinite)
        fprintf(stderr, "softlight check: warning: %s: %lld pixels had NaN/Inf radiance (written as %s)\n",
                lighting ? lighting : "the built-in program", (long long)r.lighting_stats.nonfinite,
                lighting ? "magenta" : "0");

    const sl_gl_twin_request q = {.scene = positional[0],
                                  .gbuffer = &r.gbuffer,
                                  .camera = &scene.camera,
                                  .glsl = glsl,
                                  .options = forward,
                                  .option_count = nforward,
                                  .who = "softlight check",
                                  .verbose = verbose,
                                  .relay_warnings = true};
    char renderer_name[256];
    if (!sl_gl_twin_light(&q, &gl, &repairs, renderer_name, sizeof renderer_name, &err))
        goto done;

    sl_compare_desc cd = {.exposure = r.desc.tonemap.exposure, .contrast = r.desc.tonemap.contrast};
    sl_compare_stats stats;
    if (!sl_compare_images(&r.radiance, &gl, &cd, &stats, &err))
        goto done;
    printf("C   %s\nGL  %s on %s\n", lighting ? lighting : "the built-in program (the port of shaders/lighting.frag)",
           glsl ? glsl : "shaders/lighting.frag", renderer_name);
    printf("scene %s, %dx%d, the same G-buffer shaded both ways\n", positional[0], r.desc.width, r.desc.height);
    sl_compare_print(stdout, &stats, cd.exposure ? cd.exposure : 1.0f, "C", "GL");
    if (stats.worst_count > 0) {
        printf("trace the worst: softlight trace");
        sl_print_shell_word(stdout, positional[0]);
        if (lighting) {
            sl_print_shell_word(stdout, "--lighting");
            sl_print_shell_word(stdout, lighting);
        }
        for (int i = 0; i < nforward; i++)
            sl_print_shell_word(stdout, forward[i]);
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
    sl_image_free(&gl);
    sl_image_free(&diff);
    if (renderer_ready)
        sl_renderer_free(&r);
    sl_scene_free(&scene);
    return status;
}

/* cmd_trace.c - `softlight trace scene.json --pixel X,Y`: rasterize the frame, recording the
 * pixel's texture fetches (trace_fetches.c), then run the C lighting shader for one pixel with a
 * trace, printing every intermediate value and then the fetches. The traced code is the same
 * function the lighting pass runs, so a breakpoint in sl_lighting_shade (gdb: `break
 * sl_lighting_shade if x == X`) follows the same path. With --lighting, the pixel runs through
 * that program instead (its texel and result are printed; gdb stops in the program's own
 * function: docs/lighting-programs.md). With --gbuffer-shader, the texel is the user's G-buffer
 * program's (docs/gbuffer-programs.md). */
#include <stdio.h>
#include <stdlib.h>

#include "commands.h"
#include "gbuffer_load.h"
#include "lighting_load.h"
#include "render_options.h"
#include "scene/scene.h"
#include "shading/lighting_trace.h"
#include "trace_fetches.h"

int cmd_trace(int argc, char **argv)
{
    int pixel[2] = {-1, -1};
    const char *lighting = NULL, *gbuffer_shader = NULL;
    bool verbose = false, debug_shader = false;
    sl_render_options ro;
    sl_arg table[SL_RENDER_OPTION_COUNT + 5];
    int n = sl_render_options_table(&ro, table);
    table[n++] = (sl_arg){"--pixel", "-p", SL_ARG_PAIR, pixel, 0, SL_RASTER_MAX_SIZE - 1, NULL, "X,Y",
                          "the pixel to trace, (0,0) = top left as in the written image", NULL};
    table[n++] = (sl_arg){"--lighting", NULL, SL_ARG_STRING, &lighting, 0, 0, NULL, "FILE",
                          "trace this lighting program (a C source or a shared object): the texel and its result", NULL};
    table[n++] = (sl_arg){"--gbuffer-shader", NULL, SL_ARG_STRING, &gbuffer_shader, 0, 0, NULL, "FILE",
                          "fill the G-buffer with this fragment program (a C source or a shared object): the pixel's "
                          "texel is its", NULL};
    table[n++] = (sl_arg){"--debug-shader", NULL, SL_ARG_FLAG, &debug_shader, 0, 0, NULL, NULL,
                          "compile the --lighting and --gbuffer-shader sources with -g -O0, for a debugger", NULL};
    table[n++] = (sl_arg){"--verbose", "-v", SL_ARG_FLAG, &verbose, 0, 0, NULL, NULL,
                          "print the --lighting and --gbuffer-shader compiler commands", NULL};
    const char *positional[1];
    int npos;
    bool help;
    sl_error err = {0};
    if (!sl_args_parse(argc, argv, 2, table, n, positional, 1, &npos, &help, &err)) {
        fprintf(stderr, "softlight trace: %s\n", err.msg);
        return 2;
    }
    if (help || npos != 1 || pixel[0] < 0) {
        if (!help)
            fprintf(stderr, "softlight trace: needs a scene and --pixel X,Y\n");
        sl_args_print_help(help ? stdout : stderr, "softlight trace SCENE.json --pixel X,Y [options]", table, n);
        return help ? 0 : 2;
    }
    sl_render_desc desc;
    if (!sl_render_options_desc(&ro, &desc, &err)) {
        fprintf(stderr, "softlight trace: %s\n", err.msg);
        return 2;
    }
    /* only the command line names code to run; a scene never does */
    if (!sl_lighting_load_arg("trace", lighting, debug_shader, verbose, &desc.lighting_program) ||
        !sl_gbuffer_program_load_arg("trace", gbuffer_shader, debug_shader, verbose, &desc.gbuffer_program))
        return 2;
    sl_scene scene;
    if (!sl_scene_load_with(positional[0], &desc.options, &scene, &err)) {
        fprintf(stderr, "softlight trace: %s\n", err.msg);
        return 2;
    }
    fputs(scene.warnings, stderr); /* what the scene loads but does not draw */
    int status = 2;
    sl_renderer r;
    sl_lighting_trace *trace = NULL;
    sl_trace_fetches *fetches = NULL;
    if (!sl_renderer_init(&r, &scene, &desc, &err))
        goto done_scene;
    if (pixel[0] >= r.desc.width || pixel[1] >= r.desc.height) {
        sl_fail(&err, SL_ERR_RANGE, "--pixel %d,%d is outside the %dx%d image", pixel[0], pixel[1], r.desc.width,
                r.desc.height);
        goto done;
    }
    trace = malloc(sizeof *trace);
    fetches = malloc(sizeof *fetches);
    if (!trace || !fetches) {
        sl_fail(&err, SL_ERR_MEMORY, "out of memory for the trace");
        goto done;
    }
    int gb_y = r.desc.height - 1 - pixel[1]; /* G-buffer row 0 = bottom */
    sl_trace_fetches_hook(fetches, &r.textures, pixel[0], gb_y);
    if (!sl_renderer_raster(&r, NULL, &err) || !sl_renderer_prepare_lighting(&r, NULL, &err) ||
        !sl_lighting_trace_pixel(r.uniforms, &r.gbuffer, pixel[0], pixel[1], trace, &err))
        goto done;
    if (r.gbuffer.reflection && trace->covered && !trace->program) { /* the rays the plane's value came from */
        trace->reflection = true;
        vec2 plane = sl_reflection_texel(&r.gbuffer, &scene.camera, r.desc.options.reflection_occlusion, pixel[0],
                                         gb_y, trace->reflection_rays, trace->reflection_weights,
                                         trace->reflection_used);
        trace->reflection_visibility = plane.x;
        trace->reflection_count = (int)plane.y;
        trace->facet = r.gbuffer.facet != NULL;
        if (trace->facet)
            trace->facet_normal = r.gbuffer.facet[(size_t)gb_y * (size_t)r.gbuffer.width + (size_t)pixel[0]];
    }
    sl_lighting_trace_print(stdout, trace);
    if (desc.gbuffer_program) /* the fetch hook is the built-in textured program's */
        printf("G-buffer program: %s (%s); its texture fetches are not traced\n",
               desc.gbuffer_program->name ? desc.gbuffer_program->name : "(unnamed)", gbuffer_shader);
    else
        sl_trace_fetches_print(stdout, fetches, sl_gbuffer_at(&r.gbuffer, pixel[0], gb_y)->depth);
    status = 0;
done:
    free(fetches);
    free(trace);
    sl_renderer_free(&r);
done_scene:
    if (status)
        fprintf(stderr, "softlight trace: %s\n", err.msg);
    sl_scene_free(&scene);
    return status;
}

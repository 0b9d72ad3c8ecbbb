/* cmd_render.c - `softlight render scene.json`: one frame to PNG / .hdr / .pfm, the G-buffer
 * as PFM files with --aov, the radiance and the G-buffer as one multi-layer OpenEXR with --exr,
 * all replaced or none (one output set, core/output_set.h). Prints the time each stage took. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "core/output_set.h"
#include "core/timer.h"
#include "gbuffer_load.h"
#include "occlusion/gtao.h"
#include "occlusion/reflection.h"
#include "lighting_load.h"
#include "render_options.h"
#include "scene/scene.h"
#include "shard.h"

/* The PNG name when none is given: the scene's name in the current directory. */
static void default_png_name(const char *scene_path, char *out, size_t size)
{
    const char *base = strrchr(scene_path, '/');
    base = base ? base + 1 : scene_path;
    size_t n = strcspn(base, ".");
    snprintf(out, size, "%.*s.png", (int)n, base);
}

static void warn_repairs(const char *path, const sl_image_repairs *rep)
{
    if (rep->nan_count || rep->inf_count || rep->negative_count)
        fprintf(stderr, "softlight: warning: %s: replaced %ld NaN, %ld Inf and %ld negative texels by 0\n", path,
                rep->nan_count, rep->inf_count, rep->negative_count);
}

/* Whether any texel of the frame's G-buffer holds a surface (depth < 1: docs/gbuffer.md). A frame
 * without one is almost always a camera looking away, or a model too small or too far to cover a
 * pixel: worth a warning, since the image alone looks like a success. */
static bool any_surface(const sl_gbuffer *gb)
{
    size_t n = (size_t)gb->width * (size_t)gb->height;
    for (size_t i = 0; i < n; i++)
        if (gb->texels[i].depth < 1.0f)
            return true;
    return false;
}

/* Render `repeat` frames; r->timings then hold each stage's median, which is what
 * bench/vs-gl compares with softlight-gl --time. */
static bool render_frames(sl_renderer *r, int repeat, sl_error *err)
{
    double raster[1000], shading[1000], tonemap[1000], ao[1000], reflection[1000];
    for (int i = 0; i < repeat; i++) {
        if (!sl_renderer_frame(r, NULL, err))
            return false;
        raster[i] = r->timings.raster_ms;
        shading[i] = r->timings.shading_ms;
        tonemap[i] = r->timings.tonemap_ms;
        ao[i] = r->timings.ao_ms;
        reflection[i] = r->timings.reflection_ms;
    }
    r->timings.raster_ms = sl_median(raster, repeat);
    r->timings.shading_ms = sl_median(shading, repeat);
    r->timings.tonemap_ms = sl_median(tonemap, repeat);
    r->timings.ao_ms = sl_median(ao, repeat);
    r->timings.reflection_ms = sl_median(reflection, repeat);
    return true;
}

int cmd_render(int argc, char **argv)
{
    const char *png = NULL, *hdr = NULL, *pfm = NULL, *aov = NULL, *normals = NULL, *exr = NULL, *env = NULL;
    const char *shard_arg = NULL;
    bool quiet = false, verbose = false, debug_shader = false;
    const char *lighting = NULL, *gbuffer_shader = NULL;
    int repeat = 1;
    sl_render_options ro;
    sl_shard shard = {0};
    sl_arg table[SL_RENDER_OPTION_COUNT + 15];
    int n = sl_render_options_table(&ro, table);
    table[n++] = (sl_arg){"--output", "-o", SL_ARG_STRING, &png, 0, 0, NULL, "FILE.png", "tone-mapped image (default: SCENE.png)", NULL};
    table[n++] = (sl_arg){"--hdr", NULL, SL_ARG_STRING, &hdr, 0, 0, NULL, "FILE.hdr", "linear radiance as Radiance RGBE", NULL};
    table[n++] = (sl_arg){"--pfm", NULL, SL_ARG_STRING, &pfm, 0, 0, NULL, "FILE.pfm", "linear radiance as float32 PFM", NULL};
    table[n++] = (sl_arg){"--exr", NULL, SL_ARG_STRING, &exr, 0, 0, NULL, "FILE.exr",
                          "radiance (R, G, B) and every G-buffer channel as layers of one OpenEXR file, 32-bit float", NULL};
    table[n++] = (sl_arg){"--env", NULL, SL_ARG_STRING, &env, 0, 0, NULL, "FILE",
                          "environment image (.exr, .hdr or .pfm) in place of the scene's, and no irradiance map", NULL};
    table[n++] = (sl_arg){"--aov", NULL, SL_ARG_STRING, &aov, 0, 0, NULL, "DIR", "write the G-buffer channels as DIR/*.pfm", NULL};
    table[n++] = (sl_arg){"--normals", NULL, SL_ARG_STRING, &normals, 0, 0, NULL, "FILE.png", "normal visualisation (n*0.5+0.5)", NULL};
    table[n++] = (sl_arg){"--repeat", NULL, SL_ARG_INT, &repeat, 1, 1000, NULL, "N",
                          "render N frames and report each stage's median time (for benchmarks)", NULL};
    table[n++] = (sl_arg){"--shard", NULL, SL_ARG_STRING, &shard_arg, 0, 0, NULL, "I/N",
                          "compute image rows band I of N only and write a partial file (softlight merge)", NULL};
    table[n++] = (sl_arg){"--partial", NULL, SL_ARG_STRING, &shard.partial, 0, 0, NULL, "FILE",
                          "where --shard writes its partial (default: the first output + .shard-I-of-N)", NULL};
    table[n++] = (sl_arg){"--quiet", "-q", SL_ARG_FLAG, &quiet, 0, 0, NULL, NULL, "print nothing but errors", NULL};
    table[n++] = (sl_arg){"--lighting", NULL, SL_ARG_STRING, &lighting, 0, 0, NULL, "FILE",
                          "shade with this lighting program: a C source (compiled and cached) or a shared object "
                          "(docs/lighting-programs.md)", NULL};
    table[n++] = (sl_arg){"--gbuffer-shader", NULL, SL_ARG_STRING, &gbuffer_shader, 0, 0, NULL, "FILE",
                          "fill the G-buffer with this fragment program for every object: a C source (compiled and "
                          "cached) or a shared object (docs/gbuffer-programs.md)", NULL};
    table[n++] = (sl_arg){"--debug-shader", NULL, SL_ARG_FLAG, &debug_shader, 0, 0, NULL, NULL,
                          "compile the --lighting and --gbuffer-shader sources with -g -O0, for a debugger", NULL};
    table[n++] = (sl_arg){"--verbose", "-v", SL_ARG_FLAG, &verbose, 0, 0, NULL, NULL,
                          "print the --lighting and --gbuffer-shader compiler commands", NULL};

    const char *positional[1];
    int npos;
    bool help;
    sl_error err = {0};
    if (!sl_args_parse(argc, argv, 2, table, n, positional, 1, &npos, &help, &err)) {
        fprintf(stderr, "softlight render: %s\n", err.msg);
        return 2;
    }
    if (help || npos != 1) {
        sl_args_print_help(help ? stdout : stderr, "softlight render SCENE.json [-o out.png] [--hdr out.hdr] "
                           "[--pfm out.pfm] [--exr out.exr] [--aov DIR] [options]", table, n);
        return help ? 0 : 2;
    }
    sl_render_desc desc;
    uint64_t identity = 0;
    if (!sl_render_options_desc(&ro, &desc, &err) || (shard_arg && !sl_shard_parse(shard_arg, &shard, &err)) ||
        (shard_arg && !sl_shard_identity("render", argc, argv, positional[0], &identity, &err))) {
        fprintf(stderr, "softlight render: %s\n", err.msg);
        return 2;
    }
    /* only the command line names code to run; a scene never does */
    if (!sl_lighting_load_arg("render", lighting, debug_shader, verbose, &desc.lighting_program) ||
        !sl_gbuffer_program_load_arg("render", gbuffer_shader, debug_shader, verbose, &desc.gbuffer_program))
        return 2;
    char default_png[1024];
    if (!png && !hdr && !pfm && !aov && !normals && !exr) {
        default_png_name(positional[0], default_png, sizeof default_png);
        png = default_png;
    }

    sl_scene scene;
    if (!sl_scene_load_with(positional[0], &desc.options, &scene, &err)) {
        fprintf(stderr, "softlight render: %s\n", err.msg);
        return 2;
    }
    fputs(scene.warnings, stderr); /* what the scene loads but does not draw */
    if (env) { /* a path as given on the command line: relative to here, not to the scene */
        if (strlen(env) >= sizeof scene.environment.hdr_path) {
            fprintf(stderr, "softlight render: --env: path too long\n");
            sl_scene_free(&scene);
            return 2;
        }
        snprintf(scene.environment.hdr_path, sizeof scene.environment.hdr_path, "%s", env);
        scene.environment.irradiance_path[0] = '\0'; /* the scene's map belongs to its own environment */
    }
    int status = 2;
    sl_renderer r;
    sl_output_set out = {0};
    if (!sl_render_desc_resolve(&desc, &scene, &err))
        goto done_scene;
    if (shard.count) { /* the band of the scene's size, or of --size */
        desc.banded = true;
        sl_shard_rows(shard.index, shard.count, desc.height, &desc.band[0], &desc.band[1]);
    }
    if (!sl_renderer_init(&r, &scene, &desc, &err))
        goto done_scene;
    if (shard.count) {
        const char *first = png ? png : hdr ? hdr : pfm ? pfm : exr ? exr : normals ? normals : aov;
        if (!sl_shard_begin(&shard, &out, "render", identity, r.desc.width, r.desc.height, first, &err))
            goto done;
    }
    warn_repairs(scene.environment.hdr_path, &r.env_repairs);
    if (!render_frames(&r, repeat, &err))
        goto done;
    if (r.lighting_stats.nonfinite && lighting)
        fprintf(stderr, "softlight render: warning: %s: %lld pixels had NaN/Inf radiance (written as magenta)\n",
                lighting, (long long)r.lighting_stats.nonfinite);
    else if (r.lighting_stats.nonfinite)
        fprintf(stderr, "softlight render: warning: %lld pixels had NaN/Inf radiance (replaced by 0)\n",
                (long long)r.lighting_stats.nonfinite);
    if (!shard.count && !any_surface(sl_renderer_gbuffer(&r)))
        fprintf(stderr, "softlight render: warning: %s: no surface is in view (the camera sees none of the scene's "
                "triangles; the image is the environment alone)\n", positional[0]);

    /* Every output into one set: replaced together once all were written, or none of them. */
    if (png && !sl_output_set_image(&out, png, sl_image_encode_png, &r.display, &err))
        goto done;
    if (hdr && !sl_output_set_image(&out, hdr, sl_image_encode_hdr, &r.radiance, &err))
        goto done;
    if (pfm && !sl_output_set_image(&out, pfm, sl_image_encode_pfm, &r.radiance, &err))
        goto done;
    if (exr && !sl_gbuffer_add_exr(&r.gbuffer, scene.camera.eye, &r.radiance, exr, &out, &err))
        goto done;
    if (aov && !(sl_output_set_dir(&out, aov, &err) &&
                 sl_gbuffer_add_aovs(&r.gbuffer, scene.camera.eye, aov, &out, &err)))
        goto done;
    if (normals) {
        sl_image img = {0};
        bool ok = sl_gbuffer_normal_image(&r.gbuffer, &img, &err) &&
                  sl_output_set_image(&out, normals, sl_image_encode_png, &img, &err);
        sl_image_free(&img);
        if (!ok)
            goto done;
    }
    if (!sl_output_set_commit(&out, &err) || (shard.count && !sl_shard_finish(&shard, &err)))
        goto done;
    if (!quiet) {
        const sl_lighting_options *l = &r.uniforms->options;
        printf("softlight render: %s %dx%d N=%d lod=%s g=%s estimator=%s | raster %.1f ms, shading %.1f ms, "
               "tone map %.1f ms (%d threads%s)\n",
               positional[0], r.desc.width, r.desc.height, l->samples, sl_lod_rule_name(l->lod_rule),
               sl_gterm_name(l->gterm), sl_estimator_name(l->estimator), r.timings.raster_ms, r.timings.shading_ms,
               r.timings.tonemap_ms, sl_raster_threads(r.raster), repeat > 1 ? ", medians" : "");
        if (sl_lighting_sets_differ(l))
            printf("GGX materials: estimator=%s lod=%s%s (the line above is the Phong materials')\n",
                   sl_estimator_name(l->ggx.estimator), sl_lod_rule_name(l->ggx.lod_rule),
                   l->ggx.distortion ? " distortion" : "");
        if (r.desc.options.ao_radius > 0.0f)
            printf("ambient occlusion: radius %g, %.1f ms a frame (GTAO, %d slices x %d steps a side)\n",
                   (double)r.desc.options.ao_radius, r.timings.ao_ms, SL_GTAO_SLICES, SL_GTAO_STEPS);
        if (r.desc.options.reflection_occlusion > 0.0f)
            printf("reflection occlusion: rays %g world units long, %.1f ms a frame (%d rays x %d steps; %lld "
                   "texels, at edges and where the normal turns fast, traced their own %d)\n",
                   (double)r.desc.options.reflection_occlusion, r.timings.reflection_ms, SL_REFLECTION_RAYS,
                   SL_REFLECTION_STEPS, (long long)r.timings.reflection_lone, SL_REFLECTION_RAYS);
        if (r.shadows_built > 0) {
            int cubes = 0;
            for (int i = 0; i < r.shadows.count; i++)
                cubes += r.shadows.cubes[i].casts;
            printf("shadow maps: %d cube map%s of %d texels a face side, drawn in %.1f ms once per scene\n", cubes,
                   cubes == 1 ? "" : "s", SL_SHADOW_CUBE_SIZE, r.timings.shadow_ms);
        }
        const sl_lighting_options *lo = &r.desc.lighting;
        if (r.env_lights_built > 0) {
            char of[64] = "";
            if (lo->env_lights_worth)
                snprintf(of, sizeof of, ", those worth their cost of the brightest %d", lo->env_lights);
            printf("env lights: %d texels summed exactly%s (%.1f%% of the map's luminous power, residual clamped at "
                   "luminance %.4g), extracted in %.1f ms once per environment\n",
                   r.env_lights.count, of, 100.0 * r.env_lights.share, (double)r.env_lights.clamp,
                   r.timings.env_lights_ms);
        }
        else if (lo->env_lights > 0 && lo->env_lights_worth)
            printf("env lights: none (the brightest %d texels are a plateau, not peaks: the samples read the whole "
                   "environment)\n", lo->env_lights);
        if (r.suns_built > 0) {
            int mapped = 0;
            for (int k = 0; k < r.suns.count; k++)
                mapped += r.suns.maps[k].lights;
            if (r.suns.count == 0)
                printf("env-light shadow maps: none (no cluster of the %d env lights carries %g%% of the map's "
                       "luminous power)\n",
                       r.suns.env_light_count, 100.0 * SL_SHADOW_SUN_MIN_SHARE);
            else
                printf("env-light shadow maps: %d orthographic map%s of %d texels a side for %d of %d env lights "
                       "(clusters of %g degrees with %g%% of the map's luminous power or more, at most %d), drawn "
                       "in %.1f ms once per scene and environment\n",
                       r.suns.count, r.suns.count == 1 ? "" : "s", SL_SHADOW_SUN_SIZE, mapped, r.suns.env_light_count,
                       (double)SL_SHADOW_SUN_CLUSTER_DEG, 100.0 * SL_SHADOW_SUN_MIN_SHARE, SL_SHADOW_SUN_MAX,
                       r.timings.sun_shadow_ms);
        }
        if (r.sky_built > 0)
            printf("sky visibility maps: %d orthographic maps of %d texels a side (%s weighted), drawn in %.1f ms "
                   "once per scene and environment\n",
                   r.sky_built, SL_SKY_MAP_SIZE, r.sky_env_lights > 0 ? "the env lights' residual" : "the environment",
                   r.timings.sky_ms);
        if (r.env_oct_built >= 0)
            printf("octahedral chain: %dx%d, %d levels, built in %.1f ms once per environment\n",
                   r.env_oct.levels[0].width, r.env_oct.levels[0].height, r.env_oct.level_count,
                   r.timings.env_oct_ms);
        if (r.splitsum_built >= 0)
            printf("split sum: prefiltered chains %dx%d, %d levels (%s%s%s), and the BRDF table, built in %.1f ms "
                   "once per environment\n",
                   sl_renderer_splitsum_chain(&r, false)->levels[0].width,
                   sl_renderer_splitsum_chain(&r, false)->levels[0].height,
                   sl_renderer_splitsum_chain(&r, false)->level_count, r.splitsum_phong.level_count ? "Phong" : "",
                   r.splitsum_phong.level_count && r.splitsum_ggx.level_count ? " and " : "",
                   r.splitsum_ggx.level_count ? "GGX" : "", r.timings.splitsum_ms);
        const char *outs[] = {png, hdr, pfm, exr, aov, normals};
        for (size_t i = 0; i < sizeof outs / sizeof outs[0] && !shard.count; i++)
            if (outs[i])
                printf("wrote %s\n", outs[i]);
        if (shard.count)
            printf("wrote %s (rows %d..%d of %d; softlight merge joins the %d shards)\n", shard.partial,
                   shard.part.y0, shard.part.y1, shard.part.height, shard.count);
    }
    status = 0;
done:
    sl_output_set_free(&out);
    sl_shard_free(&shard);
    sl_renderer_free(&r);
done_scene:
    if (status)
        fprintf(stderr, "softlight render: %s\n", err.msg);
    sl_scene_free(&scene);
    return status;
}

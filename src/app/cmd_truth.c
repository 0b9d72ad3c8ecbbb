/* cmd_truth.c - `softlight truth scene.json`: the ground-truth image of a scene (eq. (1) with
 * eq. (2) over every texel of the environment, src/shading/ground_truth_image.h), cached, with
 * progress on stderr, and optionally how far a rendering is from it.
 *
 *   softlight truth SCENE.json [--size WxH] [--g inv-lh2|one] [--cache FILE] [--pfm OUT.pfm]
 *                   [--parts DIR] [-o OUT.png] [--compare RENDER.pfm] [--threads N] [--shard I/N]
 *                   [--visibility [--vis-level L]] [--lights]
 *
 * --shard I/N integrates only band I of N of the image rows and writes a partial file instead
 * of the outputs (app/shard.h); `softlight merge` joins the N partials into the same files.
 *
 * The truth is image-based light only by default (no point lights, no background: 0 outside the
 * mask), so compare it with `softlight render --no-lights --pfm`, of the same size and G term;
 * --lights adds the scene's point lights. By default every surface sees the whole environment
 * (the lighting shader's assumption); --visibility traces the scene's triangles so that
 * occluders shadow it (docs/ibl.md "Visibility"; needs a build with Embree), and leaves a
 * scene's ambient occlusion (render.ao_radius) off, since it traces what that estimates. The sky
 * visibility maps (render.sky_maps) are never drawn and the reflection occlusion
 * (render.reflection_occlusion) never traced: the truth does not read them. It costs
 * about 5.6 ms per covered pixel and core (a 1280x720 frame is hours): use a small --size, and
 * --cache so a second run is instant. Exit status: 0, or 2 on an error. */
#include <stdio.h>
#include <string.h>

#include "app/args.h"
#include "commands.h"
#include "core/options.h"
#include "core/output_set.h"
#include "core/timer.h"
#include "post/compare.h"
#include "render/renderer.h"
#include "shading/ground_truth_image.h"
#include "shading/visibility.h"
#include "shard.h"

typedef struct {
    double t0, last;
} truth_progress;

/* Percentage and ETA on stderr, at most twice a second. */
static void on_progress(void *user, long done, long total)
{
    truth_progress *p = user;
    double now = sl_now_seconds();
    if (done < total && now - p->last < 0.5)
        return;
    p->last = now;
    double el = now - p->t0, eta = done > 0 ? el * (double)(total - done) / (double)done : 0.0;
    fprintf(stderr, "\rsoftlight truth: %5.1f%% (%ld/%ld pixels), %.0f s, ETA %.0f s  ",
            total ? 100.0 * (double)done / (double)total : 100.0, done, total, el, eta);
    if (done == total)
        fputc('\n', stderr);
}

static bool add_parts(const char *dir, const sl_gt_image *gt, int g, sl_output_set *out, sl_error *err)
{
    if (!sl_output_set_dir(out, dir, err))
        return false;
    char path[1100];
    snprintf(path, sizeof path, "%s/diffuse.pfm", dir);
    if (!sl_output_set_image(out, path, sl_image_encode_pfm, &gt->diffuse, err))
        return false;
    snprintf(path, sizeof path, "%s/specular.pfm", dir);
    if (!sl_output_set_image(out, path, sl_image_encode_pfm, &gt->specular[g], err))
        return false;
    /* both G terms by name, for bench_speed_vs_error --truth (its error per G term) */
    snprintf(path, sizeof path, "%s/specular-inv-lh2.pfm", dir);
    if (!sl_output_set_image(out, path, sl_image_encode_pfm, &gt->specular[SL_GT_G_INV_LH2], err))
        return false;
    snprintf(path, sizeof path, "%s/specular-one.pfm", dir);
    if (!sl_output_set_image(out, path, sl_image_encode_pfm, &gt->specular[SL_GT_G_ONE], err))
        return false;
    snprintf(path, sizeof path, "%s/mask.pfm", dir);
    return sl_output_set_image(out, path, sl_image_encode_pfm, &gt->mask, err);
}

static bool compare_with(const char *path, const sl_image *truth, const sl_gt_image *gt,
                         const sl_tonemap_options *tm, sl_error *err)
{
    sl_image img = {0};
    if (!sl_image_read_pfm(path, 0, &img, NULL, err))
        return false;
    sl_compare_stats s;
    sl_compare_desc d = {.exposure = tm->exposure, .contrast = tm->contrast, .mask = &gt->mask};
    bool ok = sl_compare_images(&img, truth, &d, &s, err);
    sl_image_free(&img);
    if (!ok)
        return false;
    printf("%s against the truth (%ld covered pixels): rmse %.6g, nrmse %.4f, mean rel %.4f, p99 rel %.4f, "
           ">1/255 %.2f%%, >8/255 %.2f%%\n",
           path, s.pixels, s.rmse, s.nrmse, s.mean_rel, s.p99_rel, 100.0 * s.share_over_1,
           100.0 * s.share_over_8);
    return true;
}

int cmd_truth(int argc, char **argv)
{
    int part = 0;
    sl_option_values given; /* the rendering options truth takes, as the command line gives them */
    sl_option_values_default(&given);
    const sl_arg_mark size_given = {&given.set, SL_OPT_BIT(SL_OPT_SIZE)},
                      g_given = {&given.set, SL_OPT_BIT(SL_OPT_GTERM)},
                      threads_given = {&given.set, SL_OPT_BIT(SL_OPT_THREADS)};
    const char *cache = NULL, *pfm = NULL, *parts = NULL, *png = NULL, *against = NULL, *shard_arg = NULL;
    bool visibility = false, lights = false;
    int vis_level = -1; /* not given */
    sl_shard shard = {0};
    /* --size, --g and --threads: the rendering options' rows of the option table (core/options.h) */
    const sl_option *size_opt = &sl_options[SL_OPT_SIZE], *g_opt = &sl_options[SL_OPT_GTERM];
    const sl_option *threads_opt = &sl_options[SL_OPT_THREADS];
    char g_choices[64];
    sl_option_choices(g_opt, g_choices, sizeof g_choices);
    sl_arg table[] = {
        {size_opt->cli, NULL, SL_ARG_SIZE, given.size, size_opt->min, size_opt->max, NULL, "WxH",
         "image size (default: the scene's; keep it small)", &size_given},
        {g_opt->cli, NULL, SL_ARG_CHOICE, &given.gterm, g_opt->min, 0, g_choices, NULL,
         "G/(L.N V.N) of the truth (default inv-lh2)", &g_given},
        {"--cache", NULL, SL_ARG_STRING, &cache, 0, 0, NULL, "FILE", "read the truth from FILE when it matches, else write it", NULL},
        {"--pfm", NULL, SL_ARG_STRING, &pfm, 0, 0, NULL, "OUT.pfm", "radiance of --part (default: total = diffuse + specular), float32", NULL},
        {"--parts", NULL, SL_ARG_STRING, &parts, 0, 0, NULL, "DIR",
         "DIR/diffuse.pfm, specular.pfm (--g), specular-inv-lh2.pfm, specular-one.pfm, mask.pfm", NULL},
        {"--output", "-o", SL_ARG_STRING, &png, 0, 0, NULL, "OUT.png", "tone-mapped --part (the scene's exposure)", NULL},
        {"--compare", NULL, SL_ARG_STRING, &against, 0, 0, NULL, "RENDER.pfm", "print the error of a rendering (same size)", NULL},
        {"--part", NULL, SL_ARG_CHOICE, &part, 0, 0, "total|diffuse|specular", NULL,
         "what --pfm, -o and --compare use (default total; render with --diffuse-only or --specular-only to match)", NULL},
        {threads_opt->cli, threads_opt->alias, SL_ARG_INT, &given.threads, threads_opt->min, threads_opt->max, NULL,
         "N", "worker threads (default: all cores)", &threads_given},
        {"--shard", NULL, SL_ARG_STRING, &shard_arg, 0, 0, NULL, "I/N",
         "integrate image rows band I of N only and write a partial file (softlight merge)", NULL},
        {"--partial", NULL, SL_ARG_STRING, &shard.partial, 0, 0, NULL, "FILE",
         "where --shard writes its partial (default: the first output + .shard-I-of-N)", NULL},
        {"--visibility", NULL, SL_ARG_FLAG, &visibility, 0, 0, NULL, NULL,
         "occluders shadow the environment (and --lights): rays traced against the scene (Embree)", NULL},
        {"--vis-level", NULL, SL_ARG_INT, &vis_level, 0, SL_GT_VIS_LEVEL_MAX, NULL, "L",
         "--visibility: one ray per 2^L x 2^L texels of the environment (default 3; 0 = one per texel)", NULL},
        {"--lights", NULL, SL_ARG_FLAG, &lights, 0, 0, NULL, NULL,
         "add the scene's point lights (render without --no-lights to compare)", NULL},
    };
    const int count = (int)(sizeof table / sizeof table[0]);
    const char *positional[1];
    int npos;
    bool help;
    sl_error err = {0};
    if (!sl_args_parse(argc, argv, 2, table, count, positional, 1, &npos, &help, &err)) {
        fprintf(stderr, "softlight truth: %s\n", err.msg);
        return 2;
    }
    if (help || npos != 1) {
        sl_args_print_help(help ? stdout : stderr, "softlight truth SCENE.json [--size WxH] [--cache FILE] "
                           "[--pfm OUT.pfm] [--compare RENDER.pfm] [options]", table, count);
        return help ? 0 : 2;
    }
    uint64_t identity = 0;
    if (shard_arg && !(sl_shard_parse(shard_arg, &shard, &err) &&
                       sl_shard_identity("truth", argc, argv, positional[0], &identity, &err))) {
        fprintf(stderr, "softlight truth: %s\n", err.msg);
        return 2;
    }
    if (visibility && !sl_visibility_available()) {
        fprintf(stderr, "softlight truth: --visibility needs Embree 3, and this build has none "
                        "(install libembree-dev and rebuild)\n");
        return 2;
    }
    if (vis_level >= 0 && !visibility) {
        fprintf(stderr, "softlight truth: --vis-level needs --visibility\n");
        return 2;
    }
    if (vis_level < 0)
        vis_level = SL_GT_VIS_LEVEL_DEFAULT;
    if (shard_arg && against) {
        fprintf(stderr, "softlight truth: --compare needs the whole image: merge the shards, then compare\n");
        return 2;
    }
    const sl_gterm gterm = given.gterm; /* the truth's own: not the scene's */
    const int threads = given.threads;
    const int gi = gterm == SL_GTERM_ONE ? SL_GT_G_ONE : SL_GT_G_INV_LH2;
    sl_scene scene;
    if (!sl_scene_load(positional[0], &scene, &err)) {
        fprintf(stderr, "softlight truth: %s\n", err.msg);
        return 2;
    }
    fputs(scene.warnings, stderr); /* what the scene loads but does not draw */
    int status = 2;
    sl_renderer r;
    sl_render_desc desc = {.options = given};
    /* no irradiance is needed: the truth integrates the environment itself */
    sl_option_set_specular_only(&desc.options, true);
    /* traced visibility replaces the screen-space estimate of it: a scene's ambient occlusion
     * (render.ao_radius, GTAO) would count the occluders twice */
    if (visibility)
        sl_option_set_ao_radius(&desc.options, 0.0f);
    sl_option_set_sky_maps(&desc.options, 0);
    sl_option_set_reflection_occlusion(&desc.options, 0.0f);
    sl_option_set_diffuse_only(&desc.options, false);
    sl_gt_image gt = {0};
    sl_image total = {0}, display = {0};
    sl_output_set out = {0};
    if (!sl_render_desc_resolve(&desc, &scene, &err))
        goto done_scene;
    if (shard.count) { /* the band of the scene's size, or of --size */
        desc.banded = true;
        sl_shard_rows(shard.index, shard.count, desc.height, &desc.band[0], &desc.band[1]);
    }
    if (!sl_renderer_init(&r, &scene, &desc, &err))
        goto done_scene;
    if (!sl_renderer_raster(&r, NULL, &err))
        goto done;
    if (shard.count) {
        const char *first = pfm ? pfm : parts ? parts : png;
        if (!sl_shard_begin(&shard, &out, "truth", identity, r.desc.width, r.desc.height, first, &err))
            goto done;
    }
    truth_progress p = {.t0 = sl_now_seconds()};
    sl_gt_image_desc gd = {.env = &r.env, .gbuffer = &r.gbuffer, .eye = scene.camera.eye,
                           .env_rotation_deg = r.desc.lighting.env_rotation_deg,
                           .env_intensity = r.desc.lighting.env_intensity, .threads = threads, .cache_path = cache,
                           .label = positional[0], .progress = on_progress, .progress_user = &p,
                           .scene = &scene, .textures = &r.textures, .visibility = visibility,
                           .visibility_level = vis_level, .lights = lights};
    if (!sl_gt_image_compute(&gt, &gd, &err) || !sl_gt_image_total(&gt, (sl_gt_geometry)gi, &total, &err))
        goto done;
    if (part > 0) /* one part instead of the sum */
        memcpy(total.data, part == 1 ? gt.diffuse.data : gt.specular[gi].data,
               (size_t)total.width * (size_t)total.height * 3 * sizeof(float));
    printf("softlight truth: %s %dx%d, %ld covered pixels, G %s%s%s: %s\n", positional[0], gt.width, gt.height,
           gt.covered, sl_gterm_name(gterm), visibility ? ", visibility" : "", lights ? ", point lights" : "",
           gt.from_cache ? "read from the cache" : "integrated");
    if (!gt.from_cache)
        printf("  %.1f s (%.2f ms per covered pixel)\n", gt.seconds,
               gt.covered ? 1e3 * gt.seconds / (double)gt.covered : 0.0);
    if (!gt.from_cache && visibility)
        printf("  visibility level %d: %ld rays (%.0f per covered pixel), %ld pixels without a geometric normal\n",
               vis_level, gt.rays, gt.covered ? (double)gt.rays / (double)gt.covered : 0.0, gt.ng_fallbacks);
    /* Every output into one set: replaced together once all were written, or none of them. */
    if (png && !(sl_tonemap_image(&total, &display, &r.desc.tonemap, threads, &err) &&
                 sl_output_set_image(&out, png, sl_image_encode_png, &display, &err)))
        goto done;
    if (pfm && !sl_output_set_image(&out, pfm, sl_image_encode_pfm, &total, &err))
        goto done;
    if (parts && !add_parts(parts, &gt, gi, &out, &err))
        goto done;
    if (against && !compare_with(against, &total, &gt, &r.desc.tonemap, &err))
        goto done;
    if (!sl_output_set_commit(&out, &err) || (shard.count && !sl_shard_finish(&shard, &err)))
        goto done;
    if (shard.count)
        printf("wrote %s (rows %d..%d of %d; softlight merge joins the %d shards)\n", shard.partial, shard.part.y0,
               shard.part.y1, shard.part.height, shard.count);
    status = 0;
done:
    sl_output_set_free(&out);
    sl_shard_free(&shard);
    sl_image_free(&display);
    sl_image_free(&total);
    sl_gt_image_free(&gt);
    sl_renderer_free(&r);
done_scene:
    if (status)
        fprintf(stderr, "softlight truth: %s\n", err.msg);
    sl_scene_free(&scene);
    return status;
}
